#pragma once
// sarloc-command's DDS node: incident command's one picture, published.
//
// The rules live in incident::IncidentCommand (core, no DDS): which estimates are fused and with
// which fix, teams, alarms, hot standby, re-disposal. This node has CoreNode's shape: listeners
// convert a sample to core types, check its writer (WriterAuthority) and enqueue it; one thread
// applies the queue to the core object and cycles it every cycle_s; the writers publish what
// the cycle returns.
//
// Inputs: every rescuer's VictimEstimate (all sectors), every responder's ResponderPosition
// (with its writer's liveliness: a crashed device is "link lost" within the lease; only a
// device's own writer stands for its link, not the core daemon's map-aided positions, whose
// writer serves many responders), devices' ResponderAlarm, operators' AlarmAcknowledgement and
// DigOrder, and VictimRecovery from operators or finders. The picture is published TRANSIENT_LOCAL (FusedVictim per
// victim, TeamStatus per team, IncidentAlarm, IncidentSummary, IncidentFrame), so a dashboard that subscribes late has
// it at once.
//
// Hot standby (docs/operations.md): an incident runs `standby.instances` of these. The picture
// topics are OWNERSHIP EXCLUSIVE, so a standby's picture readers deliver the active one's
// samples only; the core object adopts them. The active one's summary writer losing its
// liveliness (3 s lease, asserted every cycle) wakes the cycle at once, and the standby takes
// over with the same victim ids. The active one raises its picture writers' ownership strength
// (set_qos) so that an instance activating later ranks below it.
#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "sarloc/core/incident/incident_command.hpp"
#include "sarloc/dds/mission_clock.hpp"
#include "sarloc/dds/participant.hpp"
#include "sarloc/dds/rate_limited_log.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/reject_counters.hpp"
#include "sarloc/dds/speaker_claim.hpp"
#include "sarloc/dds/writer.hpp"
#include "sarloc/dds/writer_authority.hpp"

namespace sarloc::dds {

struct CommandNodeConfig {
  std::string node_id = "sarloc-command";
  /// The rules' settings (incident, fusion, teams, fixes, standby).
  incident::IncidentCommandConfig incident;
  /// Partitions to read estimates from: {"*"} when sectors split the incident, empty otherwise.
  std::vector<std::string> estimate_partitions;
  double cycle_s = 1.0;  ///< wall period of fusion and publication (the standby's peer period)

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
  using Input = std::function<void(incident::IncidentCommand&)>;
  /// Inputs waiting for the next cycle; beyond this many a sample is refused (counted), which
  /// no incident reaches (500 responders send a few thousand a second).
  static constexpr std::size_t kInboxLimit = 65536;

  void create_input_readers();
  void create_picture_readers();
  void enqueue(const std::string& subject, Input input);
  void cycle();
  void publish(const incident::CommandCycle& out);
  /// Ownership strength of the picture writers.
  void apply(const incident::RoleChange& change);
  void log(const incident::CommandCycle& out);
  /// Keeps the picture writers' MANUAL_BY_TOPIC liveliness (3 s lease) while active.
  void assert_picture_liveliness();
  /// False (counted and logged as unauthorized_writer) when `writer` may not write a sample
  /// making `claim` (WriterAuthority).
  bool admitted(const eprosima::fastrtps::rtps::InstanceHandle_t& writer, const SpeakerClaim& claim);
  void refuse_invalid(const std::string& subject, const std::string& what);

  CommandNodeConfig config_;
  MissionClock clock_;
  std::shared_ptr<Participant> participant_;
  WriterAuthority authority_;  ///< with DDS Security: who may write about which responder
  RateLimitedLog warnings_;
  RejectCounters counters_;

  std::mutex inbox_mutex_;
  std::vector<Input> inbox_;
  mutable std::mutex mutex_;  ///< the core object: the cycle thread and the queries
  incident::IncidentCommand command_;

  Writer<::sarloc::FusedVictim> victim_writer_;
  Writer<::sarloc::TeamStatus> team_writer_;
  Writer<::sarloc::IncidentSummary> summary_writer_;
  Writer<::sarloc::IncidentFrame> frame_writer_;
  Writer<::sarloc::SearchPlan> plan_writer_;
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
  std::unique_ptr<Reader<::sarloc::SearchPlan>> picture_plan_reader_;
  std::unique_ptr<Reader<::sarloc::IncidentAlarm>> picture_alarm_reader_;
  std::unique_ptr<Reader<::sarloc::ResponderAlarm>> responder_alarm_reader_;
  std::unique_ptr<Reader<::sarloc::AlarmAcknowledgement>> acknowledgement_reader_;
  std::unique_ptr<Reader<::sarloc::VictimRecovery>> recovery_reader_;
  std::unique_ptr<Reader<::sarloc::DigOrder>> dig_order_reader_;
  std::unique_ptr<Reader<::sarloc::DepositDrawing>> deposit_reader_;
};

}  // namespace sarloc::dds
