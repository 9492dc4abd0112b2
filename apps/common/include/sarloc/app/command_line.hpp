#pragma once
// Command-line parsing with sarloc's exit codes (docs/operations.md): --help and --version
// print and give 0; any other parse error (unknown option, bad value, missing required
// option, bad --log-level) prints CLI11's message and gives ExitCode::kUsage (2), never
// CLI11's own codes (106, 105, ...).
//
//   CLI::App cli{"sarloc-x: ..."};
//   app::add_log_level_option(cli, log_level);
//   if (auto code = app::parse_command_line(cli, argc, argv)) return *code;
#include "sarloc/app/cli_app.hpp"
#include <optional>
#include <string>

namespace sarloc::app {

/// --log-level, checked at parse time against spdlog's level names.
void add_log_level_option(CLI::App& cli, std::string& level);

/// nullopt: parsed, go on. Otherwise the exit code to return from main().
std::optional<int> parse_command_line(CLI::App& cli, int argc, char** argv);

}  // namespace sarloc::app
