// Pieces the `lambert` subcommands share: reading a file, and decoding a scene file with its errors.
#pragma once

#include <optional>
#include <string>

#include "server/scene_codec.h"

namespace lambert {

// Whole file as bytes; false if it cannot be read.
bool read_text_file(const std::string& path, std::string& text);

// How a scene read from the command line reaches its "file" surfaces: anywhere, relative paths
// against the scene file's directory.
FileAccess command_line_file_access(const std::string& scene_path);

// Decodes `text`, the contents of the scene file at `path` (command_line_file_access); when it is
// invalid, prints "PATH: invalid scene" and every error with its JSON pointer to stderr and returns
// nullopt.
std::optional<Scene> decode_scene_file(const std::string& path, const std::string& text);

// Reads and decodes the scene file at `path`; prints what is wrong ("lambert COMMAND: cannot read
// PATH", or the decoder's errors) and returns nullopt.
std::optional<Scene> load_scene_file(const std::string& command, const std::string& path);

}  // namespace lambert
