// The `lambert` command line (SPEC §3): every subcommand of server/cli_commands.inc, parsed by
// server/cli_parser.h. Exit status: 0 success, 1 solve failure, 2 bad usage or an invalid scene
// (the message names the field).
#include <string>
#include <vector>

#include "server/cli_parser.h"
#include "server/worker_command.h"

namespace lambert {
#define LAMBERT_COMMAND(name) cli::CommandSpec command_##name();
#include "server/cli_commands.inc"
#undef LAMBERT_COMMAND
}  // namespace lambert

int main(int argc, char** argv) {
  // Run by `lambert serve` for each solve (server/solve_process.h); not a user's command.
  if (argc > 1 && std::string(argv[1]) == "solve-worker")
    return lambert::run_solve_worker(std::vector<std::string>(argv + 2, argv + argc));
  const std::vector<lambert::cli::CommandSpec> commands = {
#define LAMBERT_COMMAND(name) lambert::command_##name(),
#include "server/cli_commands.inc"
#undef LAMBERT_COMMAND
  };
  return lambert::cli::run(argc, argv, commands, LAMBERT_VERSION);
}
