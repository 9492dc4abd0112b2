#include "mission_options.hpp"

#include "sarloc/app/command_line.hpp"
#include "sarloc/app/shipped_missions.hpp"
#include "sarloc/core/common/errors.hpp"

namespace sarloc::app {

std::map<std::string, std::string> MissionOptions::hosts() const {
  std::map<std::string, std::string> hosts;
  for (const auto& item : host_args) {
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0) throw ConfigError("--host " + item + ": expected NAME=HOST");
    hosts[item.substr(0, eq)] = item.substr(eq + 1);
  }
  return hosts;
}

void add_mission_options(CLI::App& cli, MissionOptions& o) {
  o.config_path = shipped_mission("default.yaml");
  cli.add_option("mission", o.config_path, std::string("mission YAML (default: default.yaml in ") + kShippedMissionsHelp + ")");
  cli.add_option("--json", o.json_path, "write the summary as JSON here");
  cli.add_option("--run-dir", o.run_dir, "folder for the processes' logs and summaries (default: a new one in /tmp)");
  cli.add_option("--restart", o.restarts,
                 "start again what a --kill stopped (core: the daemon(s); command: the killed instance, which "
                 "rejoins as standby) at mission SECONDS, e.g. core@25");
  cli.add_option("--kill", o.kills,
                 "fault injection: SIGKILL TARGET (core, command = the active incident command, or a rescuer id) "
                 "at mission SECONDS, e.g. core@40");
  cli.add_option("--startup", o.startup_s, "wall seconds given to the processes to start and discover each other");
  cli.add_option("--domain", o.domain, "DDS domain id for every process, overriding dds.domain_id of the mission");
  cli.add_option("--launcher", o.launcher,
                 "command that runs a process on another host as LAUNCHER HOST PROGRAM ARGS... (e.g. lan-exec of "
                 "../shared/tools/lan; scripts/lan-mission)");
  cli.add_option("--host", o.host_args,
                 "run process NAME on HOST through --launcher: NAME is core (core-SECTOR), command (command-K with "
                 "several instances) or rescuer-ID, e.g. --host rescuer-r1=h5")
      ->delimiter(',');
  cli.add_option("--record", o.record_dir,
                 "folder for the mission's MCAP recording (default: record.directory of the mission, recordings/)");
  cli.add_flag("--no-record", o.no_record, "do not record the mission");
  cli.add_flag("--dashboard", o.dashboard, "also start sarloc-dashboard on the mission and print its URL");
  cli.add_option("--dashboard-port", o.dashboard_port,
                 "the dashboard's port (default: dashboard.port of the mission; 0: any)");
  cli.add_flag("--identities", o.identities,
               "print the DDS Security identities the mission's nodes load from dds.security_dir, one ROLE:NAME "
               "a line, and exit: make-certs.sh DIR $(sarloc-mission --identities MISSION.yaml) issues them");
  add_log_level_option(cli, o.log_level);
  cli.set_version_flag("--version", SARLOC_VERSION);
}

}  // namespace sarloc::app
