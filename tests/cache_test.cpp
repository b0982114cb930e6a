// The content-addressed cache (server/cache_key.h): a scene's canonical JSON and the program's
// version name its result, so the same scene is answered from the store without a solve.
// Independent answers: a reordered or reformatted document must give the same canonical text (and
// the same bytes of result, which a second solve would not: its stats carry its own timings), a
// changed value must not, and a changed point source must give its own closed form E = I/h²
// (REFERENCES P1), never the cached one.
#pragma GCC diagnostic ignored "-Wunused-function"  // the fixture's helpers this file does not use
#include "tests/service_fixture.h"

#include "server/cache_key.h"

namespace lambert {
namespace {

// The same document with every object's members in reverse order and every number in another
// spelling: integers with a fraction and an exponent ("2.0e0"), others with 17 significant digits.
std::string respelled(const json& j) {
  char buf[64];
  switch (j.type()) {
    case json::value_t::object: {
      std::vector<std::pair<std::string, const json*>> members;
      for (auto it = j.begin(); it != j.end(); ++it) members.emplace_back(it.key(), &it.value());
      std::string out = "{ ";
      for (auto m = members.rbegin(); m != members.rend(); ++m)
        out += (m == members.rbegin() ? "" : ",\n ") + json(m->first).dump() + " : " + respelled(*m->second);
      return out + "}";
    }
    case json::value_t::array: {
      std::string out = "[";
      for (std::size_t k = 0; k < j.size(); ++k) out += (k ? ", " : "") + respelled(j[k]);
      return out + "]";
    }
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
      std::snprintf(buf, sizeof buf, "%lld.0e0", static_cast<long long>(j.get<std::int64_t>()));
      return buf;
    case json::value_t::number_float:
      std::snprintf(buf, sizeof buf, "%.17g", j.get<double>());
      return buf;
    default:
      return j.dump();
  }
}

TEST(CacheKey, CanonicalTextSortsMembersAndSpellsNumbersOnce) {
  const auto a = canonical_json(R"({"b": 1, "a": [1.0, 2e0, -0.0, 0.1, "x\u00e9"], "c": {"z": 0, "y": null}})");
  const auto b = canonical_json("{\"c\":{\"y\":null,\"z\":-0},\"a\":[10e-1,2,0,0.10000000000000001,\"x\xc3\xa9\"],\"b\":1.0}");
  ASSERT_TRUE(a && b);
  EXPECT_EQ(*a, *b);
  EXPECT_EQ(*a, "{\"a\":[1.0,2.0,0.0,0.1,\"x\xc3\xa9\"],\"b\":1.0,\"c\":{\"y\":null,\"z\":0.0}}");
  // The next double after 0.1 is another value.
  EXPECT_NE(*canonical_json("[0.1]"), *canonical_json("[0.10000000000000002]"));
  // Integers a double cannot hold keep every digit: 2^53 + 1 differs from 2^53.
  EXPECT_NE(*canonical_json("[9007199254740993]"), *canonical_json("[9007199254740992]"));
  EXPECT_EQ(*canonical_json("[9007199254740992]"), *canonical_json("[9007199254740992.0]"));
  EXPECT_FALSE(canonical_json("{\"a\": }"));
}

TEST(CacheKey, TheKeyHoldsTheVersionAndScenesNamingFilesHaveNone) {
  const std::string scene = point_scene(100).dump();
  const std::string key = scene_cache_key(scene, "1.0.0");
  EXPECT_EQ(key.size(), 64u);
  EXPECT_EQ(key, scene_cache_key(respelled(point_scene(100)), "1.0.0"));
  EXPECT_NE(key, scene_cache_key(scene, "1.0.1"));
  EXPECT_NE(key, scene_cache_key(point_scene(100.000001).dump(), "1.0.0"));
  json with_file = point_scene(100);
  with_file["surfaces"].push_back({{"name", "m"}, {"material", "black"}, {"file", "m.obj"}});
  EXPECT_EQ(scene_cache_key(with_file.dump(), "1.0.0"), "");
  // FIPS 180-2's example: SHA-256("abc").
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST(CacheHttp, AReorderedSceneIsAnsweredFromTheStoreAndAChangedOneIsSolved) {
  TestServer server;
  auto cli = server.client();
  const std::string first = submit(server, point_scene(100));
  ASSERT_EQ(wait_final(server, first).value("state", ""), "done");
  auto solved = cli->Get("/v1/jobs/" + first + "/result");
  ASSERT_TRUE(solved && solved->status == 200);

  // The same scene, spelled differently: done on arrival, with the very bytes of the first result.
  const json again = expect_json(cli->Post("/v1/jobs", respelled(point_scene(100)), "application/json"), 202);
  EXPECT_EQ(again.value("state", ""), "done");
  EXPECT_TRUE(again.value("cached", false));
  auto cached = cli->Get("/v1/jobs/" + again.value("id", "") + "/result");
  ASSERT_TRUE(cached && cached->status == 200);
  EXPECT_TRUE(cached->body == solved->body);
  auto sync = cli->Post("/v1/solve", respelled(point_scene(100)), "application/json");
  ASSERT_TRUE(sync && sync->status == 200);
  EXPECT_TRUE(sync->body == solved->body);

  // One value changed: solved, to its own closed form E = I/h² (120 cd, h = 2 m: 30 lx).
  const json changed = expect_json(cli->Post("/v1/jobs", point_scene(120).dump(), "application/json"), 202);
  EXPECT_FALSE(changed.value("cached", false));
  const std::string id = changed.value("id", "");
  ASSERT_EQ(wait_final(server, id).value("state", ""), "done");
  EXPECT_FALSE(job_status(server, id).value("cached", false));
  const json result = json::parse(cli->Get("/v1/jobs/" + id + "/result")->body);
  EXPECT_NEAR(probe_lx(result, "below"), expected_below(120), 1e-9 * expected_below(120));

  // Deleting the first job leaves the cached copy's result in place.
  EXPECT_EQ(cli->Delete("/v1/jobs/" + first)->status, 200);
  auto still = cli->Get("/v1/jobs/" + again.value("id", "") + "/result");
  ASSERT_TRUE(still);
  EXPECT_EQ(still->status, 200);
}

TEST(CacheHttp, TheCacheOutlivesARestartOfADataDirectory) {
  TempDir dir;
  ServiceOptions options;
  options.data_dir = dir.path;
  std::string body;
  {
    TestServer server(options);
    const std::string id = submit(server, point_scene(50));
    ASSERT_EQ(wait_final(server, id).value("state", ""), "done");
    body = server.client()->Get("/v1/jobs/" + id + "/result")->body;
  }
  TestServer server(options);
  const json again = expect_json(server.client()->Post("/v1/jobs", respelled(point_scene(50)), "application/json"), 202);
  EXPECT_TRUE(again.value("cached", false));
  EXPECT_TRUE(server.client()->Get("/v1/jobs/" + again.value("id", "") + "/result")->body == body);
}

}  // namespace
}  // namespace lambert
