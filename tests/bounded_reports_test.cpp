// Error reports are bounded whatever the input (issue 37: a 2 MB request with 600 bad values made a
// 502 MB error response and +1.9 GiB of server memory). The hostile document: 200 levels of
// 3000-byte keys inside "expected" and, at the bottom, one key written `n` times: n − 1 duplicate-key
// errors, each with a 600 kB pointer. The count is known by construction; the report must list the
// first kMaxListedErrors, count all of them exactly, and stay small: in the decoder, in the HTTP
// answer of a real `lambert serve` (and its memory) and in `lambert check`'s exit-2 output.
#include <gtest/gtest.h>

#include <httplib.h>

#include <nlohmann/json.hpp>
#include <string>

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
