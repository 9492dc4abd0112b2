#pragma once
// One YAML file describes a whole (simulated) mission; every process of it reads the same
// file and takes its own part: sarloc-core its sector, sarloc-rescuer its rescuer,
// sarloc-command the incident, sarloc-mission all of it. docs/configuration.md lists the keys;
// config/missions/default.yaml is the annotated default.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sarloc/app/dashboard_config.hpp"
#include "sarloc/core/estimator/make_estimator.hpp"
#include "sarloc/core/incident/deposit.hpp"
#include "sarloc/core/incident/sector_areas.hpp"
#include "sarloc/core/mission/mission_scenario.hpp"
#include "sarloc/core/mission/simulated_firefighter.hpp"
#include "sarloc/dds/command_node.hpp"
#include "sarloc/dds/core_node.hpp"
#include "sarloc/dds/participant.hpp"
#include "sarloc/dds/recorder.hpp"
#include "sarloc/dds/rescuer_node.hpp"

namespace sarloc::app {

/// A firefighter of the mission (rescuers[] with role firefighter): its team and, simulated,
/// its part in a directional search of the building.
struct FirefighterEntry {
  std::string id;
  std::string team;
  mission::FirefighterSpec spec;
  /// A recorded boot IMU file the device plays instead of the simulated walk ("" = simulated),
  /// and its IMU source description (config/imu/*.yaml; "" = the sarloc boot IMU CSV), both
  /// resolved against the mission file's folder.
  std::string recording;
  std::string imu_source;
};

/// The DDS Security identities of the nodes that are neither a responder's device, a core
/// daemon nor incident command (those are named by their ids).
inline constexpr const char* kDashboardIdentity = "dashboard";
inline constexpr const char* kRecorderIdentity = "recorder";
inline constexpr const char* kMissionIdentity = "mission";  ///< sarloc-mission's picture watcher
/// core.handover_journal_entries when a sector has an area and the file does not set it: about
/// an hour of a rescuer's search at 1 Hz.
inline constexpr std::size_t kHandoverJournalWithAreas = 8192;

struct MissionConfig {
  std::string name = "mission";
  double time_limit_s = 900.0;  ///< mission seconds before sarloc-mission gives up
  double speedup = 1.0;         ///< mission seconds per wall second (1 = real time)
  double period_s = 1.0;        ///< one measurement epoch per mission second (seed 000, section V)

  dds::ParticipantConfig dds;
  /// dds.security_dir, resolved ("" = none): an incident's DDS Security material from
  /// deploy/security/make-certs.sh. Each node then loads its own identity's profile,
  /// <dir>/<identity>/secure.xml (participant_config), and refuses to run unauthenticated.
  std::string security_dir;
  mission::MissionScenario scenario;                  ///< victims, rescuers, sensors
  std::map<std::string, std::string> sector_of;       ///< rescuer id -> sector name ("" = none)
  std::map<std::string, estimator::ResponderRole> role_of;  ///< rescuer id -> role (rescuers[].role)
  std::vector<std::string> sectors;                   ///< one sarloc-core per sector (none: one core)
  /// sectors[].area (WGS-84 in the file), in the incident frame, and rescuer.sector_margin_m:
  /// a device moves to the sector whose area it walks into (empty: devices stay in their sector).
  incident::SectorAreas sector_areas;
  estimator::EstimatorConfigs estimators;             ///< every role's estimator (sog:, search:, rescuer_search:, building:, firefighter:)
  std::string building_path;                          ///< building.plan, resolved ("" = no building)
  /// The building as it is (the simulated world); the daemon's map (estimators.firefighter.
  /// building) differs by building.map_error, if any.
  std::shared_ptr<const firefighter::FloorPlan> world;
  std::string map_error_door;                         ///< building.map_error.door ("" = none)
  double map_error_shift_m = 0.0;                     ///< as applied (clamped to the wall)
  std::vector<FirefighterEntry> firefighters;         ///< rescuers[] with role firefighter
  /// The avalanche deposit (incident.deposit, WGS-84 in the file), in the incident frame.
  std::optional<incident::Deposit> deposit;
  dds::CoreNodeConfig core;
  dds::RescuerNodeConfig rescuer;                     ///< template: id/team/partitions filled per rescuer
  /// Two instances of incident command unless the file says otherwise (command.instances):
  /// one publishes the picture, the other stands by (docs/operations.md).
  dds::CommandNodeConfig command = [] {
    dds::CommandNodeConfig c;
    c.incident.standby.instances = 2;
    return c;
  }();

  /// How sarloc-record records this mission (record:); output_path is set per run.
  dds::RecorderConfig record;
  std::string record_directory = "recordings";  ///< record.directory, resolved
  /// sarloc-dashboard (dashboard:).
  DashboardConfig dashboard;

  /// Throws ConfigError naming the key.
  void validate() const;

  /// The DDS partition of a sector ("sector-<name>"), or {} for no sector.
  static std::vector<std::string> partitions_of_sector(const std::string& sector);
  dds::CoreNodeConfig core_config(const std::string& sector) const;
  /// The node id of the core daemon of `sector` ("" without sectors), and of every one.
  std::string core_node_id(const std::string& sector) const;
  std::vector<std::string> core_node_ids() const;
  /// The DDS Security identities this mission's nodes load, as make-certs.sh takes them
  /// ("role:name"; a device's name is its responder id): every core daemon, every incident
  /// command instance, every responder's device, the dashboard, the recorder and
  /// sarloc-mission's own watcher.
  std::vector<std::string> security_identities() const;
  dds::RescuerNodeConfig rescuer_config(const std::string& rescuer_id) const;
  /// The team of any responder (avalanche rescuer or firefighter); ConfigError when unknown.
  std::string team_of(const std::string& responder_id) const;
  /// The firefighter with this id, nullptr if it is none.
  const FirefighterEntry* firefighter(const std::string& responder_id) const;
  /// Incident command instance `instance` (1..command.standby.instances): with more than one,
  /// its node id gets "-<instance>" (NodeStatus keys must differ).
  dds::CommandNodeConfig command_config(unsigned instance = 1) const;
  /// How many sarloc-command processes the incident runs (command.instances).
  unsigned command_instances() const { return command.incident.standby.instances; }
};

/// Loads and validates a mission file (relative DDS file paths resolve against its folder).
MissionConfig load_mission_config(const std::string& path);
MissionConfig load_mission_config_text(const std::string& text, const std::string& name,
                                       const std::string& base_dir = ".");

}  // namespace sarloc::app
