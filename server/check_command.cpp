// `lambert check SCENE.json` (SPEC §3): validates a scene without solving it. Exit status: 0 valid
// (warnings on stdout), 2 bad usage or an invalid scene (every error with its JSON pointer).
#include <iostream>
#include <memory>
#include <string>

#include "server/cli_common.h"
#include "server/cli_parser.h"

namespace lambert {
namespace {

struct CheckArgs {
  std::string path;
  SceneLimits limits;
};

int run_check(const CheckArgs& args) {
  const std::string& path = args.path;
  const auto scene = load_scene_file("check", path, args.limits);
  if (!scene) return 2;
  std::size_t triangles = 0;
  for (const auto& s : scene->surfaces) triangles += s.mesh.triangles.size();
  std::cout << path << ": valid (" << scene->surfaces.size() << " surfaces, " << triangles << " triangles, "
            << scene->lights.size() << " lights, " << scene->grid.size() << " wavelengths)\n";
  for (const auto& w : scene->warnings) std::cout << "warning: " << w << "\n";
  return 0;
}

}  // namespace

cli::CommandSpec command_check() {
  return {"check", "validate a scene without solving it: every problem with its JSON pointer",
          [](cli::Options& o) {
            auto args = std::make_shared<CheckArgs>();
            o.input("SCENE.json", args->path, "the scene (docs/SPEC.md section 1)");
            scene_limit_options(o, args->limits);
            return [args] { return run_check(*args); };
          }};
}

}  // namespace lambert
