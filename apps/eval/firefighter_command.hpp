#pragma once
// `sarloc-eval firefighter`: the map-aided firefighter localization of seed 004 on a building
// of config/buildings/, in the configurations of the paper's Figs. 7-8, with the map-error
// experiment of its section V-E. Prints the tables, writes JSON and the RMSE figure (SVG).
#include "sarloc/app/cli_app.hpp"
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace sarloc::eval {

struct FirefighterOptions {
  std::string building;
  std::string config_path;
  std::optional<std::uint32_t> runs;
  std::optional<std::uint64_t> seed;
  std::optional<std::uint32_t> threads;
  std::string json_path;
  std::string plot_path;
  std::string map_error_door;
  double map_error_shift_m = 2.0;
  std::vector<std::string> rows;  ///< row names or "default"; empty: all eight
  bool no_map_error = false;
  bool no_target_check = false;
};

CLI::App* add_firefighter_command(CLI::App& app, FirefighterOptions& options);
/// Returns a sarloc::app::ExitCode value.
int run_firefighter_command(const FirefighterOptions& options);

}  // namespace sarloc::eval
