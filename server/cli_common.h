// Pieces the `lambert` subcommands share: reading and writing a file, and decoding a scene file with its errors.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "server/cli_parser.h"
#include "server/scene_codec.h"
#include "solver/radiosity.h"

namespace lambert {

// Whole file as bytes; false if it cannot be read.
bool read_text_file(const std::string& path, std::string& text);
// Writes `bytes` to the file at `path` (created or replaced); when that fails, prints
// "lambert COMMAND: cannot write PATH" to stderr and returns false.
bool write_text_file(const std::string& command, const std::string& path, std::string_view bytes);

// How a scene read from the command line reaches its "file" surfaces: anywhere, relative paths
// against the scene file's directory.
FileAccess command_line_file_access(const std::string& scene_path);

// Decodes `text`, the contents of the scene file at `path` (command_line_file_access); when it is
// invalid, prints "PATH: invalid scene" and every error with its JSON pointer to stderr and returns
// nullopt.
std::optional<Scene> decode_scene_file(const std::string& path, const std::string& text,
                                       const SceneLimits& limits = {});

// Reads and decodes the scene file at `path`; prints what is wrong ("lambert COMMAND: cannot read
// PATH", or the decoder's errors) and returns nullopt.
std::optional<Scene> load_scene_file(const std::string& command, const std::string& path,
                                     const SceneLimits& limits = {});

// --max-probe-points, --max-spectral-values and --max-result-bytes (server/scene_limits.h), shared by
// `lambert solve`, `check` and `serve`.
void scene_limit_options(cli::Options& o, SceneLimits& limits);

// The solver's patch budget for `scene` under `limits` (and a plain patch limit, 0: none).
void apply_patch_budget(const Scene& scene, const SceneLimits& limits, std::size_t max_patches,
                        SolveControl& control);

}  // namespace lambert
