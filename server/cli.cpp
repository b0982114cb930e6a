// The `lambert` command line (SPEC §3). Exit status: 0 success, 1 solve failure, 2 bad usage or an
// invalid scene (the message names the field).
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "server/result_codec.h"
#include "server/scene_codec.h"
#include "server/bench_command.h"
#include "server/cli_common.h"
#include "server/compare_command.h"
#include "server/render_command.h"
#include "server/serve_command.h"
#include "solver/radiosity.h"
#include "solver/report.h"

namespace {

constexpr const char* kUsage =
    "usage:\n"
    "  lambert solve SCENE.json [-o RESULT.json]   solve; summary on stdout, progress on stderr (tty)\n"
    "  lambert check SCENE.json                    validate only: every problem with its JSON pointer\n"
    "  lambert serve [--host 127.0.0.1] [--port 8080] [--threads N] [--data-dir DIR] [--mesh-root DIR]\n"
    "                                              the HTTP service (lambert serve --help for every option)\n"
    "  lambert bench [--quick] [-o BENCH.json] [--plot BENCH.png]\n"
    "                                              speed against error on built-in reference scenes\n"
    "  lambert bench --scaling MAX_PATCHES [-o SCALING.json]\n"
    "                                              time and memory from 10^3 patches up to MAX_PATCHES\n"
    "  lambert compare-rgb SCENE.json [-o REPORT.json]  spectral against rgb mode: per-patch dE00 and lux\n"
    "  lambert render (SCENE.json | RESULT.json) -o IMAGE.png [--camera \"eye=X,Y,Z look=X,Y,Z ...\"]\n"
    "                 [--false-color illuminance|luminance] [--white CD_M2]\n"
    "                                              a picture of the solution (lambert render --help)\n";

int usage_error(const std::string& message) { return lambert::usage_error("lambert", message, kUsage); }

// Decodes a scene file; prints errors and returns nullopt when it is invalid.
std::optional<lambert::Scene> load_scene(const std::string& path) {
  std::string text;
  if (!lambert::read_text_file(path, text)) {
    std::cerr << "lambert: cannot read " << path << "\n";
    return std::nullopt;
  }
  return lambert::decode_scene_file(path, text);
}

int check(const std::vector<std::string>& args) {
  if (args.size() != 1) return usage_error("check takes one scene file");
  const auto scene = load_scene(args[0]);
  if (!scene) return 2;
  std::size_t triangles = 0;
  for (const auto& s : scene->surfaces) triangles += s.mesh.triangles.size();
  std::cout << args[0] << ": valid (" << scene->surfaces.size() << " surfaces, " << triangles
            << " triangles, " << scene->lights.size() << " lights, " << scene->grid.size()
            << " wavelengths)\n";
  for (const auto& w : scene->warnings) std::cout << "warning: " << w << "\n";
  return 0;
}

int solve(const std::vector<std::string>& args) {
  bool help = false;
  const auto parsed = lambert::parse_scene_command(args, "solve", kUsage, help);
  if (!parsed) return help ? 0 : 2;
  const std::string& output_path = parsed->output_path;
  const auto scene = load_scene(parsed->scene_path);
  if (!scene) return 2;

  lambert::SolveControl control;
  control.progress = lambert::terminal_progress();
  try {
    const lambert::Solution solution = lambert::solve(*scene, control);
    const lambert::Report report = lambert::make_report(*scene, solution);
    if (output_path.empty()) {
      lambert::write_result(std::cout, *scene, solution, report);
      std::cout << "\n";
      std::cerr << lambert::summarize(*scene, solution, report);
    } else {
      std::ofstream out(output_path, std::ios::binary);
      lambert::write_result(out, *scene, solution, report);
      out << "\n";
      if (!out) {
        std::cerr << "lambert: cannot write " << output_path << "\n";
        return 1;
      }
      std::cout << lambert::summarize(*scene, solution, report) << "result written to " << output_path << "\n";
    }
  } catch (const lambert::SolveError& e) {
    std::cerr << "lambert: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "lambert: solve failed: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage_error("no command");
  const std::string command = argv[1];
  const std::vector<std::string> args(argv + 2, argv + argc);
  if (command == "solve") return solve(args);
  if (command == "check") return check(args);
  if (command == "-h" || command == "--help" || command == "help") {
    std::cout << kUsage;
    return 0;
  }
  if (command == "serve") return lambert::run_serve(args);
  if (command == "bench") return lambert::run_bench(args);
  if (command == "compare-rgb") return lambert::run_compare_rgb(args);
  if (command == "render") return lambert::render_command(args);
  return usage_error("unknown command '" + command + "'");
}
