#pragma once
// sarloc-mission's command line.
#include <CLI/CLI.hpp>

#include <map>
#include <string>
#include <vector>

namespace sarloc::app {

struct MissionOptions {
  std::string config_path;
  std::string json_path;
  std::string run_dir;
  std::string log_level = "info";
  std::vector<std::string> kills;
  std::vector<std::string> restarts;
  double startup_s = 3.0;
  int domain = -1;
  std::string launcher;
  std::vector<std::string> host_args;  ///< NAME=HOST
  std::string record_dir;
  bool no_record = false;
  bool dashboard = false;
  int dashboard_port = -1;
  bool identities = false;  ///< print the mission's DDS Security identities and exit

  /// "NAME=HOST" of each --host (CLI11 reads a map option as key/value token pairs, not as
  /// NAME=HOST); throws ConfigError.
  std::map<std::string, std::string> hosts() const;
};

void add_mission_options(CLI::App& cli, MissionOptions& options);

}  // namespace sarloc::app
