// The `lambert` command line (SPEC §3, server/cli_parser.h) as a user meets it: the built binary run
// as a child process. Every command listed in server/cli_commands.inc answers --help; --version is
// the CMake project version; bad usage exits 2 naming the option; the options of SPEC §3 and the
// README still work; on a terminal (a pseudo-terminal here) the progress line is drawn in place.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <pty.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "server/cli_progress.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = LAMBERT_SOURCE_DIR;
const fs::path kBinary = LAMBERT_BINARY;

struct Outcome {
  int status = -1;
  std::string out, err;
};

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs the binary with `args` (no shell), stdout and stderr to files.
Outcome run(const std::vector<std::string>& args) {
  const fs::path dir = fs::temp_directory_path() / ("lambert_cli_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path out = dir / "stdout", err = dir / "stderr";
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    ::dup2(o, 1);
    ::dup2(e, 2);
    std::vector<char*> argv{const_cast<char*>(kBinary.c_str())};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(kBinary.c_str(), argv.data());
    ::_exit(127);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  Outcome r;
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_text(out);
  r.err = read_text(err);
  fs::remove_all(dir);
  return r;
}

// The command names of server/cli_commands.inc ("compare_rgb" is the command compare-rgb).
std::vector<std::string> registered_commands() {
  std::vector<std::string> names;
  std::istringstream lines(read_text(kSource / "server/cli_commands.inc"));
  const std::regex entry(R"(^LAMBERT_COMMAND\((\w+)\))");
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (!std::regex_search(line, m, entry)) continue;
    std::string name = m[1];
    std::replace(name.begin(), name.end(), '_', '-');
    names.push_back(name);
  }
  return names;
}

class TempDir {
 public:
  TempDir() : path_(fs::temp_directory_path() / ("lambert_cli_files_" + std::to_string(::getpid()))) {
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// A 1 m² black floor under a 1 cd point source 1 m above its centre, one wavelength: solves in
// milliseconds.
void write_small_scene(const fs::path& path) {
  std::ofstream(path) << R"({"lambert": 1, "spectrum": {"mode": "spectral", "wavelengths_nm": [555]},
    "materials": {"black": {"reflectance": 0}},
    "surfaces": [{"name": "floor", "material": "black", "polygon": [[0,0,0], [1,0,0], [1,1,0], [0,1,0]]}],
    "lights": [{"type": "point", "position": [0.5, 0.5, 1], "intensity": 1.0}]})";
}

TEST(Cli, EveryRegisteredCommandAnswersHelp) {
  const std::vector<std::string> commands = registered_commands();
  ASSERT_GE(commands.size(), 6u);
  const Outcome overview = run({"--help"});
  EXPECT_EQ(overview.status, 0);
  for (const std::string& name : commands) {
    SCOPED_TRACE(name);
    EXPECT_NE(overview.out.find("\n  " + name + " "), std::string::npos) << overview.out;
    const Outcome help = run({name, "--help"});
    EXPECT_EQ(help.status, 0) << help.err;
    EXPECT_NE(help.out.find("Usage: lambert " + name), std::string::npos) << help.out;
    EXPECT_NE(help.out.find("-h,--help"), std::string::npos);
    EXPECT_EQ(run({"help", name}).out, help.out);  // `lambert help NAME` is the same
  }
}

TEST(Cli, VersionIsTheProjectVersion) {
  const Outcome r = run({"--version"});
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out, std::string("lambert ") + LAMBERT_PROJECT_VERSION + "\n");
}

TEST(Cli, BadUsageExitsTwoNamingTheProblem) {
  struct Case {
    std::vector<std::string> args;
    std::string message;
  };
  const std::vector<Case> cases = {
      {{}, "lambert: no command"},
      {{"frobnicate"}, "lambert: unknown command 'frobnicate'"},
      {{"solve"}, "lambert solve: SCENE.json is required"},
      {{"solve", "a.json", "b.json"}, "lambert solve: The following argument was not expected: b.json"},
      {{"solve", "a.json", "--bogus"}, "--bogus"},
      {{"check"}, "lambert check: SCENE.json is required"},
      {{"serve", "--port", "70000"}, "lambert serve: --port: '70000' is not a whole number from 0 to 65535"},
      {{"serve", "--threads", "0"}, "--threads: '0' is not a whole number from 1 to 256"},
      {{"serve", "--job-time-limit-s", "nan"}, "--job-time-limit-s: 'nan' is not a number from 0 to 1e9"},
      {{"serve", "--mesh-root", "/no/such/dir"}, "--mesh-root: '/no/such/dir' is not an existing directory"},
      {{"render", "x.json"}, "lambert render: --output is required"},
      {{"render", "x.json", "-o", "x.png", "--false-color", "heat"},
       "--false-color: 'heat' is not one of: none, illuminance, luminance"},
      {{"render", "x.json", "-o", "x.png", "--white", "-1"}, "--white: '-1' is not a number greater than 0"},
      {{"bench", "--scaling", "10"}, "--scaling: '10' is not a number from 1000 to 2e6"},
      {{"bench", "--scaling", "5000", "--quick"}, "excludes"},
      {{"render", "x.json", "-o", "x.png", "--probe-grid", "g", "--smooth"}, "excludes"},
      {{"render", "x.json", "-o", "x.png", "--scale", "sqrt"}, "--scale: 'sqrt' is not one of: log, linear"},
      {{"export", "r.json"}, "lambert export: --output is required"},
      {{"export", "r.json", "-o", "x.glb", "--shading", "soft"}, "--shading: 'soft' is not one of: smooth, flat"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(::testing::PrintToString(c.args));
    const Outcome r = run(c.args);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;  // the message goes to stderr only
  }
}

TEST(Cli, SolveAndCheckKeepTheirOptions) {
  const TempDir dir;
  const fs::path scene = dir.path() / "scene.json", result = dir.path() / "result.json";
  write_small_scene(scene);
  const Outcome checked = run({"check", scene.string()});
  EXPECT_EQ(checked.status, 0) << checked.err;
  EXPECT_NE(checked.out.find("valid (1 surfaces, 2 triangles, 1 lights, 1 wavelengths)"), std::string::npos)
      << checked.out;
  for (const char* flag : {"-o", "--output"}) {
    fs::remove(result);
    const Outcome solved = run({"solve", scene.string(), flag, result.string()});
    EXPECT_EQ(solved.status, 0) << solved.err;
    EXPECT_NE(solved.out.find("result written to " + result.string()), std::string::npos);
    EXPECT_NE(read_text(result).find("\"patches\""), std::string::npos);
  }
  const Outcome to_stdout = run({"solve", scene.string()});  // the result on stdout, the summary on stderr
  EXPECT_EQ(to_stdout.status, 0);
  EXPECT_EQ(to_stdout.out.find("{"), 0u);
  EXPECT_FALSE(to_stdout.err.empty());

  // export: the format from the extension; a file that is not a result is bad input.
  const Outcome exported = run({"export", result.string(), "-o", (dir.path() / "r.glb").string()});
  EXPECT_EQ(exported.status, 0) << exported.err;
  EXPECT_EQ(read_text(dir.path() / "r.glb").substr(0, 4), "glTF");
  const Outcome no_format = run({"export", result.string(), "-o", (dir.path() / "r.txt").string()});
  EXPECT_EQ(no_format.status, 2);
  EXPECT_NE(no_format.err.find(".glb, .ply or .csv"), std::string::npos) << no_format.err;
  const Outcome scene_given = run({"export", scene.string(), "-o", (dir.path() / "s.glb").string()});
  EXPECT_EQ(scene_given.status, 2);
  EXPECT_NE(scene_given.err.find("a result of lambert solve is expected"), std::string::npos) << scene_given.err;

  std::ofstream(dir.path() / "bad.json") << R"({"lambert": 1, "surfaces": 3})";
  const Outcome bad = run({"check", (dir.path() / "bad.json").string()});
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("/surfaces"), std::string::npos) << bad.err;
  EXPECT_EQ(run({"solve", (dir.path() / "missing.json").string()}).status, 2);
}

TEST(Cli, ServeStartsWithItsOptionsAndStopsOnSigterm) {
  const TempDir dir;
  int out[2];
  ASSERT_EQ(::pipe(out), 0);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(out[1], 1);
    ::close(out[0]);
    const std::string mesh_root = dir.path().string();
    ::execl(kBinary.c_str(), kBinary.c_str(), "serve", "--port", "0", "--threads", "1", "--mesh-root",
            mesh_root.c_str(), "--job-time-limit-s", "5", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(out[1]);
  std::string line;
  char c = 0;
  while (::read(out[0], &c, 1) == 1 && c != '\n') line += c;
  EXPECT_NE(line.find("listening on http://127.0.0.1:"), std::string::npos) << line;
  EXPECT_NE(line.find("1 solver workers"), std::string::npos) << line;
  EXPECT_NE(line.find("mesh root " + fs::canonical(dir.path()).string()), std::string::npos) << line;
  ::kill(pid, SIGTERM);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ::close(out[0]);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
}

// On a pseudo-terminal the progress is one line redrawn with \r, ending at 100 % with the time taken.
TEST(Cli, ProgressIsDrawnInPlaceOnATerminal) {
  const TempDir dir;
  const fs::path scene = dir.path() / "scene.json", result = dir.path() / "result.json";
  // A grey floor and wall, so that there are links to form and a system to solve.
  std::ofstream(scene) << R"({"lambert": 1, "spectrum": {"mode": "spectral", "wavelengths_nm": [555]},
    "materials": {"grey": {"reflectance": 0.5}},
    "surfaces": [{"name": "floor", "material": "grey", "polygon": [[0,0,0], [1,0,0], [1,1,0], [0,1,0]]},
                 {"name": "wall", "material": "grey", "polygon": [[0,0,0], [0,0,1], [1,0,1], [1,0,0]]}],
    "lights": [{"type": "point", "position": [0.5, 0.5, 1], "intensity": 1.0}],
    "meshing": {"max_patch_area": 0.02}})";
  int master = -1;
  const pid_t pid = ::forkpty(&master, nullptr, nullptr, nullptr);
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::execl(kBinary.c_str(), kBinary.c_str(), "solve", scene.c_str(), "-o", result.c_str(),
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  std::string seen;
  char buffer[4096];
  for (ssize_t n; (n = ::read(master, buffer, sizeof buffer)) > 0;) seen.append(buffer, n);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ::close(master);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << seen;
  EXPECT_TRUE(std::regex_search(seen, std::regex(R"(\r\w+: 100 % \(\d+\.\d s\))"))) << seen;
  // The line names the solver's stages as they begin, in the pipeline's order.
  std::size_t at = 0;
  for (const char* stage : {"\rmeshing:", "\rvisibility:", "\rlinks:", "\rsolve:", "\rprobes:"}) {
    const std::size_t found = seen.find(stage, at);
    EXPECT_NE(found, std::string::npos) << stage << " after offset " << at << " in " << seen;
    if (found != std::string::npos) at = found;
  }
  // Without a terminal there is no progress line at all.
  const Outcome piped = run({"solve", scene.string(), "-o", result.string()});
  EXPECT_EQ(piped.err.find('\r'), std::string::npos);
}

TEST(CliProgress, TimeLeftIsTheLinearExtrapolation) {
  // elapsed × (1 − f) / f: 10 s at 50 % leaves 10 s; 30 s at 25 % leaves 90 s = 1.5 min → "2 min".
  EXPECT_EQ(progress_text("links", 0.5, 10), "links:  50 % (about 10 s left)");
  EXPECT_EQ(progress_text("solve", 0.25, 30), "solve:  25 % (about 2 min left)");
  EXPECT_EQ(progress_text("links", 0.9, 36), "links:  90 % (about 4 s left)");
  EXPECT_EQ(progress_text("links", 0.1, 1000), "links:  10 % (about 2.5 h left)");  // 9000 s
  // Too early to say: below 2 % or within the first second.
  EXPECT_EQ(progress_text("meshing", 0.01, 5), "meshing:   1 %");
  EXPECT_EQ(progress_text("meshing", 0.5, 0.5), "meshing:  50 %");
  EXPECT_EQ(progress_text("probes", 1, 12.34), "probes: 100 % (12.3 s)");
}

}  // namespace
}  // namespace lambert
