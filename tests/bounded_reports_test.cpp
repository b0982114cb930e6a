// Error reports are bounded whatever the input (issue 37: a 2 MB request with 600 bad values made a
// 502 MB error response and +1.9 GiB of server memory). The hostile document: 200 levels of
// 3000-byte keys inside "expected" and, at the bottom, one key written `n` times: n − 1 duplicate-key
// errors, each with a 600 kB pointer. The count is known by construction; the report must list the
// first kMaxListedErrors, count all of them exactly, and stay small: in the decoder, in the HTTP
// answer of a real `lambert serve` (and its memory) and in `lambert check`'s exit-2 output.
#include <gtest/gtest.h>

#include <httplib.h>

#include <algorithm>
#include <chrono>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "server/codec/decoder.h"
#include "server/scene_codec.h"
#include "tests/child_process.h"

namespace lambert {
namespace {

using json = nlohmann::json;
using testing::ChildOutcome;
using testing::ScratchDir;
using testing::ServeProcess;

const std::string kScene = R"({"lambert": 1, "spectrum": {"mode": "spectral", "wavelengths_nm": [555]},
  "materials": {"black": {"reflectance": 0}},
  "surfaces": [{"name": "floor", "material": "black", "polygon": [[0,0,0], [1,0,0], [1,1,0], [0,1,0]]}],
  "lights": [{"type": "point", "position": [0.5, 0.5, 1], "intensity": 1.0}])";

// kScene with "expected": {k0: {k1: ... {"d": 0, "d": 1, ..., "d": n-1}}} under `depth` long keys.
std::string deep_duplicates(int depth, int n, std::size_t key_bytes = 3000) {
  std::string inner = "{";
  for (int i = 0; i < n; ++i) inner += (i ? ",\"d\":" : "\"d\":") + std::to_string(i);
  inner += "}";
  const std::string key(key_bytes, 'k');
  std::string doc = inner;
  for (int level = depth - 1; level >= 0; --level) doc = "{\"" + key + std::to_string(level) + "\":" + doc + "}";
  return kScene + ", \"expected\": " + doc + "}";
}

TEST(BoundedReports, TheDecoderListsTheFirstErrorsAndCountsThemAll) {
  const std::string text = deep_duplicates(200, 600);
  ASSERT_GT(text.size(), 600'000u);
  const DecodeResult r = decode_scene(text);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.errors.size(), kMaxListedErrors);
  EXPECT_EQ(r.error_count(), 599u);  // 600 keys "d": all but the first repeat
  for (const DecodeError& e : r.errors) {
    EXPECT_LE(e.pointer.size(), kMaxErrorTextBytes);
    EXPECT_LE(e.message.size(), kMaxErrorTextBytes);
    // The two ends of the pointer are kept: where it starts and which key repeats.
    EXPECT_EQ(e.pointer.rfind("/expected/kkk", 0), 0u) << e.pointer;
    EXPECT_TRUE(e.pointer.ends_with("199/d")) << e.pointer;
    EXPECT_NE(e.pointer.find(" bytes left out] ... "), std::string::npos);
  }
  const std::string report = format_errors(r);
  EXPECT_LT(report.size(), kMaxListedErrors * 2 * (kMaxErrorTextBytes + 8));
  EXPECT_NE(report.find("... and 499 more errors (599 in all"), std::string::npos) << report.substr(report.size() - 300);
}

TEST(BoundedReports, ShorteningKeepsUtf8WholeAndSaysHowMuchWasLeftOut) {
  std::string text;
  for (int i = 0; i < 1000; ++i) text += "é€𝄞";  // 2-, 3- and 4-byte sequences
  const std::string s = shorten_for_report(text, 100);
  EXPECT_LE(s.size(), 100u);
  EXPECT_TRUE(json::accept(json(s).dump())) << "not valid UTF-8: " << s;
  // What is kept plus what was left out is the whole text.
  const auto open = s.find(" ... ["), close = s.find(" bytes left out] ... ");
  ASSERT_NE(open, std::string::npos);
  const std::size_t left_out = std::stoul(s.substr(open + 6, close - open - 6));
  EXPECT_EQ(open + (s.size() - close - 21) + left_out, text.size());
  EXPECT_EQ(shorten_for_report("short", 100), "short");
}

TEST(BoundedReports, AnInvalidTokenIsNotQuotedWhole) {
  // An unterminated 1 MB string: the parser's message quotes the token it last read.
  const std::string text = kScene + ", \"name\": \"" + std::string(1 << 20, 'x');
  const DecodeResult r = decode_scene(text);
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_LE(r.errors[0].message.size(), kMaxErrorTextBytes);
  EXPECT_NE(r.errors[0].message.find("invalid JSON"), std::string::npos);
}

// The banded distance (codec::edit_distance with a limit) against the full Levenshtein table, on
// random words over a small alphabet (so that near words are common).
TEST(BoundedReports, TheBandedEditDistanceAgreesWithTheFullTable) {
  auto full = [](const std::string& a, const std::string& b) {
    std::vector<std::vector<std::size_t>> t(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
    for (std::size_t i = 0; i <= a.size(); ++i) t[i][0] = i;
    for (std::size_t j = 0; j <= b.size(); ++j) t[0][j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i)
      for (std::size_t j = 1; j <= b.size(); ++j)
        t[i][j] = std::min({t[i - 1][j] + 1, t[i][j - 1] + 1, t[i - 1][j - 1] + (a[i - 1] != b[j - 1])});
    return t[a.size()][b.size()];
  };
  std::mt19937 rng(37);
  auto word = [&] {
    std::string w(rng() % 9, 'a');
    for (char& c : w) c = static_cast<char>('a' + rng() % 3);
    return w;
  };
  for (int k = 0; k < 20000; ++k) {
    const std::string a = word(), b = word();
    const std::size_t limit = rng() % 4, d = full(a, b);
    EXPECT_EQ(codec::edit_distance(a, b, limit), std::min(d, limit + 1)) << a << " / " << b << " limit " << limit;
  }
}

TEST(BoundedReports, SuggestionsStayCheapForTenThousandMisspeltMaterials) {
  // 10⁴ materials and 10⁴ surfaces naming a misspelt one: every error used to compare its word with
  // every material (quadratic; 5000 of each took 21 s).
  std::string materials, surfaces;
  for (int i = 0; i < 10000; ++i) {
    materials += (i ? ",\"" : "\"") + std::string("material_number_") + std::to_string(i) + "\": {\"reflectance\": 0.5}";
    surfaces += (i ? ",{" : "{") + std::string("\"material\": \"material_numbr_") + std::to_string(i) +
                "\", \"polygon\": [[0,0,0], [1,0,0], [1,1,0], [0,1,0]]}";
  }
  const std::string text = "{\"materials\": {" + materials + "}, \"surfaces\": [" + surfaces + "]}";
  const auto t0 = std::chrono::steady_clock::now();
  const DecodeResult r = decode_scene(text);
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(10));
  EXPECT_EQ(r.error_count(), 10000u);
  EXPECT_EQ(r.errors[0].message, "unknown material 'material_numbr_0'; did you mean 'material_number_0'?");
}

TEST(BoundedReports, TheServiceAnswersSmallAndStaysSmall) {
  ServeProcess server({});
  const std::string text = deep_duplicates(200, 3000);  // 2.4 MB
  httplib::Client client("127.0.0.1", server.port());
  client.set_read_timeout(60, 0);
  const long rss_before = server.rss_kb();
  for (int round = 0; round < 3; ++round) {
    auto res = client.Post("/v1/jobs", text, "application/json");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 422);
    EXPECT_LT(res->body.size(), 128u << 10) << "a " << res->body.size() << "-byte error answer";
    const json body = json::parse(res->body);
    EXPECT_EQ(body["error"]["code"], "invalid_scene");
    EXPECT_EQ(body["error"]["error_count"], 2999);
    EXPECT_EQ(body["error"]["errors"].size(), kMaxListedErrors);
    EXPECT_NE(body["error"]["message"].get<std::string>().find("(and 2998 more"), std::string::npos);
  }
  // The DOM of a 2.4 MB document is a few times its size; the pointers it once built were 600 kB each.
  const long grown_kb = server.rss_kb() - rss_before;
  EXPECT_LT(grown_kb, 100 * 1024) << "the server grew by " << grown_kb << " kB";
  EXPECT_TRUE(server.alive());
}

TEST(BoundedReports, CheckAndSolveExitTwoWithABoundedList) {
  ScratchDir dir("lambert_bounded");
  const auto path = dir / "dup.json";
  testing::write_file(path, deep_duplicates(200, 3000));
  for (const char* command : {"check", "solve"}) {
    const ChildOutcome r = testing::run_lambert({command, path.string()});
    EXPECT_EQ(r.status, 2) << command << ": " << r.err.substr(0, 500);
    EXPECT_LT(r.err_bytes, 128u << 10) << command;
    EXPECT_NE(r.err.find("... and 2899 more errors (2999 in all; the first 100 are listed)"), std::string::npos)
        << r.err.substr(r.err.size() > 300 ? r.err.size() - 300 : 0);
    EXPECT_LT(r.max_rss_kb, 200 * 1024) << command;
  }
}

}  // namespace
}  // namespace lambert
