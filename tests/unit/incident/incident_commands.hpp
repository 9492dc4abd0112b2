#pragma once
// IncidentCommand tests' inputs: rescuers' positions and estimates, and the active instance's
// picture as a standby receives it.
#include "sarloc/core/incident/incident_command.hpp"
#include "sarloc/core/responder/alarm.hpp"

namespace sarloc::incident::test {

constexpr TimestampNs kSecond = 1'000'000'000;
/// Mission and wall clocks of these tests start here (2025-11-22).
constexpr TimestampNs kStart = 1'763'800'000 * kSecond;

inline TimestampNs at(double seconds) { return kStart + static_cast<TimestampNs>(seconds * 1e9); }

/// One instance alone (active at its first cycle), or instance `instance` of `instances`.
inline IncidentCommandConfig command_config(unsigned instance = 1, unsigned instances = 1) {
  IncidentCommandConfig c;
  c.incident_id = "unit-incident";
  c.incident_name = "Unit test";
  c.fix_wait_s = 1.0;
  c.standby.instance = instance;
  c.standby.instances = instances;
  return c;
}

/// A GNSS fix of `responder` (team "north") at `p`, GNSS altitude 1500 m.
inline responder::ResponderPosition gnss_fix(const std::string& responder, TimestampNs stamp, const Vec3& p) {
  responder::ResponderPosition fix;
  fix.responder_id = responder;
  fix.team_id = "north";
  fix.stamp = stamp;
  fix.position.position = p;
  fix.position.covariance = 0.01 * Mat3::Identity();
  return fix;
}

/// `rescuer`'s estimate of `signal`: relative (3, 4, -2), tight, with status `status`.
inline responder::VictimEstimate estimate_of(const std::string& rescuer, std::uint32_t signal, TimestampNs stamp,
                                             responder::EstimatorStatus status = responder::EstimatorStatus::kConverged) {
  responder::VictimEstimate e;
  e.rescuer_id = rescuer;
  e.signal_id = signal;
  e.stamp = stamp;
  e.status = status;
  e.relative.position = Vec3(3.0, 4.0, -2.0);
  e.relative.covariance = 0.01 * Mat3::Identity();
  return e;
}

/// `responder`'s mayday raised at `raised_at` (team "north").
inline responder::ResponderAlarm mayday_of(const std::string& responder, TimestampNs raised_at) {
  responder::ResponderAlarm mayday;
  mayday.responder_id = responder;
  mayday.team_id = "north";
  mayday.kind = responder::AlarmKind::kMayday;
  mayday.raised_at = raised_at;
  return mayday;
}

/// What a standby's picture readers receive of the active instance's cycle `out` (written by
/// the summary writer `writer`), in the order it publishes: disposals, victims, teams, alarms,
/// summary, frame.
inline void deliver_picture(const CommandCycle& out, IncidentCommand& standby, const std::string& writer,
                            TimestampNs wall) {
  for (const auto id : out.disposed_victims) standby.on_peer_victim_disposed(id);
  for (const auto& v : out.victims) standby.on_peer_victim(v);
  for (const auto& t : out.teams) standby.on_peer_team(t);
  for (const auto id : out.disposed_alarms) standby.on_peer_alarm_disposed(id);
  for (const auto& a : out.alarms) standby.on_peer_alarm(a);
  standby.on_peer_summary(writer, wall);
  standby.on_peer_frame(out.frame);
  if (out.search_plan) standby.on_peer_search_plan(*out.search_plan);
}

inline bool has_event(const CommandCycle& out, IncidentEvent::Kind kind, const std::string& part) {
  for (const auto& e : out.events) {
    if (e.kind == kind && e.text.find(part) != std::string::npos) return true;
  }
  return false;
}

}  // namespace sarloc::incident::test
