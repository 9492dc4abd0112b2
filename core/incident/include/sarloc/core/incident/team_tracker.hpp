#pragma once
// Responder tracking by team, and the personnel accountability report (PAR) derived from it.
//
// Inputs: every ResponderPosition (which also tells the responder's team) and DDS liveliness
// changes of the responder's writer. "Heard" means a position arrived or liveliness reported
// the writer alive; times are the caller's receive clock `now`, not the device stamps (device
// clocks may be off, and a link is about what incident command receives).
//
//   link state                                   accountability (PAR)
//   kAlive : heard within stale_after_s      ->  kAccounted: telemetry confirms the responder
//   kStale : silent > stale_after_s          ->  kPending:   confirm by radio at the next PAR
//   kLost  : silent > lost_after_s, or DDS   ->  kMissing:   unaccounted for; PAR now, consider
//            liveliness lost (at once)                       the rapid intervention team
//   kSignedOff: the device stopped in order  ->  kAccounted: it said so before it left; its
//            and said so (on_signed_off)                     writer's departure raises nothing
// A responder heard again after being lost or signed off becomes kAlive / kAccounted again. A liveliness
// change for a responder never positioned yet is kept under team "" (unassigned) until its
// first position names the team; a position naming another team moves the responder.
//
//   TeamTracker teams(TeamTrackerConfig{});
//   teams.on_position(position, now);
//   teams.on_link("r1", /*alive=*/false, now);      // from a liveliness-lost callback
//   for (const TeamStatus& t : teams.evaluate(now)) ...;
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "sarloc/core/common/types.hpp"
#include "sarloc/core/responder/responder_position.hpp"
#include "sarloc/core/incident/team_status.hpp"

namespace sarloc::incident {

using responder::ResponderPosition;

struct TeamTrackerConfig {
  double stale_after_s = 5.0;   ///< silent longer than this: kStale / kPending
  double lost_after_s = 15.0;   ///< silent longer than this: kLost / kMissing (> stale_after_s)

  /// Throws ConfigError "team_tracker.<key> = value: rule".
  void validate() const;
};

/// PAR mapping of a link state (see the table above).
AccountabilityState accountability_of(LinkState link);

class TeamTracker {
 public:
  explicit TeamTracker(TeamTrackerConfig config = {});

  /// A position report. Throws InputError for an empty responder_id. The stored position is
  /// replaced only by a report with a stamp >= the stored one, and a dead-reckoned one does not
  /// replace a map-aided one less than 3 s older; every report counts as heard but a map-aided
  /// one no newer than the newest map-aided one: the core daemon writes a silent firefighter's
  /// last position again (estimator::PositionRefresh), which says nothing of his link.
  void on_position(const ResponderPosition& position, TimestampNs now);
  /// DDS liveliness: alive = false marks the link lost at once (unless the responder signed
  /// off: its writer's departure then is the sign-off's); alive = true counts as heard.
  void on_link(const std::string& responder_id, bool alive, TimestampNs now);
  /// The responder's device stopped in order and said so (it disposed its own position
  /// instance): kSignedOff until its device is heard again (its liveliness, or a newer position
  /// of its own; the core daemon's map-aided ones do not count). Throws InputError for an empty id.
  void on_signed_off(const std::string& responder_id, TimestampNs now);

  /// Fills in what another incident command published (hot standby, see VictimFusion::adopt)
  /// and this tracker has not heard itself: responders it does not know yet join with the
  /// picture's team, last position (a position with stamp position_stamp), last_seen and
  /// link (kLost stays lost until heard again); a known responder without a position takes
  /// the picture's, and its last_seen is the later of both. What this tracker heard itself
  /// is never overwritten. Throws InputError for an empty responder_id.
  void adopt(const std::vector<TeamStatus>& teams);

  /// Teams sorted by id, members sorted by id, states evaluated at `now`.
  std::vector<TeamStatus> evaluate(TimestampNs now) const;

  std::size_t responders_total() const { return members_.size(); }
  /// Whether the responder signed off and was not heard since.
  bool signed_off(const std::string& responder_id) const;
  /// Responders whose link is kLost at `now` (signed-off ones are not).
  std::size_t link_lost_count(TimestampNs now) const;
  /// Same, at the latest `now` given to any call.
  std::size_t link_lost_count() const { return link_lost_count(latest_now_); }

  const TeamTrackerConfig& config() const { return config_; }

 private:
  struct Member {
    std::string team_id;
    ResponderPosition last_position;
    bool has_position = false;
    TimestampNs last_heard = 0;
    bool liveliness_lost = false;
    bool signed_off = false;
    TimestampNs newest_map_aided = 0;  ///< stamp of the newest map-aided report (0: none)
  };
  LinkState link_of(const Member& m, TimestampNs now) const;

  TeamTrackerConfig config_;
  std::map<std::string, Member> members_;  ///< by responder id
  TimestampNs latest_now_ = 0;
};

}  // namespace sarloc::incident
