#include "server/cli_common.h"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
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

bool write_text_file(const std::string& command, const std::string& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (out) return true;
  std::cerr << "lambert " << command << ": cannot write " << path << "\n";
  return false;
}

FileAccess command_line_file_access(const std::string& scene_path) {
  FileAccess files;
  files.policy = FileAccess::Policy::Anywhere;
  files.base_dir = std::filesystem::path(scene_path).parent_path();
  return files;
}

std::optional<Scene> decode_scene_file(const std::string& path, const std::string& text, const SceneLimits& limits) {
  DecodeResult decoded = decode_scene(text, command_line_file_access(path), limits);
  if (!decoded.ok()) {
    std::cerr << path << ": invalid scene\n" << format_errors(decoded);
    return std::nullopt;
  }
  return std::move(decoded.scene);
}

std::optional<Scene> load_scene_file(const std::string& command, const std::string& path, const SceneLimits& limits) {
  std::string text;
  if (!read_text_file(path, text)) {
    std::cerr << "lambert " << command << ": cannot read " << path << "\n";
    return std::nullopt;
  }
  return decode_scene_file(path, text, limits);
}

void scene_limit_options(cli::Options& o, SceneLimits& limits) {
  constexpr std::size_t kMax = std::numeric_limits<std::size_t>::max();
  o.count("--max-probe-points", limits.max_probe_points, 0, kMax, "probe points of a scene, 0 for no limit");
  o.count("--max-spectral-values", limits.max_spectral_values, 0, kMax,
          "wavelengths x (patches + probe points) of a scene, 0 for no limit");
  o.count("--max-result-bytes", limits.max_result_bytes, 0, kMax,
          "size of a result document (an upper bound known before the solve), 0 for no limit");
}

void apply_patch_budget(const Scene& scene, const SceneLimits& limits, std::size_t max_patches, SolveControl& control) {
  const PatchBudget budget = tighter(patch_budget(scene, limits), max_patches, "max_patches");
  control.max_patches = budget.max_patches;
  control.max_patches_reason = budget.reason;
}

}  // namespace lambert
