#pragma once
// sarloc-command's DDS node: incident command's one picture.
//
// Inputs: every rescuer's VictimEstimate (all sectors), every responder's ResponderPosition
// (with its writer's liveliness: a crashed device is "link lost" within the lease).
// Each cycle: estimates are moved into the incident frame with the rescuer's fix nearest in
// time, associated and fused (incident::VictimFusion), teams evaluated (incident::TeamTracker),
// and the picture published TRANSIENT_LOCAL (FusedVictim per victim, TeamStatus per team,
// IncidentSummary, IncidentFrame), so a dashboard that subscribes late has it at once.
#include <atomic>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

#include "sarloc/core/incident/responder_track.hpp"
#include "sarloc/core/incident/team_tracker.hpp"
#include "sarloc/core/incident/victim_fusion.hpp"
#include "sarloc/dds/mission_clock.hpp"
#include "sarloc/dds/participant.hpp"
#include "sarloc/dds/rate_limited_log.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/reject_counters.hpp"
#include "sarloc/dds/writer.hpp"

namespace sarloc::dds {

struct CommandNodeConfig {
  std::string node_id = "sarloc-command";
  std::string incident_id = "incident";
  std::string incident_name;
  GeodeticOrigin origin;
  incident::VictimFusionConfig fusion;
  incident::TeamTrackerConfig teams;
  /// Partitions to read estimates from: {"*"} when sectors split the incident, empty otherwise.
  std::vector<std::string> estimate_partitions;
  double cycle_s = 1.0;              ///< wall period of fusion and publication
  /// A fix further than this (mission s) from an estimate's stamp is not used: a rescuer walks
  /// 1 m/s, so pairing an estimate with an older fix misplaces the victim by as much (measured:
  /// 3.2 m under 20 % UDP loss with 5 s). Rescuers stamp their fix with the epoch's stamp, so
  /// the matching fix is normally exact.
  double position_max_age_s = 0.5;
  /// An estimate whose matching fix has not arrived yet waits for it this long (mission s).
  double fix_wait_s = 5.0;
  /// Without a fix within position_max_age_s, the fixes just before and after the stamp are
  /// interpolated if at most this far apart (mission s): under packet loss the epoch's own fix
  /// can be lost for good (only the newest ResponderPosition is kept).
  double fix_interpolation_max_gap_s = 2.5;
  /// Heights outdoors are above the local snow surface (what diggers need), not GNSS altitude
  /// (poor, and irrelevant to a burial depth): a GNSS fix's height is replaced by the receiver
  /// antenna's height above the snow, with this 1-sigma (m). Other positions (map-aided
  /// indoors) keep their height and floor (incident::reporter_fix_of).
  double antenna_height_m = 1.0;
  double antenna_height_sigma_m = 0.15;

  /// Throws ConfigError naming the key ("command.cycle_s = 0: must be in (0, 60]").
  void validate() const;
};

class CommandNode {
 public:
  CommandNode(std::shared_ptr<Participant> participant, CommandNodeConfig config, MissionClock clock);
  ~CommandNode();
  CommandNode(const CommandNode&) = delete;
  CommandNode& operator=(const CommandNode&) = delete;

  /// A copy of the current picture (thread-safe).
  std::vector<incident::FusedVictim> victims() const;
  std::vector<incident::TeamStatus> teams() const;

 private:
  void cycle();
  std::optional<incident::ReporterFix> fix_at(const std::string& rescuer_id, TimestampNs stamp) const;

  CommandNodeConfig config_;
  MissionClock clock_;
  std::shared_ptr<Participant> participant_;
  RateLimitedLog warnings_;
  RejectCounters counters_;

  mutable std::mutex mutex_;
  incident::VictimFusion fusion_;
  incident::TeamTracker tracker_;
  struct PendingEstimate {
    responder::VictimEstimate estimate;
    std::string writer;  ///< the DDS writer's GUID: which estimator
    bool from_device = false;
  };
  std::deque<PendingEstimate> pending_estimates_;
  std::map<std::string, incident::ResponderTrack> fixes_;  ///< per responder
  std::vector<std::pair<eprosima::fastrtps::rtps::InstanceHandle_t, std::string>> writer_owner_;
  std::vector<incident::TeamStatus> last_teams_;

  Writer<::sarloc::FusedVictim> victim_writer_;
  Writer<::sarloc::TeamStatus> team_writer_;
  Writer<::sarloc::IncidentSummary> summary_writer_;
  Writer<::sarloc::IncidentFrame> frame_writer_;
  Writer<::sarloc::NodeStatus> status_writer_;
  std::atomic<bool> stopping_{false};
  std::thread thread_;
  std::unique_ptr<Reader<::sarloc::VictimEstimate>> estimate_reader_;
  std::unique_ptr<Reader<::sarloc::ResponderPosition>> position_reader_;
};

}  // namespace sarloc::dds
