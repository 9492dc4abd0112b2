#pragma once
// Incident command's rules, without DDS: one picture of the incident from every rescuer's
// victim estimates, every responder's positions and alarms, and the operators' acknowledgements.
//
// Inputs arrive in any order (on_*), each with the mission time it arrived; cycle() applies the
// rules and returns what changed. The rules, each with its unit test
// (tests/unit/incident/incident_command_*_test.cpp):
//   - only converged estimates are fused (a multimodal mean means nothing);
//   - an estimate is placed with its rescuer's fix of the same epoch (the one it carries, else
//     ResponderTrack::at); without one it waits up to fix_wait_s from its arrival, then is
//     dropped;
//   - victim fusion (VictimFusion), teams (TeamTracker), alarms until acknowledged (AlarmBoard):
//     link lost and map error are conditions this object raises from the team members;
//   - a device's own position writer stands for its link: its liveliness lost means link lost,
//     its disposal means signed off (a map-aided writer serves many responders: it stands for
//     none);
//   - hot standby (StandbyArbiter): a standby adopts each new picture of the active instance
//     (on_peer_*), fuses on top of it without publishing, and takes over with the same ids;
//     acknowledgements go to the active instance only;
//   - with a deposit, the primary search is planned (SearchPlanner) from avalanche rescuers'
//     GNSS fixes; a rescuer whose link is lost or who signed off gives its strip back; of the
//     rescuers who hear a victim, the nearest is sent (SignalPursuits); a standby takes the
//     active one's assignments and pursuits;
//   - an operator's dig order holds until the FOUND victims change (then the plan's own);
//   - a FOUND victim reported dug out (an operator, the finder's device) stays as recovered, its
//     signal expected no more;
//   - on taking over, every victim id up to the largest seen that the picture no longer holds
//     is disposed again for kRedisposeWindowNs (a reader may have missed a predecessor's
//     disposal during a fade).
//
//   IncidentCommand command(config, wall_now);
//   command.on_position(position, writer, now);          // listener thread: enqueue, then here
//   command.on_estimate(estimate, writer, from_device, now);
//   const CommandCycle out = command.cycle(now, wall_now);
//   if (out.active) publish(out.victims, out.disposed_victims, out.teams, out.alarms, ...);
//
// Not thread-safe: the DDS node (dds::CommandNode) calls it from its cycle thread only.
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "sarloc/core/incident/alarm_board.hpp"
#include "sarloc/core/incident/incident_frame.hpp"
#include "sarloc/core/incident/responder_track.hpp"
#include "sarloc/core/incident/search_plan.hpp"
#include "sarloc/core/incident/standby_arbiter.hpp"
#include "sarloc/core/incident/team_tracker.hpp"
#include "sarloc/core/incident/victim_digs.hpp"
#include "sarloc/core/incident/victim_fusion.hpp"
#include "sarloc/core/responder/victim_estimate.hpp"

namespace sarloc::incident {

/// ConfigError naming `key` for a deposit of more than kDepositVerticesMax vertices or one that
/// takes more than kSearchStripsMax strips at the configured width.
void check_deposit_fits(const Deposit& deposit, const SearchPlanConfig& search_plan, const std::string& key);

struct IncidentCommandConfig {
  std::string incident_id = "incident";
  std::string incident_name;
  GeodeticOrigin origin;
  VictimFusionConfig fusion;
  TeamTrackerConfig teams;
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
  /// indoors) keep their height and floor (reporter_fix_of).
  double antenna_height_m = 1.0;
  double antenna_height_sigma_m = 0.15;
  /// Hot standby: this instance's number, how many the incident runs, when to claim, and the
  /// active one's summary period (the node's cycle).
  StandbyConfig standby;
  /// The avalanche deposit (incident.deposit): with one, incident command plans the primary
  /// search over it (SearchPlanner) and publishes the plan. At most kDepositVerticesMax vertices.
  std::optional<Deposit> deposit;
  SearchPlanConfig search_plan;
  /// triage: the survival curve and dig time of the dig order (victim_digs.hpp), and the
  /// minutes the victims were buried before incident command's first cycle.
  TriageConfig triage;
  static constexpr std::size_t kDepositVerticesMax = 250;  ///< a strip's piece has a few more (IDL: 256)

  /// Throws ConfigError naming the key ("command.fix_wait_s = 0: must be in (0, 600]").
  void validate() const;
};

/// Something the commander's log should say, or an input refused (counted by reason).
struct IncidentEvent {
  enum class Kind : std::uint8_t { kDebug, kInfo, kWarning, kError, kRejected };
  Kind kind = Kind::kInfo;
  std::string text;
  std::string subject;  ///< kRejected: who sent it (one warning per subject and reason)
  std::string reason;   ///< kRejected: "invalid_value", "unknown_alarm"
};

/// The counts of IncidentSummary.
struct IncidentCounts {
  std::uint32_t victims_total = 0;
  std::uint32_t victims_located = 0;  ///< not unconfirmed
  std::uint32_t victims_found = 0;    ///< found or recovered
  std::uint32_t responders_total = 0;
  std::uint32_t responders_link_lost = 0;
};

/// What one cycle changed: the whole picture to publish while active (publication is
/// idempotent: every reader keeps the newest sample per instance).
struct CommandCycle {
  TimestampNs stamp = 0;                  ///< the cycle's mission time
  std::optional<RoleChange> role_change;  ///< apply its strength before publishing
  bool active = false;                    ///< false: publish nothing
  std::vector<FusedVictim> victims;
  std::vector<std::uint32_t> disposed_victims;  ///< merged away now, or retired ids re-disposed
  std::vector<TeamStatus> teams;
  std::vector<IncidentAlarm> alarms;
  std::vector<std::uint32_t> disposed_alarms;
  IncidentCounts counts;
  IncidentFrame frame;
  std::optional<SearchPlanPicture> search_plan;  ///< with a deposit
  std::size_t estimates_fused = 0;
  std::vector<IncidentEvent> events;  ///< in order, the inputs' since the last cycle first
};

class IncidentCommand {
 public:
  /// A reader takes a new active instance's disposal only once it counts the predecessor lost:
  /// up to the picture writers' 3 s lease after this instance took over on its silence. So the
  /// retired ids are disposed again every cycle for a while longer than that (wall ns).
  static constexpr TimestampNs kRedisposeWindowNs = 10'000'000'000;

  /// Throws ConfigError (config.validate()).
  IncidentCommand(IncidentCommandConfig config, TimestampNs start_wall_ns);

  // --- inputs (mission time `now` of arrival; `writer` names the DDS writer) ---------------
  /// A rescuer's (or the core daemon's) victim estimate. `from_device`: the device's own.
  void on_estimate(responder::VictimEstimate estimate, std::string writer, bool from_device, TimestampNs now);
  /// A responder's position; refused (an event) when not finite. A writer that is not
  /// map-aided becomes the responder's link.
  void on_position(const responder::ResponderPosition& position, const std::string& writer, TimestampNs now);
  /// A position writer's liveliness changed: link lost or back for the responder it stands for.
  void on_writer_liveliness(const std::string& writer, bool alive, TimestampNs now);
  /// A position writer disposed of its instance: its responder signed off.
  void on_writer_disposed(const std::string& writer, TimestampNs now);
  void on_device_alarm(const responder::ResponderAlarm& alarm, TimestampNs now);
  /// An operator's acknowledgement of an alarm, made at `stamp` (the acknowledgement's), received
  /// at `now`.
  void on_acknowledgement(std::uint32_t alarm_id, const std::string& operator_id, TimestampNs stamp, TimestampNs now);
  /// An operator or the finder's device reports a FOUND victim dug out: it stays in the picture
  /// as kRecovered (VictimFusion::recover). Refused (an event, on the active instance) for an
  /// unknown victim, one not FOUND, or a reporter that is not an identifier. The dig happened at
  /// the report's `stamp`, never later than `now` (a reporter's clock ahead of ours, or 0).
  void on_recovery(std::uint32_t victim_id, const std::string& reported_by, TimestampNs stamp, TimestampNs now);
  /// An operator's dig order: these FOUND victims first, in this order. It holds until the
  /// FOUND victims change; then incident command's own order replaces it (the last writer wins;
  /// both are events). Refused (an event, changing nothing) when empty, with a repeated id, an
  /// unknown or not FOUND victim, or an operator id that is not an identifier. Another
  /// incident's is ignored.
  void on_dig_order(const std::string& incident_id, const std::vector<std::uint32_t>& victim_ids,
                    const std::string& operator_id);
  /// An operator's outline of the deposit (incident frame): the search is planned over it from
  /// now on, in place of the mission's. The plan starts again: strips cut afresh, the coverage
  /// so far not carried over (an outline is drawn when the search begins, or when the one it
  /// had was wrong). Refused (an event, changing nothing) for an outline that is not a simple
  /// polygon of 3 to kDepositVerticesMax finite vertices, one that takes more than
  /// kSearchStripsMax strips, or an operator id that is not an identifier. The same outline
  /// again changes nothing (TRANSIENT_LOCAL delivers it again to a restarted instance). Another
  /// incident's is ignored.
  void on_deposit_drawing(const std::string& incident_id, const std::vector<Vec2>& outline,
                          const std::string& operator_id);

  // --- the active instance's picture, as received (another instance's writers) ------------
  void on_peer_summary(const std::string& writer, TimestampNs wall_now);
  void on_peer_lost(const std::string& writer, TimestampNs wall_now);
  void on_peer_victim(FusedVictim victim);  ///< refused (an event) unless check_adoptable
  void on_peer_victim_disposed(std::uint32_t victim_id);
  void on_peer_team(TeamStatus team);
  void on_peer_alarm(IncidentAlarm alarm);
  void on_peer_alarm_disposed(std::uint32_t alarm_id);
  void on_peer_frame(const IncidentFrame& frame);  ///< another incident's is ignored
  /// The active one's search plan: a standby takes its assignments and pursuits (another
  /// incident's is ignored).
  void on_peer_search_plan(SearchPlanPicture plan);

  /// Role, estimates placed and fused, standby adoption, teams, alarms: see the file comment.
  CommandCycle cycle(TimestampNs now, TimestampNs wall_now);

  const std::vector<FusedVictim>& victims() const { return fusion_.victims(); }
  const std::vector<TeamStatus>& teams() const { return last_teams_; }  ///< as of the last cycle
  std::vector<IncidentAlarm> alarms() const { return alarm_board_.alarms(); }
  CommandRole role() const { return arbiter_.role(); }
  const IncidentCommandConfig& config() const { return config_; }
  /// The primary-search planner (with a deposit).
  const SearchPlanner* search_planner() const { return planner_ ? &*planner_ : nullptr; }
  /// Estimates waiting for their fix.
  std::size_t estimates_waiting() const { return pending_estimates_.size(); }

 private:
  struct PendingEstimate {
    responder::VictimEstimate estimate;
    std::string writer;  ///< which estimator
    bool from_device = false;
    TimestampNs arrived = 0;  ///< it waits fix_wait_s from then for its fix
  };

  void fuse_pending(TimestampNs now, CommandCycle& out);
  /// The fix that places `e`: the one it carries if of its epoch, else the track's.
  std::optional<ReporterFix> fix_for(const responder::VictimEstimate& e) const;
  /// The active one's picture (as received) into the fusion, the tracker and the board.
  void adopt_picture();
  void take_over(TimestampNs now);
  /// Ids up to the largest seen that neither the picture holds nor `removed` disposes now.
  std::vector<std::uint32_t> retired_ids(const std::vector<std::uint32_t>& removed) const;
  void raise_conditions(const std::vector<TeamStatus>& teams, TimestampNs now);
  /// Rescuers whose link is lost or who signed off search no more; the plan updated, with the
  /// signals handed over to each victim's one pursuer.
  std::optional<SearchPlanPicture> plan_search(const std::vector<TeamStatus>& teams,
                                               const std::vector<FusedVictim>& victims, TimestampNs now);
  /// Every rescuer's signal as last heard of (any status), for handing a transmitter to one
  /// rescuer before anyone has placed it (signal_groups.hpp).
  void note_heard(const responder::VictimEstimate& e, TimestampNs now);
  std::vector<HeardSignal> heard_signals(TimestampNs now);
  /// A signal's separation event and repeat state as the log should say them, once each.
  void note_separation_event(const responder::VictimEstimate& e, bool from_device);
  void say(IncidentEvent::Kind kind, std::string text);
  void reject(std::string subject, std::string reason, std::string text);

  IncidentCommandConfig config_;
  std::optional<SearchPlanner> planner_;
  bool planner_seeded_ = true;  ///< false: made since the last cycle, not yet told where everyone is
  /// The mission time the victims count as buried from (minus triage.buried_before_start_min): this
  /// instance's first cycle, or the active one's if earlier (a standby started late).
  std::optional<TimestampNs> incident_start_;
  std::string dig_order_logged_;            ///< the victim ids in dig order, as last logged
  struct OperatorDigOrder {
    std::vector<std::uint32_t> victim_ids;
    std::string operator_id;
    std::set<std::uint32_t> found;  ///< the FOUND victims it was given for
  };
  std::optional<OperatorDigOrder> operator_dig_order_;
  std::optional<SignalPursuits> pursuits_;  ///< with the planner
  VictimFusion fusion_;
  TeamTracker tracker_;
  AlarmBoard alarm_board_;
  StandbyArbiter arbiter_;
  std::deque<PendingEstimate> pending_estimates_;
  std::map<std::string, ResponderTrack> fixes_;          ///< per responder
  std::map<std::string, std::string> link_writers_;      ///< writer -> the responder it stands for
  std::map<std::pair<std::string, std::uint32_t>, TimestampNs> separation_events_logged_;
  std::map<std::pair<std::string, std::uint32_t>, responder::RepeatState> repeats_logged_;
  struct HeardRecord {
    HeardSignal signal;
    TimestampNs arrived = 0;  ///< the last estimate's arrival; older than fusion.source_timeout_s: dropped
  };
  std::map<SignalKey, HeardRecord> heard_;
  std::vector<TeamStatus> last_teams_;
  std::vector<IncidentEvent> events_;

  // The active instance's picture as received (while standby).
  std::map<std::uint32_t, FusedVictim> adopted_victims_;
  std::map<std::string, TeamStatus> adopted_teams_;
  std::map<std::uint32_t, IncidentAlarm> adopted_alarms_;
  std::optional<IncidentFrame> adopted_frame_;
  std::optional<SearchPlanPicture> adopted_plan_;
  bool plan_adoption_refused_ = false;  ///< said once: the strips were cut differently
  bool fresh_picture_ = false;  ///< a summary of the active one arrived since the last adoption

  TimestampNs redispose_until_ = 0;    ///< wall
  std::uint32_t largest_id_seen_ = 0;  ///< victim ids published so far, disposed ones included
  IncidentFrame frame_;                ///< what this instance publishes while active
};

}  // namespace sarloc::incident
