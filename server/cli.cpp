// The `lambert` command line (SPEC §3): every subcommand of server/cli_commands.inc, parsed by
// server/cli_parser.h. Exit status: 0 success, 1 solve failure, 2 bad usage or an invalid scene
// (the message names the field).
#include <vector>

#include "server/cli_parser.h"

namespace lambert {
#define LAMBERT_COMMAND(name) cli::CommandSpec command_##name();
#include "server/cli_commands.inc"
#undef LAMBERT_COMMAND
}  // namespace lambert

int main(int argc, char** argv) {
  const std::vector<lambert::cli::CommandSpec> commands = {
#define LAMBERT_COMMAND(name) lambert::command_##name(),
#include "server/cli_commands.inc"
#undef LAMBERT_COMMAND
  };
  return lambert::cli::run(argc, argv, commands, LAMBERT_VERSION);
}
