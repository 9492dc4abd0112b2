#pragma once
// Incident command's alarms: what the commander must see and answer. Each alarm stays on the
// board until an operator acknowledged it *and* its condition cleared, so an alarm that came
// and went while nobody looked is still there to be seen.
//
// One alarm per (responder, kind) at most, as an alarm system's state machine has it (ISA-18.2:
// a cleared alarm nobody acknowledged that goes off again is the same alarm, active again). A
// condition that comes and goes (a map error flickering at a doorway) is then one row to answer
// and not one per episode: 670 such rows piled up for 200 firefighters in an hour, each
// republished every cycle, and the board and its readers grew without end (issue 64).
//
// Sources:
//   - a device's alarms (motionless, mayday; responder::ResponderAlarm), identified by
//     (responder, kind, raised_at): the raise and its clear are one alarm, in whichever order and
//     however often they arrive. A newer raise is a new episode; an older episode's samples are
//     late and change nothing, unless they say active while the alarm is not (a device whose clock
//     went back): a raise is never hidden;
//   - conditions incident command sees itself (link lost, map error): set_condition(true) raises
//     the (responder, kind) alarm unless it is active, set_condition(false) clears it.
// A new episode reopens the alarm when nobody acknowledged it (same id, active, raised_at the new
// episode's). Once acknowledged it is answered: the next episode is a new alarm, and the
// acknowledged one, if still active, goes (a device's clear was lost). An acknowledgement made
// before the alarm was reopened is of an earlier episode: it leaves this one to be answered. The
// time compared is incident command's, not the device's raised_at: a device's clock may be ahead.
// Acknowledging a cleared alarm removes it (its id is reported by take_removed so the picture
// can dispose of it); acknowledging an active one marks it, and it goes when it clears.
//
// Hot standby: a standby instance adopts the active one's board as published (adopt), with its
// ids and acknowledgements, and goes on from there when it takes over.
//
//   AlarmBoard board;
//   board.on_device_alarm(alarm, now);
//   board.set_condition("ff1", "alpha", AlarmKind::kLinkLost, true, now, last_position);
//   board.acknowledge(id, "ic-1", acknowledged_at, now);
//   publish(board.alarms()); dispose(board.take_removed());
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sarloc/core/responder/alarm.hpp"

namespace sarloc::incident {

struct IncidentAlarm {
  std::uint32_t alarm_id = 0;
  responder::ResponderAlarm alarm;  ///< responder, team, kind, raised/cleared, position
  bool acknowledged = false;
  std::string acknowledged_by;
  TimestampNs acknowledged_at = 0;
  /// Incident command's time when a new episode last reopened it (0: not since it was opened, or
  /// adopted). Not published: a standby's board starts from 0.
  TimestampNs reopened_at = 0;
};

/// Every field equal: a reader of the alarms republished each cycle tells a change by it.
bool same_alarm(const IncidentAlarm& a, const IncidentAlarm& b);

enum class AckResult : std::uint8_t {
  kAcknowledged,    ///< marked (and removed if it had cleared)
  kAlready,         ///< acknowledged before: nothing changed
  kEarlierEpisode,  ///< made before the alarm's current episode began: nothing changed
  kUnknown,         ///< no such alarm (never raised, or removed already)
};

class AlarmBoard {
 public:
  /// A device's alarm raised or cleared: the (responder, kind) alarm's episode `alarm.raised_at`
  /// (see the top). Throws InputError for an empty responder_id or a
  /// clear before its raise (cleared_at < raised_at).
  void on_device_alarm(const responder::ResponderAlarm& alarm, TimestampNs now);
  /// A condition incident command watches (kLinkLost, kMapError): raises its alarm when it
  /// becomes true (opened, or reopened if nobody acknowledged it), clears it when it becomes false. `position` (if
  /// known) is where the responder was last known.
  void set_condition(const std::string& responder_id, const std::string& team_id, responder::AlarmKind kind,
                     bool active, TimestampNs now, const std::optional<GaussianPosition>& position = std::nullopt,
                     std::int32_t floor = 0);
  /// An operator's acknowledgement, made at `stamp` (the operator's clock; 0: unknown), received
  /// at `now`.
  AckResult acknowledge(std::uint32_t alarm_id, const std::string& operator_id, TimestampNs stamp, TimestampNs now);

  /// Every alarm on the board, by id.
  std::vector<IncidentAlarm> alarms() const;
  /// Ids removed since the previous call (acknowledged and cleared, or acknowledged and followed
  /// by a new episode).
  std::vector<std::uint32_t> take_removed();
  /// Replaces the board by the active instance's (hot standby).
  void adopt(const std::vector<IncidentAlarm>& alarms);
  std::size_t active_count() const;

 private:
  using Condition = std::pair<std::string, responder::AlarmKind>;

  /// The (responder, kind) alarm, or null.
  IncidentAlarm* find(const std::string& responder_id, responder::AlarmKind kind);
  /// A new episode: reopens the (responder, kind) alarm if nobody acknowledged it, else opens one
  /// (removing the acknowledged one, whose episode has ended).
  void raise(const responder::ResponderAlarm& alarm, TimestampNs now);
  void remove(std::uint32_t alarm_id);
  void remove_if_done(std::uint32_t alarm_id);

  std::map<std::uint32_t, IncidentAlarm> alarms_;
  std::map<Condition, std::uint32_t> alarm_of_;  ///< the one alarm of each (responder, kind)
  std::uint32_t next_id_ = 1;
  std::vector<std::uint32_t> removed_;
};

}  // namespace sarloc::incident
