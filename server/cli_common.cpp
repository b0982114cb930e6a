#include "server/cli_common.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace lambert {

int usage_error(const std::string& program, const std::string& message, const char* usage) {
  std::cerr << program << ": " << message << "\n" << usage;
  return 2;
}

std::optional<SceneCommandArgs> parse_scene_command(const std::vector<std::string>& args,
                                                    const std::string& command, const char* usage,
                                                    bool& help) {
  help = false;
  auto fail = [&](const std::string& why) -> std::optional<SceneCommandArgs> {
    usage_error("lambert " + command, why, usage);
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

FileAccess command_line_file_access(const std::string& scene_path) {
  FileAccess files;
  files.policy = FileAccess::Policy::Anywhere;
  files.base_dir = std::filesystem::path(scene_path).parent_path();
  return files;
}

std::optional<Scene> decode_scene_file(const std::string& path, const std::string& text) {
  DecodeResult decoded = decode_scene(text, command_line_file_access(path));
  if (!decoded.ok()) {
    std::cerr << path << ": invalid scene\n" << format_errors(decoded.errors);
    return std::nullopt;
  }
  return std::move(decoded.scene);
}

}  // namespace lambert
