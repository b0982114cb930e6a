// Pieces every `lambert` subcommand shares: "SCENE.json [-o OUT]" arguments, reading a file, and the
// terminal progress display.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "server/scene_codec.h"

namespace lambert {

struct SceneCommandArgs {
  std::string scene_path;
  std::string output_path;  // empty: none given
};

// Parses "SCENE.json [-o|--output FILE]". On bad usage prints "lambert COMMAND: why" and the usage
// text to stderr and returns nullopt; "-h"/"--help" prints the usage to stdout and sets `help`.
std::optional<SceneCommandArgs> parse_scene_command(const std::vector<std::string>& args,
                                                    const std::string& command, const char* usage,
                                                    bool& help);

// Prints "PROGRAM: message" and the usage text to stderr; returns 2, the exit code of bad usage.
// PROGRAM is "lambert" or "lambert COMMAND".
int usage_error(const std::string& program, const std::string& message, const char* usage);

// Whole file as bytes; false if it cannot be read.
bool read_text_file(const std::string& path, std::string& text);

// How a scene read from the command line reaches its "file" surfaces: anywhere, relative paths
// against the scene file's directory.
FileAccess command_line_file_access(const std::string& scene_path);

// Decodes `text`, the contents of the scene file at `path` (command_line_file_access); when it is
// invalid, prints "PATH: invalid scene" and every error with its JSON pointer to stderr and returns
// nullopt.
std::optional<Scene> decode_scene_file(const std::string& path, const std::string& text);

// A progress callback that redraws "solving: NN %" on stderr when stderr is a terminal (else none).
std::function<void(double)> terminal_progress();

}  // namespace lambert
