#pragma once
// What changed in the incident picture, in words. The dashboard's event log and the
// post-mission report's timeline both derive their events here, from the same picture samples,
// so a commander reads the same sentence, at the same time, live and afterwards.
//
//   PictureEvents events;
//   for (const PictureEvent& e : events.on_victim(victim)) log(e.stamp, e.kind, e.text);
//
// Each event carries the time the sample gives for it (located_at, found_at, raised_at, ...),
// not when it was read: a dashboard started late, or a report, dates a FOUND when it happened.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "sarloc/core/common/types.hpp"
#include "sarloc/core/incident/alarm_board.hpp"
#include "sarloc/core/incident/fused_victim.hpp"
#include "sarloc/core/incident/team_status.hpp"
#include "sarloc/core/responder/responder_position.hpp"

namespace sarloc::incident {

struct PictureEvent {
  TimestampNs stamp = 0;  ///< when it happened, by the sample (incident clock)
  std::string kind;       ///< "victim", "link", "accountability", "alarm", "map error"
  std::string text;
};

/// "accounted for", "check due (PAR)", "MISSING at the check".
const char* display_name(AccountabilityState state);

class PictureEvents {
 public:
  /// In the picture; LOCATED, FOUND (with its 95 % radius), recovered; a confirmation withdrawn;
  /// its sources disagreeing, or agreeing again. A victim first seen FOUND gives each step
  /// whose time it carries.
  std::vector<PictureEvent> on_victim(const FusedVictim& v);
  /// Disposed by incident command: merged into another victim (one transmitter).
  std::vector<PictureEvent> on_victim_gone(std::uint32_t victim_id, TimestampNs stamp);
  /// A member's link or accountability changing (nothing for a member's first status).
  std::vector<PictureEvent> on_team(const TeamStatus& t);
  /// Raised (again when a new episode reopened it), acknowledged (by whom), cleared; an alarm
  /// first seen already cleared gives both.
  std::vector<PictureEvent> on_alarm(const IncidentAlarm& a);
  /// Disposed by incident command: acknowledged and cleared.
  std::vector<PictureEvent> on_alarm_gone(std::uint32_t alarm_id, TimestampNs stamp);
  /// Map-aided positions only: the map-aided filter's floor-plan suspicion switching on or off.
  /// A sample not newer than the responder's newest map-aided one changes nothing.
  std::vector<PictureEvent> on_position(const responder::ResponderPosition& p);

 private:
  struct VictimSeen {
    VictimState state = VictimState::kUnconfirmed;
    bool conflict = false;
  };
  struct MemberSeen {
    LinkState link = LinkState::kAlive;
    AccountabilityState accountability = AccountabilityState::kPending;
  };
  struct AlarmSeen {
    bool acknowledged = false, active = true;
    TimestampNs raised_at = 0;  ///< the episode: a newer one reopened the alarm (AlarmBoard)
  };
  struct MapAidedSeen {
    TimestampNs stamp = 0;
    bool suspected = false;
  };
  std::map<std::uint32_t, VictimSeen> victims_;
  std::map<std::string, MemberSeen> members_;
  std::map<std::uint32_t, AlarmSeen> alarms_;
  std::map<std::string, MapAidedSeen> map_aided_;
};

}  // namespace sarloc::incident
