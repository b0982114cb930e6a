// The limits on what one scene may make Lambert compute and answer (server/scene_limits.h; issue 37:
// a 300-byte scene with 10 000 wavelengths made a 1.18 GB result, 100 grid probes of 10⁶ points ended
// in std::bad_alloc). Checked against independent answers: the result size bound against the
// encoder's real output, the probe-point count against the scene's construction, each refusal by
// the limit its message names, before the memory it guards is taken (the child's peak RSS), and the
// server's own cap on a worker's output against a worker that writes too much.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include "server/result_codec.h"
#include "server/scene_codec.h"
#include "server/solve_process.h"
#include "solver/report.h"
#include "tests/child_process.h"
#include "tests/service_fixture.h"

namespace lambert {
namespace {

using testing::ChildOutcome;
using testing::ScratchDir;

// A floor under a point light, `W` wavelengths from 380 nm, with `extra` members merged in.
json floor_scene(int wavelengths, json extra = json::object()) {
  json s = {{"lambert", 1},
            {"spectrum", {{"mode", "spectral"}, {"from_nm", 380}, {"to_nm", 380 + 0.04 * (wavelengths - 1)}, {"step_nm", 0.04}}},
            {"materials", {{"grey", {{"reflectance", 0.5}}}}},
            {"surfaces", json::array({{{"name", "floor"},
                                       {"material", "grey"},
                                       {"polygon", {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}}}}})},
            {"lights", json::array({{{"type", "point"}, {"position", {0.5, 1, 0.5}}, {"intensity", 1.0}}})}};
  s.merge_patch(extra);
  return s;
}

json grid_probe(const std::string& name, int nu, int nv) {
  return {{"name", name},
          {"grid", {{"origin", {0, 0.01, 0}}, {"u", {1, 0, 0}}, {"v", {0, 0, 1}}, {"nu", nu}, {"nv", nv}}},
          {"normal", {0, 1, 0}}};
}

// ---- the result's size bound ------------------------------------------------------------------------

TEST(SceneLimits, TheResultSizeBoundHoldsForEveryPartOfAResult) {
  json two_lights = floor_scene(41);
  two_lights["spectrum"] = {{"mode", "spectral"}, {"from_nm", 380}, {"to_nm", 780}, {"step_nm", 10}};
  two_lights["lights"].push_back({{"type", "point"}, {"position", {0.2, 2, 0.5}}, {"intensity", 2.0}});
  two_lights["meshing"] = {{"max_patch_area", 0.01}};
  struct Case { const char* what; json scene; };
  std::vector<Case> cases = {{"spectral", two_lights}, {"not spectral", two_lights},
                             {"per source", two_lights}, {"grid probes", two_lights}, {"rgb", two_lights},
                             {"daylight", two_lights}, {"sun", two_lights}};
  cases[1].scene["output"] = {{"spectral", false}};
  cases[2].scene["output"] = {{"per_source", true}};
  cases[3].scene["probes"] = json::array({grid_probe("g", 20, 15), {{"name", "p"}, {"position", {0.5, 0, 0.5}}, {"normal", {0, 1, 0}}}});
  cases[3].scene["output"] = {{"per_source", true}};
  cases[4].scene["spectrum"] = {{"mode", "rgb"}};
  // A sky with a daylight-factor grid (EN 17037's summary) and a façade probe's VSC; a sun placed by
  // place and time (the floor faces +y: up is +y).
  cases[5].scene["lights"] = json::array({{{"type", "sky"}, {"cie_type", 16}, {"zenith_luminance_cd_m2", 1000}, {"up", {0, 1, 0}}}});
  json df = grid_probe("df", 20, 15);
  df["daylight_factor"] = true;
  df["en17037"] = {{"level", "high"}, {"median_external_diffuse_illuminance_lx", 15000}};
  json vsc = grid_probe("vsc", 10, 10);
  vsc["normal"] = {1, 0, 0};
  vsc["vertical_sky_component"] = true;
  cases[5].scene["probes"] = json::array({df, vsc});
  cases[6].scene["lights"] = json::array({{{"type", "directional"}, {"irradiance", 1}, {"up", {0, 1, 0}}, {"north", {0, 0, -1}},
                                            {"sun", {{"latitude_deg", 48}, {"longitude_deg", 11}, {"time", "2026-06-21T12:00+02:00"}}}}});
  for (const Case& c : cases) {
    const DecodeResult d = decode_scene(c.scene.dump());
    ASSERT_TRUE(d.ok()) << c.what << ": " << format_errors(d);
    const Solution sol = solve(*d.scene);
    const std::string text = encode_result(*d.scene, sol, make_report(*d.scene, sol));
    const double bound = result_size_bound(*d.scene).bytes(sol.patches.size());
    EXPECT_LE(static_cast<double>(text.size()), bound) << c.what;
    EXPECT_LE(bound, 6.0 * static_cast<double>(text.size()) + 400e3) << c.what << ": a bound too loose to be useful";
    std::printf("%-13s %6zu patches: result %9zu bytes, bound %11.0f\n", c.what, sol.patches.size(), text.size(), bound);
  }
}

// ---- decode time: probe points --------------------------------------------------------------------------

TEST(SceneLimits, ProbePointsAreCountedAcrossEveryProbe) {
  json scene = floor_scene(41);
  scene["probes"] = json::array();
  for (int k = 0; k < 100; ++k) scene["probes"].push_back(grid_probe(std::string("g").append(std::to_string(k)), 1000, 1000));
  const DecodeResult r = decode_scene(scene.dump());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error_count(), 99u);  // the first grid fits, every later one would exceed
  EXPECT_EQ(r.errors[0].pointer, "/probes/1/grid");
  EXPECT_EQ(r.errors[0].message, "the probes would have 2000000 points in all; the limit is max_probe_points = "
                                 "1000000, --max-probe-points");
  // Single points count too: 4 allowed, the fifth refused.
  json five = floor_scene(41);
  five["probes"] = json::array();
  for (int k = 0; k < 5; ++k)
    five["probes"].push_back({{"name", std::string("p").append(std::to_string(k))}, {"position", {0.5, 0, 0.5}}, {"normal", {0, 1, 0}}});
  const DecodeResult r5 = decode_scene(five.dump(), {}, SceneLimits{4, 0, 0});
  ASSERT_EQ(r5.errors.size(), 1u) << format_errors(r5);
  EXPECT_EQ(r5.errors[0].pointer, "/probes/4");
  EXPECT_TRUE(decode_scene(five.dump(), {}, SceneLimits{5, 0, 0}).ok());
}

TEST(SceneLimits, CheckRefusesAHundredMillionProbePointsWithoutTakingTheMemory) {
  ScratchDir dir("lambert_limits");
  json scene = floor_scene(41);
  scene["probes"] = json::array();
  for (int k = 0; k < 100; ++k) scene["probes"].push_back(grid_probe(std::string("g").append(std::to_string(k)), 1000, 1000));
  testing::write_file(dir / "probes.json", scene.dump());
  const ChildOutcome r = testing::run_lambert({"check", (dir / "probes.json").string()});
  EXPECT_EQ(r.status, 2) << r.err.substr(0, 1000);
  EXPECT_NE(r.err.find("/probes/1/grid: the probes would have 2000000 points in all"), std::string::npos) << r.err;
  // One grid of 10⁶ points is 24 MB; all of them would have been 2.4 GB (and ended in bad_alloc).
  EXPECT_LT(r.max_rss_kb, 150 * 1024);
}

TEST(SceneLimits, SpectralValuesOfProbesAreLimitedBeforeAnyPatch) {
  json scene = floor_scene(9001);
  scene["probes"] = json::array({grid_probe("g", 100, 150)});
  const DecodeResult r = decode_scene(scene.dump());
  // Two limits, each named: 9001 wavelengths × 15 000 points = 1.35e8 > 1e8 spectral values, and their
  // spectra in the result, 1.35e8 numbers at 25 bytes, far beyond 256 MiB.
  ASSERT_EQ(r.errors.size(), 2u) << format_errors(r);
  EXPECT_EQ(r.errors[0].pointer, "/probes");
  EXPECT_NE(r.errors[0].message.find("9001 wavelengths × 15000 probe points = 135015000 spectral values"),
            std::string::npos) << r.errors[0].message;
  EXPECT_NE(r.errors[0].message.find("max_spectral_values = 100000000, --max-spectral-values"), std::string::npos);
  EXPECT_EQ(r.errors[1].pointer, "/probes");
  EXPECT_NE(r.errors[1].message.find("max_result_bytes = 268435456, --max-result-bytes"), std::string::npos)
      << r.errors[1].message;
  // Without output.spectral the probes' spectra stay out of the result: only the first limit remains.
  scene["output"] = {{"spectral", false}};
  EXPECT_EQ(decode_scene(scene.dump()).errors.size(), 1u);
}

// ---- solve time: the patch budget -------------------------------------------------------------------------

TEST(SceneLimits, TheServiceRefusesAHugeResultBeforeSolving) {
  TestServer server;
  auto cli = server.client();
  const json scene = floor_scene(9001);  // the case: a few hundred bytes, 1200 default patches
  ASSERT_LT(scene.dump().size(), 500u);
  const auto t0 = Clock::now();
  const json e = expect_error(cli->Post("/v1/solve", scene.dump(), "application/json"), 422, "solve_failed");
  EXPECT_LT(Clock::now() - t0, 20s);
  const std::string message = e.value("message", "");
  EXPECT_NE(message.find("max_result_bytes = 268435456, --max-result-bytes"), std::string::npos) << message;
  EXPECT_NE(message.find("output.spectral false makes it smaller"), std::string::npos) << message;
  const std::string id = submit(server, scene);
  const json s = wait_final(server, id);
  EXPECT_EQ(s.value("state", ""), "failed");
  EXPECT_NE(s.value("error", "").find("max_result_bytes"), std::string::npos) << s;
}

TEST(SceneLimits, WavelengthsTimesPatchesFailsNamingTheLimitAndBelowItSolves) {
  ServiceOptions jobs = job_options();
  jobs.scene_limits.max_spectral_values = 20000;
  TestServer server(jobs);
  auto cli = server.client();
  json fine = point_scene(10);  // 41 wavelengths, 2 probe points
  fine["meshing"] = {{"max_patch_area", 0.004}};  // 1000 patches: 41 × 1002 > 20 000
  const json e = expect_error(cli->Post("/v1/solve", fine.dump(), "application/json"), 422, "solve_failed");
  const std::string message = e.value("message", "");
  EXPECT_NE(message.find("the 485 patches that max_spectral_values = 20000, --max-spectral-values allows with 41 "
                         "wavelengths"), std::string::npos) << message;  // ⌊20000 / 41⌋ − 2 = 485
  json coarse = point_scene(10);  // 80 patches and whatever refinement the budget leaves room for
  const json result = expect_json(cli->Post("/v1/solve", coarse.dump(), "application/json"), 200);
  EXPECT_LE(41 * (result["stats"]["patches"].get<double>() + 2), 20000);
  EXPECT_NEAR(probe_lx(result, "below"), expected_below(10), 1e-3 * expected_below(10));
}

// A stand-in for `lambert solve-worker` that writes `bytes` of result and exits 0.
fs::path fake_worker(const ScratchDir& dir, std::size_t bytes) {
  const fs::path path = dir / ("worker_" + std::to_string(bytes) + ".sh");
  testing::write_file(path, "#!/bin/sh\nhead -c " + std::to_string(bytes) + " /dev/zero | tr '\\0' 'x'\n");
  ::chmod(path.c_str(), 0700);
  return path;
}

SolveProcessOutcome run_to_end(SolveProcess& p) {
  while (p.wait(100ms, [](const std::string&) {})) {
  }
  return p.outcome();
}

TEST(SceneLimits, TheServerStopsReadingAWorkerPastTheResultLimit) {
  ScratchDir dir("lambert_limits");
  SolveLimits limits;
  limits.scene.max_result_bytes = 1 << 20;
  SolveProcess over(fake_worker(dir, 3 << 20), "{}", limits);
  const SolveProcessOutcome o = run_to_end(over);
  EXPECT_EQ(o.kind, SolveProcessOutcome::Kind::Failed);
  EXPECT_NE(o.reason.find("max_result_bytes = 1048576, --max-result-bytes"), std::string::npos) << o.reason;
  EXPECT_TRUE(o.result.empty());
  SolveProcess under(fake_worker(dir, 1000), "{}", limits);
  const SolveProcessOutcome u = run_to_end(under);
  EXPECT_EQ(u.kind, SolveProcessOutcome::Kind::Done) << u.reason;
  EXPECT_EQ(u.result, std::string(1000, 'x'));
}

TEST(SceneLimits, SolveOnTheCommandLineNamesTheLimitAndItsOption) {
  ScratchDir dir("lambert_limits");
  testing::write_file(dir / "wide.json", floor_scene(9001).dump());
  const ChildOutcome r = testing::run_lambert({"solve", (dir / "wide.json").string(), "-o", (dir / "r.json").string()});
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("--max-result-bytes"), std::string::npos) << r.err;
  EXPECT_LT(r.seconds, 30);
  EXPECT_FALSE(fs::exists(dir / "r.json") && fs::file_size(dir / "r.json") > 0);
}

}  // namespace
}  // namespace lambert
