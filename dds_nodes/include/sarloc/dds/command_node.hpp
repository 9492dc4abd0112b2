#pragma once
// sarloc-command's DDS node: incident command's one picture.
//
// Inputs: every rescuer's VictimEstimate (all sectors), every responder's ResponderPosition
// (with its writer's liveliness: a crashed device is "link lost" within the lease; only a
// device's own writer stands for its link, not the core daemon's map-aided positions, whose
// writer serves many responders), devices' ResponderAlarm, operators' AlarmAcknowledgement.
// Alarms (incident::AlarmBoard) are published as IncidentAlarm until acknowledged and cleared.
// Each cycle: estimates are moved into the incident frame with the rescuer's fix nearest in
// time, associated and fused (incident::VictimFusion), teams evaluated (incident::TeamTracker),
// and the picture published TRANSIENT_LOCAL (FusedVictim per victim, TeamStatus per team,
// IncidentSummary, IncidentFrame), so a dashboard that subscribes late has it at once.
//
// Hot standby (docs/operations.md): an incident runs `standby.instances` of these. Each one
// reads the inputs and places every estimate, but only the active one fuses and publishes;
// a standby reads the picture (the topics are OWNERSHIP EXCLUSIVE, so its readers deliver the
// active one's samples only), adopts each new one (VictimFusion::adopt, TeamTracker::adopt)
// and fuses on top of it as the active one would, without publishing. incident::StandbyArbiter decides the role: the active one's summary
// writer losing its liveliness (3 s lease, asserted every cycle) makes the standby active at
// once, with the same victim ids, states and timestamps. The active one raises its picture
// writers' ownership strength (set_qos) so that an instance activating later ranks below it.
#include <atomic>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

#include <optional>

#include "sarloc/core/incident/alarm_board.hpp"
#include "sarloc/core/incident/responder_track.hpp"
#include "sarloc/core/incident/standby_arbiter.hpp"
#include "sarloc/core/incident/team_tracker.hpp"
#include "sarloc/core/incident/victim_fusion.hpp"
#include "sarloc/dds/mission_clock.hpp"
#include "sarloc/dds/participant.hpp"
#include "sarloc/dds/rate_limited_log.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/reject_counters.hpp"
#include "sarloc/dds/writer.hpp"
#include "sarloc/dds/writer_authority.hpp"

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
  /// Hot standby: this instance's number, how many the incident runs (alone by default; a
  /// mission file runs two unless command.instances says otherwise), when to claim.
  incident::StandbyConfig standby;

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
  std::vector<incident::IncidentAlarm> alarms() const;
  /// Standby or active now (thread-safe).
  incident::CommandRole role() const;

  /// This instance stops in order: stops its cycle, then disposes its NodeStatus instance
  /// (sign_off.hpp). The destructor still hands the last picture over. Not on an error.
  bool sign_off(std::chrono::milliseconds timeout);

 private:
  void cycle();
  /// Ownership strength of the picture writers and the log line of a role change.
  void apply(const incident::RoleChange& change, std::size_t adopted_victims);
  /// The active one's picture (as received) into the fusion and the tracker; under mutex_.
  void adopt_picture();
  /// On taking over: the ids up to the largest seen that the picture no longer holds, disposed
  /// again, since a reader may have missed a predecessor's disposal during a fade.
  std::vector<std::uint32_t> retired_ids(const std::vector<incident::FusedVictim>& victims,
                                         const std::vector<std::uint32_t>& removed) const;
  /// The event log's line for a signal that a rescuer's separation reacquired or separated
  /// after a merge (its victim's contribution went through it), once per event, and for a
  /// signal's repeat state (one transmitter split in two) as its device says it, once per
  /// change. Under mutex_.
  void log_separation_event(const responder::VictimEstimate& estimate, bool from_device);
  /// Keeps the picture writers' MANUAL_BY_TOPIC liveliness (3 s lease) while active.
  void assert_picture_liveliness();
  /// False (counted and logged as unauthorized_writer) when `writer` may not write `what`
  /// about `responder_id` (WriterAuthority).
  bool admitted(const eprosima::fastrtps::rtps::InstanceHandle_t& writer, const std::string& responder_id,
                WriterAuthority::Speakers speakers, const char* what);
  std::optional<incident::ReporterFix> fix_at(const std::string& rescuer_id, TimestampNs stamp) const;
  /// The fix that places `e`: the one it carries if of its epoch, else fix_at (under mutex_).
  std::optional<incident::ReporterFix> fix_for(const responder::VictimEstimate& e) const;

  CommandNodeConfig config_;
  MissionClock clock_;
  std::shared_ptr<Participant> participant_;
  WriterAuthority authority_;  ///< with DDS Security: who may write about which responder
  RateLimitedLog warnings_;
  RejectCounters counters_;

  mutable std::mutex mutex_;
  incident::VictimFusion fusion_;
  incident::TeamTracker tracker_;
  /// Alarms until acknowledged: devices' (motionless, mayday) and this node's (link lost and
  /// map error, from the team tracker's members each cycle).
  incident::AlarmBoard alarm_board_;
  std::map<std::uint32_t, incident::IncidentAlarm> adopted_alarms_;  ///< the active one's, while standby
  struct PendingEstimate {
    responder::VictimEstimate estimate;
    std::string writer;  ///< the DDS writer's GUID: which estimator
    bool from_device = false;
    TimestampNs arrived = 0;  ///< mission time it arrived: it waits fix_wait_s from then for its fix
  };
  std::deque<PendingEstimate> pending_estimates_;
  /// Per (rescuer, signal): the stamp of the last signal-separation event logged.
  std::map<std::pair<std::string, std::uint32_t>, TimestampNs> separation_events_logged_;
  std::map<std::pair<std::string, std::uint32_t>, responder::RepeatState> repeats_logged_;
  std::map<std::string, incident::ResponderTrack> fixes_;  ///< per responder
  std::vector<std::pair<eprosima::fastrtps::rtps::InstanceHandle_t, std::string>> writer_owner_;
  std::vector<incident::TeamStatus> last_teams_;
  incident::StandbyArbiter arbiter_;
  // The active instance's picture as this instance's readers receive it (while standby).
  std::map<std::uint32_t, incident::FusedVictim> adopted_victims_;
  std::map<std::string, incident::TeamStatus> adopted_teams_;
  std::optional<::sarloc::IncidentFrame> adopted_frame_;
  bool fresh_picture_ = false;         ///< a summary of the active one arrived since the last adoption
  /// A reader takes a new active instance's disposal only once it counts the predecessor lost:
  /// up to the picture writers' 3 s lease after this instance took over on its silence. So the
  /// retired ids are disposed again every cycle for a while longer than that.
  static constexpr TimestampNs kRedisposeWindowNs = 10'000'000'000;
  TimestampNs redispose_until_ = 0;  ///< wall clock
  std::uint32_t largest_id_seen_ = 0;  ///< victim ids published so far, disposed ones included
  ::sarloc::IncidentFrame frame_;      ///< what this instance publishes while active

  Writer<::sarloc::FusedVictim> victim_writer_;
  Writer<::sarloc::TeamStatus> team_writer_;
  Writer<::sarloc::IncidentSummary> summary_writer_;
  Writer<::sarloc::IncidentFrame> frame_writer_;
  Writer<::sarloc::IncidentAlarm> alarm_writer_;
  Writer<::sarloc::NodeStatus> status_writer_;
  std::atomic<bool> stopping_{false};
  std::atomic<bool> wake_{false};  ///< run the next cycle now (the active instance was lost)
  std::thread thread_;
  std::unique_ptr<Reader<::sarloc::VictimEstimate>> estimate_reader_;
  std::unique_ptr<Reader<::sarloc::ResponderPosition>> position_reader_;
  std::unique_ptr<Reader<::sarloc::ResponderPosition>> device_position_reader_;  ///< MANUAL_BY_TOPIC: devices' own writers
  std::unique_ptr<Reader<::sarloc::IncidentSummary>> summary_reader_;
  std::unique_ptr<Reader<::sarloc::FusedVictim>> picture_victim_reader_;
  std::unique_ptr<Reader<::sarloc::TeamStatus>> picture_team_reader_;
  std::unique_ptr<Reader<::sarloc::IncidentFrame>> picture_frame_reader_;
  std::unique_ptr<Reader<::sarloc::IncidentAlarm>> picture_alarm_reader_;
  std::unique_ptr<Reader<::sarloc::ResponderAlarm>> responder_alarm_reader_;
  std::unique_ptr<Reader<::sarloc::AlarmAcknowledgement>> acknowledgement_reader_;
};

}  // namespace sarloc::dds
