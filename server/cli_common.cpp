#include "server/cli_common.h"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

namespace lambert {

std::optional<SceneCommandArgs> parse_scene_command(const std::vector<std::string>& args,
                                                    const std::string& command, const char* usage,
                                                    bool& help) {
  help = false;
  auto fail = [&](const std::string& why) -> std::optional<SceneCommandArgs> {
    std::cerr << "lambert " << command << ": " << why << "\n" << usage;
    return std::nullopt;
  };
  SceneCommandArgs out;
  for (std::size_t k = 0; k < args.size(); ++k) {
    if (args[k] == "-o" || args[k] == "--output") {
      if (k + 1 >= args.size()) return fail("-o needs a file name");
      out.output_path = args[++k];
    } else if (args[k] == "-h" || args[k] == "--help") {
      std::cout << usage;
      help = true;
      return std::nullopt;
    } else if (!args[k].empty() && args[k][0] == '-') {
      return fail("unknown option " + args[k]);
    } else if (out.scene_path.empty()) {
      out.scene_path = args[k];
    } else {
      return fail(command + " takes one scene file");
    }
  }
  if (out.scene_path.empty()) return fail(command + " needs a scene file");
  return out;
}

bool read_text_file(const std::string& path, std::string& text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream buffer;
  buffer << in.rdbuf();
  text = buffer.str();
  return static_cast<bool>(in) || in.eof();
}

std::function<void(double)> terminal_progress() {
  if (!isatty(STDERR_FILENO)) return {};
  return [last = -1](double f) mutable {
    const int percent = static_cast<int>(f * 100);
    if (percent != last) std::fprintf(stderr, "\rsolving: %3d %%", last = percent);
    if (percent >= 100) std::fprintf(stderr, "\n");
  };
}

}  // namespace lambert
