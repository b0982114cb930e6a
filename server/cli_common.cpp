#include "server/cli_common.h"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace lambert {

bool read_text_file(const std::string& path, std::string& text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream buffer;
  buffer << in.rdbuf();
  text = buffer.str();
  return static_cast<bool>(in) || in.eof();
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
    std::cerr << path << ": invalid scene\n" << format_errors(decoded);
    return std::nullopt;
  }
  return std::move(decoded.scene);
}

std::optional<Scene> load_scene_file(const std::string& command, const std::string& path) {
  std::string text;
  if (!read_text_file(path, text)) {
    std::cerr << "lambert " << command << ": cannot read " << path << "\n";
    return std::nullopt;
  }
  return decode_scene_file(path, text);
}

}  // namespace lambert
