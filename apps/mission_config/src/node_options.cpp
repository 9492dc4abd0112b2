#include "sarloc/app/node_options.hpp"

#include <CLI/CLI.hpp>
#include <filesystem>

#include "sarloc/app/command_line.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::app {

dds::ParticipantConfig participant_config(const MissionConfig& mission, int domain, const std::string& name,
                                          const std::string& identity) {
  require(domain >= -1 && domain <= 232, "--domain", domain, "must be in [0, 232] (absent: dds.domain_id)");
  dds::ParticipantConfig config = mission.dds;
  if (domain >= 0) config.domain_id = static_cast<std::uint32_t>(domain);
  config.name = name;
  config.core_node_ids = mission.core_node_ids();
  if (!mission.security_dir.empty()) {
    const auto profile = std::filesystem::path(mission.security_dir) / identity / "secure.xml";
    if (!std::filesystem::is_regular_file(profile)) {
      throw ConfigError("dds.security_dir = '" + mission.security_dir + "': no identity '" + identity + "' (" +
                        profile.string() + "); issue this mission's identities with make-certs.sh " +
                        mission.security_dir + " $(sarloc-mission --identities MISSION.yaml)");
    }
    config.profiles_file = profile.string();
    config.profile = "sarloc_secure";
    config.require_security = true;
  }
  return config;
}

void NodeOptions::validate() const {
  require(domain >= -1 && domain <= 232, "--domain", domain, "must be in [0, 232] (absent: dds.domain_id)");
  require(epoch_ns >= 0, "--epoch-ns", epoch_ns, "must be >= 0 (absent: now)");
  require(epoch_wall_ns >= 0, "--epoch-wall-ns", epoch_wall_ns, "must be >= 0 (absent: --epoch-ns)");
  require(speedup == 0.0 || (speedup >= 0.1 && speedup <= 100.0), "--speedup", speedup,
          "must be in [0.1, 100] (as mission.speedup)");
}

dds::ParticipantConfig NodeOptions::participant(const MissionConfig& mission, const std::string& name,
                                                const std::string& identity) const {
  validate();
  return participant_config(mission, domain, name, identity);
}

dds::MissionClock NodeOptions::clock(const MissionConfig& mission) const {
  validate();
  const TimestampNs epoch = epoch_ns > 0 ? epoch_ns : dds::MissionClock::wall_now_ns();
  return dds::MissionClock(epoch, speedup > 0.0 ? speedup : mission.speedup, epoch_wall_ns > 0 ? epoch_wall_ns : epoch);
}

void add_node_options(CLI::App& cli, NodeOptions& options, bool with_epoch) {
  cli.add_option("-c,--config", options.config_path, "mission YAML (config/missions/default.yaml)")->required();
  add_log_level_option(cli, options.log_level);
  cli.add_option("--domain", options.domain, "DDS domain id, overriding dds.domain_id of the config");
  if (with_epoch) {
    cli.add_option("--epoch-ns", options.epoch_ns,
                   "mission start, ns since the Unix epoch (sarloc-mission sets it; default: now)");
    cli.add_option("--epoch-wall-ns", options.epoch_wall_ns,
                   "wall time at which the mission clock reads --epoch-ns (a replay of a recording; default: --epoch-ns)");
    cli.add_option("--speedup", options.speedup, "mission seconds per wall second, overriding mission.speedup")
        ->check(CLI::PositiveNumber);
  }
  cli.set_version_flag("--version", SARLOC_VERSION);
}

}  // namespace sarloc::app
