#pragma once
// sarloc-mission's processes: the recorder, the dashboard, the core daemon(s) (one per sector),
// the incident-command instances and one sarloc-rescuer per device (avalanche rescuer or
// firefighter: one block for every role). Each is started with the mission's file, domain,
// epoch and log level, logs to <run dir>/<name>.log, and runs here or, when --host places it,
// through the launcher on that host. Stopped in the order that loses nothing: devices first
// (they write their summaries and sign off), then the standby instances, the active one, the
// daemons, the dashboard, and the recorder last (it writes its file's summary when it stops).
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "sarloc/app/child_process.hpp"
#include "sarloc/app/mission_config.hpp"

namespace sarloc::app {

/// The run folder's file of the simulated devices' shared world (apps/rescuer/simulated_world.hpp).
inline constexpr const char* kSimWorldFile = "sim-world.txt";

struct ProcessTableConfig {
  std::filesystem::path bin_dir;  ///< where sarloc-core, sarloc-rescuer, ... are
  std::string mission_file;       ///< absolute
  std::filesystem::path run_dir;
  int domain_id = 0;
  TimestampNs epoch_ns = 0;
  std::string log_level = "info";
  std::string launcher;                        ///< LAUNCHER HOST PROGRAM ARGS...
  std::map<std::string, std::string> hosts;    ///< process name -> host (--host NAME=HOST)
};

class ProcessTable {
 public:
  /// Throws ConfigError for a --host without --launcher, or naming no process of the mission.
  ProcessTable(const MissionConfig& mission, ProcessTableConfig config);
  ~ProcessTable();  // stops whatever still runs

  /// The names --host may place: core (core-SECTOR), command (command-K), rescuer-ID.
  static std::set<std::string> placeable_names(const MissionConfig& mission);
  /// The programs a mission starts (the dashboard only with `dashboard`).
  static std::vector<std::string> programs(bool dashboard);

  std::string log_file(const std::string& name) const;

  void start_recorder(const std::string& recording_path);
  /// Started, and its URL (and the Foxglove feed's) printed once it writes them; port < 0:
  /// the mission's own, 0: any free ports.
  void start_dashboard(int port);
  void start_cores(const std::string& suffix = "");
  void start_command(unsigned instance, const std::string& suffix = "");
  void start_devices();

  void kill_cores();
  void kill_command(unsigned instance);
  void kill_device(const std::string& id);

  std::string command_name(unsigned instance) const;
  bool command_killed(unsigned instance) const { return command_killed_.at(instance - 1); }
  bool device_running(const std::string& id) { return devices_.at(id)->running(); }
  bool any_command_running();
  /// Instances that exited without being killed (logged with their exit code).
  bool a_command_failed();

  /// Stops the devices; returns those that were running until now (stopped in order).
  std::vector<std::string> stop_devices();
  /// The incident-command instances, `active` (0: none) last; then the daemons, the dashboard
  /// and the recorder. False when the recorder did not end cleanly.
  bool stop_the_rest(unsigned active);

 private:
  std::unique_ptr<ChildProcess> start(const std::string& name, const std::string& placed_as,
                                      std::vector<std::string> args);
  std::vector<std::string> common_args(const std::string& program) const;

  const MissionConfig& mission_;
  ProcessTableConfig config_;
  std::unique_ptr<ChildProcess> recorder_, dashboard_;
  std::vector<std::unique_ptr<ChildProcess>> cores_, commands_;
  std::vector<bool> command_killed_;
  std::map<std::string, std::unique_ptr<ChildProcess>> devices_;
};

}  // namespace sarloc::app
