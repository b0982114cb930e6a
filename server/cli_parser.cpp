// The command line's parser (cli_parser.h): the only file that includes CLI11. Values are checked by
// validators written here, so that every message says what was expected in the same words.
#include "server/cli_parser.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <cstdio>

namespace lambert::cli {

struct Access {
  static CLI::App* app(Options& o) { return static_cast<CLI::App*>(o.app_); }
  static Options make(CLI::App* app) { return Options(app); }
  static CLI::Option* option(const Option& o) { return static_cast<CLI::Option*>(o.impl_); }
};

namespace {

CLI::Option* impl(const Option& o) { return Access::option(o); }

// Parses all of `text` as a T (no sign for unsigned types, no trailing characters).
template <typename T>
std::optional<T> parse_exactly(const std::string& text) {
  T value{};
  const char* first = text.data();
  const char* last = first + text.size();
  if (text.empty() || (std::is_unsigned_v<T> && text[0] == '-')) return std::nullopt;
  const auto [end, ec] = std::from_chars(first, last, value);
  if (ec != std::errc() || end != last) return std::nullopt;
  if constexpr (std::is_floating_point_v<T>)
    if (!std::isfinite(value)) return std::nullopt;
  return value;
}

template <typename T>
std::string show(T value) {
  if constexpr (std::is_floating_point_v<T>) {
    // 1e9 rather than 1e+09.
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    std::string s = text;
    for (const char* noise : {"e+0", "e+"})
      if (const auto at = s.find(noise); at != std::string::npos) {
        s.replace(at, std::string(noise).size(), "e");
        break;
      }
    return s;
  } else {
    return std::to_string(value);
  }
}

template <typename T>
CLI::Validator in_range(T lo, T hi) {
  const std::string kind = std::is_floating_point_v<T> ? "a number" : "a whole number";
  const bool unbounded = hi == std::numeric_limits<T>::max();
  const std::string range = unbounded ? " of at least " + show(lo) : " from " + show(lo) + " to " + show(hi);
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        const auto value = parse_exactly<T>(text);
        if (!value || *value < lo || *value > hi) return "'" + text + "' is not " + kind + range;
        return {};
      },
      "", "in_range");
}

CLI::Validator one_of(const std::vector<std::string>& allowed) {
  std::string list;
  for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        if (std::find(allowed.begin(), allowed.end(), text) != allowed.end()) return {};
        return "'" + text + "' is not one of: " + list;
      },
      "", "one_of");
}

CLI::Validator existing_directory() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        std::error_code ec;
        if (!text.empty() && std::filesystem::is_directory(text, ec)) return {};
        return "'" + text + "' is not an existing directory";
      },
      "", "existing_directory");
}

CLI::Validator positive_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const auto value = parse_exactly<double>(text);
        if (!value || !(*value > 0)) return "'" + text + "' is not a number greater than 0";
        return {};
      },
      "", "positive");
}

// The help text with the accepted range appended, when it is not the type's whole range.
template <typename T>
std::string with_range(const std::string& help, T lo, T hi) {
  if (hi == std::numeric_limits<T>::max()) return help + " (at least " + show(lo) + ")";
  return help + " (" + show(lo) + " to " + show(hi) + ")";
}

constexpr const char* kFooter = "Run 'lambert COMMAND --help' for the options of a command.";
constexpr std::size_t kHelpColumn = 34;  // wide enough for "--false-color,--false-colour"

// The subcommand whose arguments were being parsed when `error` was thrown ("" for none).
std::string failing_command(const CLI::App& app) {
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App* s) { return s->parsed() > 0; }))
    return sub->get_name();
  return {};
}

}  // namespace

Option& Option::required() {
  impl(*this)->required();
  return *this;
}
Option& Option::excludes(const Option& other) {
  impl(*this)->excludes(impl(other));
  return *this;
}
Option& Option::needs(const Option& other) {
  impl(*this)->needs(impl(other));
  return *this;
}

Option Options::input(const std::string& name, std::string& into, const std::string& help) {
  return Option(Access::app(*this)->add_option(name, into, help)->required()->type_name(""));
}

Option Options::output(std::string& into, const std::string& help) {
  return Option(Access::app(*this)->add_option("-o,--output", into, help)->type_name("FILE"));
}

Option Options::text(const std::string& names, std::string& into, const std::string& help,
                     const std::string& placeholder) {
  return Option(Access::app(*this)->add_option(names, into, help)->type_name(placeholder)->capture_default_str());
}

Option Options::choice(const std::string& names, std::string& into, const std::vector<std::string>& allowed,
                       const std::string& help) {
  std::string type;
  for (const std::string& a : allowed) type += (type.empty() ? "" : "|") + a;
  return Option(Access::app(*this)
                    ->add_option(names, into, help)
                    ->type_name(type)
                    ->check(one_of(allowed))
                    ->capture_default_str());
}

Option Options::integer(const std::string& names, int& into, int lo, int hi, const std::string& help) {
  return Option(Access::app(*this)
                    ->add_option(names, into, with_range(help, lo, hi))
                    ->type_name("N")
                    ->check(in_range(lo, hi))
                    ->capture_default_str());
}

Option Options::count(const std::string& names, std::size_t& into, std::size_t lo, std::size_t hi,
                      const std::string& help) {
  return Option(Access::app(*this)
                    ->add_option(names, into, with_range(help, lo, hi))
                    ->type_name("N")
                    ->check(in_range(lo, hi))
                    ->capture_default_str());
}

Option Options::number(const std::string& names, double& into, double lo, double hi, const std::string& help) {
  return Option(Access::app(*this)
                    ->add_option(names, into, with_range(help, lo, hi))
                    ->type_name("X")
                    ->check(in_range(lo, hi))
                    ->capture_default_str());
}

Option Options::number(const std::string& names, std::optional<double>& into, double lo, double hi,
                       const std::string& help) {
  return Option(Access::app(*this)->add_option(names, into, with_range(help, lo, hi))->type_name("X")->check(in_range(lo, hi)));
}

Option Options::positive(const std::string& names, std::optional<double>& into, const std::string& help) {
  return Option(Access::app(*this)->add_option(names, into, help)->type_name("X")->check(positive_number()));
}

Option Options::directory(const std::string& names, std::string& into, const std::string& help) {
  return Option(Access::app(*this)->add_option(names, into, help)->type_name("DIR")->check(existing_directory()));
}

Option Options::flag(const std::string& names, bool& into, const std::string& help) {
  return Option(Access::app(*this)->add_flag(names, into, help));
}

void Options::footer(const std::string& text) { Access::app(*this)->footer(text); }

int usage_error(const std::string& command, const std::string& message) {
  const std::string program = command.empty() ? "lambert" : "lambert " + command;
  std::cerr << program << ": " << message << "\nRun '" << program << " --help' for the options.\n";
  return 2;
}

int run(int argc, const char* const* argv, const std::vector<CommandSpec>& commands, const std::string& version) {
  CLI::App app("Lambert " + version + ": spectral radiosity and area-light solver.", "lambert");
  app.set_version_flag("--version", "lambert " + version);
  app.require_subcommand(1);
  app.get_formatter()->column_width(kHelpColumn);
  std::vector<std::function<int()>> runners;
  std::vector<CLI::App*> subs;
  for (const CommandSpec& c : commands) {
    subs.push_back(app.add_subcommand(c.name, c.summary));
    Options options = Access::make(subs.back());
    runners.push_back(c.define(options));
  }
  app.footer(kFooter);  // after the subcommands, which would inherit it

  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty()) {
    std::cerr << "lambert: no command\n" << app.help();
    return 2;
  }
  if (args[0] == "help") {  // `lambert help [COMMAND]`
    args.erase(args.begin());
    args.push_back("--help");
  }
  const bool known = std::any_of(commands.begin(), commands.end(), [&](const CommandSpec& c) { return c.name == args[0]; });
  if (!known && args[0].rfind("-", 0) != 0) return usage_error("", "unknown command '" + args[0] + "'");

  std::reverse(args.begin(), args.end());  // CLI11 takes a vector last argument first
  try {
    app.parse(args);
  } catch (const CLI::Success& e) {  // --help, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return usage_error(failing_command(app), e.what());
  }
  for (std::size_t k = 0; k < subs.size(); ++k)
    if (subs[k]->parsed()) return runners[k]();
  return usage_error("", "no command");
}

int run_one(const CommandSpec& command, const std::vector<std::string>& args) {
  CLI::App app(command.summary, "lambert " + command.name);
  app.get_formatter()->column_width(kHelpColumn);
  Options options = Access::make(&app);
  const std::function<int()> runner = command.define(options);
  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    app.parse(reversed);
  } catch (const CLI::Success& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return usage_error(command.name, e.what());
  }
  return runner();
}

}  // namespace lambert::cli
