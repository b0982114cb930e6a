// The `lambert` command line's one parser (SPEC §3). Every subcommand declares its options through
// `cli::Options` and is listed once in server/cli_commands.inc; CLI11 is used only behind this header
// (server/cli_parser.cpp), so that it is compiled once. Exit status: the command's own, 0 after
// --help or --version, 2 on bad usage (the message names the option and what it expects).
//
// A subcommand is one file, server/NAME_command.cpp, defining
//     cli::CommandSpec command_NAME() {
//       return {"NAME", "one line for `lambert --help`", [](cli::Options& o) {
//                 auto args = std::make_shared<NameArgs>();  // the parsed values live here
//                 o.input("SCENE.json", args->scene, "the scene");
//                 o.output(args->output, "where the result goes");
//                 return [args] { return run_name(*args); };  // runs after a successful parse
//               }};
//     }
// and one line `LAMBERT_COMMAND(NAME)` in server/cli_commands.inc.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace lambert::cli {

// A declared option, for the few relations between options.
class Option {
 public:
  Option& required();                      // bad usage when absent
  Option& excludes(const Option& other);   // bad usage when both are given
  Option& needs(const Option& other);      // bad usage when this one is given without `other`

 private:
  friend class Options;
  friend struct Access;
  explicit Option(void* impl) : impl_(impl) {}
  void* impl_;  // CLI::Option*
};

// The option table of one subcommand. NAMES is CLI11's list: "-o,--output", "--port". Each value
// is checked while parsing; the message of a bad one says what was expected, and defaults (the
// bound variable's value when declared) are shown in --help.
class Options {
 public:
  // A required positional argument (a file name).
  Option input(const std::string& name, std::string& into, const std::string& help);
  // The file a command writes: "-o,--output" in every command.
  Option output(std::string& into, const std::string& help);
  // Free text; `placeholder` names it in --help ("TEXT", "FILE", "DIR").
  Option text(const std::string& names, std::string& into, const std::string& help,
              const std::string& placeholder = "TEXT");
  // One of `allowed`, spelled exactly.
  Option choice(const std::string& names, std::string& into, const std::vector<std::string>& allowed,
                const std::string& help);
  // Whole numbers in [lo, hi].
  Option integer(const std::string& names, int& into, int lo, int hi, const std::string& help);
  Option count(const std::string& names, std::size_t& into, std::size_t lo, std::size_t hi,
               const std::string& help);
  // Finite numbers in [lo, hi].
  Option number(const std::string& names, double& into, double lo, double hi, const std::string& help);
  // The same, absent staying nullopt.
  Option number(const std::string& names, std::optional<double>& into, double lo, double hi,
                const std::string& help);
  // A finite number greater than zero; absent stays nullopt.
  Option positive(const std::string& names, std::optional<double>& into, const std::string& help);
  // An existing directory.
  Option directory(const std::string& names, std::string& into, const std::string& help);
  Option flag(const std::string& names, bool& into, const std::string& help);
  // Text after the option list in --help.
  void footer(const std::string& text);

 private:
  friend struct Access;
  explicit Options(void* app) : app_(app) {}
  void* app_;  // CLI::App*
};

struct CommandSpec {
  std::string name;
  std::string summary;  // one line for `lambert --help`
  // Declares the command's options, bound to state the returned function owns; that function runs
  // after a successful parse and returns the exit status.
  std::function<std::function<int()>(Options&)> define;
};

// Parses argv (argv[0] is the program) for one of `commands` and runs it. `lambert help [COMMAND]`
// is --help.
int run(int argc, const char* const* argv, const std::vector<CommandSpec>& commands, const std::string& version);

// One command alone, given the arguments after its name (what the tests call).
int run_one(const CommandSpec& command, const std::vector<std::string>& args);

// Bad usage found after parsing (a value that only the command can judge): prints
// "lambert COMMAND: message" and where the options are listed to stderr; returns 2.
int usage_error(const std::string& command, const std::string& message);

}  // namespace lambert::cli
