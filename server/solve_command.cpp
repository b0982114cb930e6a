// `lambert solve SCENE.json [-o RESULT.json]` (SPEC §3): solves a scene; the result goes to the file
// (summary on stdout) or to stdout (summary on stderr). Exit status: 0 solved, 1 the solve or the
// writing failed, 2 bad usage or an invalid scene.
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include "server/cli_common.h"
#include "server/cli_parser.h"
#include "server/cli_progress.h"
#include "server/result_codec.h"
#include "solver/radiosity.h"
#include "solver/report.h"

namespace lambert {
namespace {

struct SolveArgs {
  std::string scene_path;
  std::string output_path;  // empty: the result goes to stdout
  SceneLimits limits;
};

int write_solution(const SolveArgs& args, const Scene& scene, const Solution& solution) {
  const Report report = make_report(scene, solution);
  if (args.output_path.empty()) {
    write_result(std::cout, scene, solution, report);
    std::cout << "\n";
    std::cerr << summarize(scene, solution, report);
    return 0;
  }
  std::ofstream out(args.output_path, std::ios::binary);
  write_result(out, scene, solution, report);
  out << "\n";
  if (!out) {
    std::cerr << "lambert solve: cannot write " << args.output_path << "\n";
    return 1;
  }
  std::cout << summarize(scene, solution, report) << "result written to " << args.output_path << "\n";
  return 0;
}

int run_solve(const SolveArgs& args) {
  const auto scene = load_scene_file("solve", args.scene_path, args.limits);
  if (!scene) return 2;
  SolveControl control;
  apply_patch_budget(*scene, args.limits, 0, control);
  show_progress_on_terminal(control);
  try {
    return write_solution(args, *scene, solve(*scene, control));
  } catch (const SolveError& e) {
    std::cerr << "lambert solve: " << e.what() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "lambert solve: solve failed: " << e.what() << "\n";
  }
  return 1;
}

}  // namespace

cli::CommandSpec command_solve() {
  return {"solve", "solve a scene: the result as JSON, a summary, progress on a terminal",
          [](cli::Options& o) {
            auto args = std::make_shared<SolveArgs>();
            o.input("SCENE.json", args->scene_path, "the scene (docs/SPEC.md section 1)");
            o.output(args->output_path, "write the result here and the summary to stdout "
                                        "(default: the result to stdout, the summary to stderr)");
            scene_limit_options(o, args->limits);
            return [args] { return run_solve(*args); };
          }};
}

}  // namespace lambert
