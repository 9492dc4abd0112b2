#pragma once
// Core messages filled with distinctive, non-default values (every field differs from its
// default, so a conversion that drops a field fails the round-trip comparison).
#include "sarloc/core/avalanche/field_measurement.hpp"
#include "sarloc/core/incident/alarm_board.hpp"
#include "sarloc/core/incident/fused_victim.hpp"
#include "sarloc/core/incident/search_plan.hpp"
#include "sarloc/core/incident/team_status.hpp"
#include "sarloc/core/responder/guidance.hpp"
#include "sarloc/core/responder/odometry.hpp"
#include "sarloc/core/responder/responder_candidates.hpp"
#include "sarloc/core/responder/responder_position.hpp"
#include "sarloc/core/responder/victim_estimate.hpp"

namespace sarloc::test {

// A full matrix whose every entry differs (catches row/column-major mix-ups).
template <int N>
Eigen::Matrix<double, N, N> distinct_matrix(double base) {
  Eigen::Matrix<double, N, N> m;
  for (int r = 0; r < N; ++r)
    for (int c = 0; c < N; ++c) m(r, c) = base + 10.0 * r + c + 0.25;
  return m;
}

inline GaussianPosition sample_position(double base) {
  return GaussianPosition{Vec3(base + 1.5, base - 2.25, base * 0.5 - 1.0), distinct_matrix<3>(base)};
}

inline avalanche::FieldMeasurement sample_field_measurement() {
  avalanche::FieldMeasurement m;
  m.rescuer_id = "rescuer-alpha";
  m.signal_id = 7;
  m.sequence = 123456789012ULL;
  m.stamp = 1763731200123456789LL;
  m.field = Vec3(1.5e-6, -2.5e-7, 3.25e-8);
  m.noise_stddev = Vec3(1e-8, 2e-8, 3e-8);
  m.valid_axes = 0b101;
  m.event = avalanche::SignalEvent::kSeparated;
  m.unattributed_pulses = 3;
  m.transmitter = {-12.5, 4.6, 1.0002, 0.0002};
  m.orientation = avalanche::OrientationObservation{Vec3(0.1, -0.2, 1.3), distinct_matrix<3>(0.001)};
  return m;
}

inline responder::Odometry sample_odometry() {
  responder::Odometry o;
  o.rescuer_id = "rescuer-bravo";
  o.sequence = 42;
  o.interval_start = 1763731200000000000LL;
  o.interval_end = 1763731201000000000LL;
  o.translation = Vec3(0.98, 0.05, -0.01);
  o.rotation_rpy = Vec3(0.004, -0.006, 0.12);
  o.covariance = distinct_matrix<6>(0.0001);
  o.source = responder::OdometrySource::kFootMountedIns;
  return o;
}

inline responder::VictimEstimate sample_victim_estimate() {
  responder::VictimEstimate e;
  e.rescuer_id = "rescuer-charlie";
  e.signal_id = 3;
  e.stamp = 1763731260000000000LL;
  e.status = responder::EstimatorStatus::kLocated;
  e.relative = sample_position(4.0);
  for (int i = 0; i < 3; ++i) {
    e.top_components.push_back({0.5 - 0.1 * i, Vec3(i, -i, 0.5 * i), distinct_matrix<3>(i)});
  }
  e.live_components = 17;
  e.moment = Vec3(0.01, -0.02, 0.005);
  e.signal_event = responder::SignalEvent::kReacquired;
  e.signal_event_stamp = 1763731250000000000LL;
  e.repeat = responder::RepeatState::kSuspected;
  e.repeat_of_signal = 1;
  e.transmitter = {25.25, 4.57, 0.99999, 0.00015};
  return e;
}

inline responder::Guidance sample_guidance() {
  responder::Guidance g;
  g.rescuer_id = "rescuer-delta";
  g.signal_id = 2;
  g.stamp = 1763731270000000000LL;
  g.mode = responder::GuidanceMode::kFineSearch;
  g.bearing_rad = -0.75;
  g.heading_rad = 2.5;
  g.distance_m = 3.25;
  g.step_m = 0.75;
  g.uncertainty_radius_m = 0.4;
  return g;
}

inline responder::ResponderPosition sample_responder_position() {
  responder::ResponderPosition r;
  r.responder_id = "ff-engine-7-a";
  r.team_id = "engine-7";
  r.stamp = 1763731280000000000LL;
  r.position = sample_position(30.0);
  r.heading_rad = 1.25;
  r.floor = 3;
  r.source = responder::PositionSource::kMapAided;
  r.converged = true;
  r.map_error_suspected = true;
  r.confirmed = true;
  r.ambiguous = true;
  return r;
}

inline responder::ResponderCandidates sample_responder_candidates() {
  responder::ResponderCandidates c;
  c.responder_id = "ff-engine-7-a";
  c.stamp = 1763731280000000000LL;
  c.candidates = {{sample_position(31.0), 3, 0.625}, {sample_position(47.0), 2, 0.25}};
  return c;
}

inline incident::FusedVictim sample_fused_victim() {
  incident::FusedVictim v;
  v.victim_id = 11;
  v.position = sample_position(55.0);
  v.sources = {{"rescuer-alpha", 1, 1763731290000000000LL, responder::SignalEvent::kNone, 0},
               {"rescuer-bravo", 4, 1763731291000000000LL, responder::SignalEvent::kSeparated, 1763731280000000000LL}};
  v.state = incident::VictimState::kFound;
  v.first_seen = 1763731200000000000LL;
  v.last_update = 1763731291000000000LL;
  v.located_at = 1763731250000000000LL;
  v.found_at = 1763731290000000000LL;
  v.evidence_conflict = true;
  v.possibly_same_as = 7;
  return v;
}

inline incident::TeamStatus sample_team_status() {
  incident::TeamStatus t;
  t.team_id = "team-north";
  t.stamp = 1763731300000000000LL;
  for (int i = 0; i < 3; ++i) {
    incident::MemberStatus m;
    m.responder_id = "rescuer-" + std::to_string(i);
    m.last_position = sample_position(10.0 * i);
    m.last_seen = 1763731299000000000LL - i;
    m.link = static_cast<incident::LinkState>(i);
    m.accountability = static_cast<incident::AccountabilityState>(2 - i);
    m.floor = i;
    m.source = static_cast<responder::PositionSource>(i);
    m.confirmed = i == 1;
    t.members.push_back(m);
  }
  return t;
}

inline responder::ResponderAlarm sample_responder_alarm() {
  responder::ResponderAlarm a;
  a.responder_id = "ff-7";
  a.team_id = "alpha";
  a.kind = responder::AlarmKind::kMotionless;
  a.raised_at = 1763731300000000000LL;
  a.cleared_at = 1763731330000000000LL;
  a.active = false;
  a.position_known = true;
  a.last_position = sample_position(3.0);
  a.floor = 1;
  return a;
}

inline incident::IncidentAlarm sample_incident_alarm() {
  incident::IncidentAlarm a;
  a.alarm_id = 42;
  a.alarm = sample_responder_alarm();
  a.alarm.kind = responder::AlarmKind::kMayday;
  a.acknowledged = true;
  a.acknowledged_by = "ic-chief";
  a.acknowledged_at = 1763731340000000000LL;
  return a;
}

/// An 80 x 100 m deposit's plan: strip 0 (the western 40 m) walked by r1, next at (20, 80);
/// strip 1 done, nobody's.
inline incident::SearchPlanPicture sample_search_plan() {
  incident::SearchPlanPicture p;
  p.incident_id = "avalanche-large";
  p.stamp = 1763731340000000000LL;
  p.deposit = {{0, 0}, {80, 0}, {80, 100}, {0, 100}};
  p.plan.revision = 7;
  p.plan.searched = 0.25;
  incident::PlannedStrip a;
  a.strip.index = 0;
  a.strip.outline = {{0, 0}, {40, 0}, {40, 100}, {0, 100}};
  a.strip.top = {20, 100};
  a.strip.bottom = {20, 0};
  a.strip.width_m = 40;
  a.searched = 0.5;
  a.rescuer_id = "r1";
  a.helper_id = "r4";
  incident::PlannedStrip b = a;
  b.strip.index = 1;
  b.strip.outline = {{40, 0}, {80, 0}, {80, 100}, {40, 100}};
  b.strip.top = {60, 100};
  b.strip.bottom = {60, 0};
  b.rescuer_id.clear();
  b.helper_id.clear();
  b.done = true;
  b.searched = 1.0;
  p.plan.strips = {a, b};
  p.next_points = {incident::Vec2(20, 80), std::nullopt};
  p.helper_next_points = {incident::Vec2(20, 12), std::nullopt};
  p.handed_over = {{"r2", 3, 7, "r1"}, {"r1", 5, 0, "r3"}};  // victim 0: a transmitter not yet placed
  // Victim 7 (0.6 m deep) dug first by r3, then victim 9 (1.8 m) when a team is free.
  p.digs.digs = {{7, 0.6, 12.0, 0.0, 4.8, 0.92, "r3"}, {9, 1.8, 12.0, 4.8, 30.0, 0.43, ""}};
  p.digs.expected_survivors = 1.35;
  p.incident_start = 1763731000000000000LL;
  return p;
}

}  // namespace sarloc::test
