// `lambert batch` through the built binary: every scene's result is its own closed form E = I/h²
// (REFERENCES P1: a point source of I cd 2 m above a black floor), whether solved locally, on a
// service, or in shards; a second run solves only what has no result; shards cover the study once.
#pragma GCC diagnostic ignored "-Wunused-function"  // the fixture's helpers this file does not use
#include "tests/service_fixture.h"

#include <pty.h>
#include <sys/stat.h>

#include <regex>

#include "tests/serve_process.h"

namespace lambert {
namespace {

struct BatchRun {
  int status = -1;
  std::string out, err;
};

BatchRun run_batch(const TempDir& dir, const std::string& args) {
  const fs::path out = dir.path / "stdout.txt", err = dir.path / "stderr.txt";
  const std::string command = std::string(LAMBERT_BINARY) + " batch " + args + " > " + out.string() + " 2> " +
                              err.string() + " < /dev/null";
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_text(out), read_text(err)};
}

// The candela of each scene, by name; the scenes of the study.
const std::vector<std::pair<std::string, double>> kStudy = {
    {"a-40cd", 40}, {"b-55cd", 55}, {"c-70cd", 70}, {"d-85cd", 85}, {"e-100cd", 100}};

void expect_closed_form(const fs::path& out_dir, const std::string& name, double cd) {
  const json result = json::parse(read_text(out_dir / (name + ".result.json")), nullptr, false);
  ASSERT_TRUE(result.is_object()) << name;
  EXPECT_NEAR(probe_lx(result, "below"), expected_below(cd), 1e-9 * expected_below(cd)) << name;  // I/h²
  EXPECT_NEAR(probe_lx(result, "side"), expected_side(cd), 1e-9 * expected_side(cd)) << name;     // I h/d³
}

std::size_t csv_rows(const fs::path& file) {
  std::istringstream in(read_text(file));
  std::size_t rows = 0;
  for (std::string line; std::getline(in, line);) rows += !line.empty();
  return rows ? rows - 1 : 0;  // without the header
}

TEST(Batch, ADirectoryIsSolvedLocallyAndASecondRunResumes) {
  const TempDir dir;
  fs::create_directories(dir.path / "scenes");
  for (const auto& [name, cd] : kStudy) std::ofstream(dir.path / "scenes" / (name + ".json")) << point_scene(cd).dump(1);
  const fs::path out = dir.path / "out";
  BatchRun r = run_batch(dir, (dir.path / "scenes").string() + " -o " + out.string() + " --jobs 2");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const auto& [name, cd] : kStudy) {
    expect_closed_form(out, name, cd);
    EXPECT_NE(r.out.find(name), std::string::npos) << r.out;  // a row of the table
  }
  EXPECT_NE(r.out.find("key illuminances"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("below 10 lx"), std::string::npos) << r.out;  // 40 cd / (2 m)²
  EXPECT_EQ(csv_rows(out / "summary.csv"), kStudy.size());

  // Interrupted after three: two results are missing. The next run solves those two only.
  fs::remove(out / "a-40cd.result.json");
  fs::remove(out / "d-85cd.result.json");
  struct stat before{};
  ::stat((out / "c-70cd.result.json").c_str(), &before);
  r = run_batch(dir, (dir.path / "scenes").string() + " -o " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("3 solved earlier, 2 to solve"), std::string::npos) << r.err;
  struct stat after{};
  ::stat((out / "c-70cd.result.json").c_str(), &after);
  EXPECT_EQ(before.st_mtim.tv_nsec, after.st_mtim.tv_nsec);
  EXPECT_EQ(before.st_ino, after.st_ino);
  expect_closed_form(out, "a-40cd", 40);
  expect_closed_form(out, "d-85cd", 85);
}

// A manifest of inline scenes (and one scene file), the names given.
fs::path write_manifest(const TempDir& dir) {
  const fs::path manifest = dir.path / "study.jsonl";
  std::ofstream m(manifest);
  for (const auto& [name, cd] : kStudy) {
    if (name == "c-70cd") {
      std::ofstream(dir.path / "c.json") << point_scene(cd).dump();
      m << json{{"scene", "c.json"}, {"name", name}}.dump() << "\n\n";
    } else {
      m << json{{"scene", point_scene(cd)}, {"name", name}}.dump() << "\n";
    }
  }
  return manifest;
}

TEST(Batch, ShardsCoverTheStudyOnceBetweenThem) {
  const TempDir dir;
  const fs::path manifest = write_manifest(dir), out = dir.path / "out";
  std::set<std::string> seen;
  for (const std::string shard : {"0/2", "1/2"}) {
    const auto before = fs::exists(out) ? std::distance(fs::directory_iterator(out), {}) : 0;
    const BatchRun r = run_batch(dir, manifest.string() + " -o " + out.string() + " --shard " + shard);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_GT(std::distance(fs::directory_iterator(out), {}), before);
  }
  // Sorted names a..e: shard 0 takes a, c, e and shard 1 b, d.
  EXPECT_EQ(csv_rows(out / "summary-0.csv"), 3u);
  EXPECT_EQ(csv_rows(out / "summary-1.csv"), 2u);
  for (const auto& [name, cd] : kStudy) expect_closed_form(out, name, cd);
}

TEST(Batch, OnAServiceTheAnswersAreTheSameAndARepeatedSceneIsCached) {
  const TempDir dir;
  const fs::path manifest = write_manifest(dir), out = dir.path / "out";
  std::ofstream(manifest, std::ios::app) << json{{"scene", point_scene(40)}, {"name", "f-again-40cd"}}.dump() << "\n";
  ServeProcess server({"--threads", "1"}, dir.path / "serve.log");
  ASSERT_GT(server.port(), 0);
  const BatchRun r = run_batch(dir, manifest.string() + " -o " + out.string() + " --jobs 1 --server http://127.0.0.1:" +
                                   std::to_string(server.port()));
  ASSERT_EQ(r.status, 0) << r.err;
  for (const auto& [name, cd] : kStudy) expect_closed_form(out, name, cd);
  expect_closed_form(out, "f-again-40cd", 40);
  EXPECT_NE(r.out.find("done (cached)"), std::string::npos) << r.out;  // the repeated scene, in order after a
  EXPECT_TRUE(read_text(out / "a-40cd.result.json") == read_text(out / "f-again-40cd.result.json"));
}

// On a pseudo-terminal the bar is redrawn in place (\r) and ends full; piped, there is none.
TEST(Batch, AProgressBarIsDrawnOnATerminalOnly) {
  const TempDir dir;
  fs::create_directories(dir.path / "scenes");
  for (double cd : {10.0, 20.0}) std::ofstream(dir.path / "scenes" / (std::to_string(int(cd)) + ".json")) << point_scene(cd);
  const std::string scenes = (dir.path / "scenes").string(), out = (dir.path / "out").string();
  int master = -1;
  const pid_t pid = ::forkpty(&master, nullptr, nullptr, nullptr);
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::execl(LAMBERT_BINARY, LAMBERT_BINARY, "batch", scenes.c_str(), "-o", out.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  std::string seen;
  char buffer[4096];
  for (ssize_t n; (n = ::read(master, buffer, sizeof buffer)) > 0;) seen.append(buffer, n);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ::close(master);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << seen;
  EXPECT_TRUE(std::regex_search(seen, std::regex(R"(\r\[\.{30}\] 0/2 finished, 1 running)"))) << seen;
  EXPECT_TRUE(std::regex_search(seen, std::regex(R"(\r\[#{30}\] 2/2 finished, 0 running)"))) << seen;
  fs::remove_all(dir.path / "out");
  const BatchRun piped = run_batch(dir, scenes + " -o " + out);
  EXPECT_EQ(piped.status, 0);
  EXPECT_EQ(piped.err.find('\r'), std::string::npos) << piped.err;
}

TEST(Batch, BadInputIsRefusedNamingTheLineAndAFailedSceneIsReported) {
  const TempDir dir;
  const fs::path bad = dir.path / "bad.jsonl";
  std::ofstream(bad) << json{{"scene", point_scene(10)}}.dump() << "\n{\"scene\": 3}\nnot json\n";
  BatchRun r = run_batch(dir, bad.string() + " -o " + (dir.path / "out").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("bad.jsonl:2: \"scene\" must be a file name or a scene object"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("bad.jsonl:3:"), std::string::npos) << r.err;
  EXPECT_EQ(run_batch(dir, bad.string() + " -o x --shard 2/2").status, 2);

  const fs::path mixed = dir.path / "mixed.jsonl";
  json invalid = point_scene(10);
  invalid["materials"]["black"]["reflectance"] = 1.5;
  std::ofstream(mixed) << json{{"scene", point_scene(20)}, {"name", "good"}}.dump() << "\n"
                       << json{{"scene", invalid}, {"name", "broken"}}.dump() << "\n";
  r = run_batch(dir, mixed.string() + " -o " + (dir.path / "out").string());
  EXPECT_EQ(r.status, 1) << r.err;
  expect_closed_form(dir.path / "out", "good", 20);
  EXPECT_NE(read_text(dir.path / "out/broken.error.txt").find("/materials/black/reflectance"), std::string::npos);
  EXPECT_NE(r.out.find("failed"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace lambert
