#pragma once
// The command-line options every DDS node shares (sarloc-core, sarloc-rescuer, sarloc-command):
// the mission file, the log level, a DDS domain override and the mission epoch.
//
//   NodeOptions options;
//   add_node_options(cli, options);
//   ... auto participant = std::make_shared<dds::Participant>(options.participant(mission, "name", identity));
#include "sarloc/app/cli_app.hpp"

#include <cstdint>
#include <string>

#include "sarloc/app/mission_config.hpp"
#include "sarloc/dds/mission_clock.hpp"

namespace sarloc::app {

struct NodeOptions {
  std::string config_path;
  std::string log_level = "info";
  int domain = -1;            ///< < 0: the mission file's dds.domain_id
  std::int64_t epoch_ns = 0;  ///< 0: now
  /// Wall time at which the mission clock reads epoch_ns (0: epoch_ns itself). sarloc-replay
  /// sets it to run fresh nodes on a recorded mission's timeline.
  std::int64_t epoch_wall_ns = 0;
  double speedup = 0.0;       ///< 0: the mission file's

  /// Throws ConfigError naming the option ("--domain = 300: must be in [0, 232] ...").
  /// participant() and clock() check it first.
  void validate() const;
  /// The mission's participant settings with this node's name and the domain override;
  /// `identity` is the node's DDS Security identity (participant_config).
  dds::ParticipantConfig participant(const MissionConfig& mission, const std::string& name,
                                     const std::string& identity) const;
  /// The mission clock from --epoch-ns (default: starting now) and the mission's speedup.
  dds::MissionClock clock(const MissionConfig& mission) const;
};

/// Adds -c/--config (required), --log-level, --domain, --version and, for nodes that follow
/// the mission clock (`with_epoch`), --epoch-ns, --epoch-wall-ns and --speedup.
void add_node_options(CLI::App& cli, NodeOptions& options, bool with_epoch = true);

/// The mission's participant settings named `name`, on `domain` if >= 0 (else dds.domain_id).
/// With dds.security_dir, the node loads `identity`'s profile from it (a device's identity is
/// its responder id, a core daemon's or incident command's its node id, otherwise
/// kDashboardIdentity and the like) and requires DDS Security; ConfigError, naming the
/// make-certs.sh call that issues it, when that identity was not issued.
dds::ParticipantConfig participant_config(const MissionConfig& mission, int domain, const std::string& name,
                                          const std::string& identity);

}  // namespace sarloc::app
