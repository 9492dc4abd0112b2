#include "sarloc/app/command_line.hpp"

#include <CLI/CLI.hpp>

#include "sarloc/app/exit_codes.hpp"

namespace sarloc::app {

void add_log_level_option(CLI::App& cli, std::string& level) {
  cli.add_option("--log-level", level, "trace, debug, info, warn, error, critical, off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}))
      ->capture_default_str();
}

std::optional<int> parse_command_line(CLI::App& cli, int argc, char** argv) {
  try {
    cli.parse(argc, argv);
    return std::nullopt;
  } catch (const CLI::ParseError& e) {
    const int cli_code = cli.exit(e);  // prints help, the version or the error
    return cli_code == 0 ? to_int(ExitCode::kOk) : to_int(ExitCode::kUsage);
  }
}

}  // namespace sarloc::app
