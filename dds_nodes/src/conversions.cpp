#include "sarloc/dds/conversions.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/identifier.hpp"
#include "sarloc/idl/incidentPubSubTypes.h"

namespace sarloc::dds {
namespace {

using Identifier = eprosima::fastrtps::fixed_string<::sarloc::ID_MAX>;

Identifier to_identifier(const std::string& value, const char* field) {
  if (value.size() > ::sarloc::ID_MAX) {
    throw InputError(std::string(field) + " = '" + value.substr(0, 16) + "...' has " + std::to_string(value.size()) +
                     " characters: at most " + std::to_string(::sarloc::ID_MAX));
  }
  return Identifier(value);
}

// Every id from the wire passes the one identifier rule (sarloc/core/common/identifier.hpp):
// a peer's bytes that are not an id (invalid UTF-8, markup, control characters) are refused
// here, counted as the reader's rejection, and never reach a picture, a page or a file name.
std::string from_identifier(const Identifier& id, const char* field, bool empty_allowed = false) {
  std::string value = id.to_string();
  check_identifier(value, field, empty_allowed);
  return value;
}

// Row-major on the wire, whatever Eigen's storage order.
template <int N, class Array>
void matrix_to_array(const Eigen::Matrix<double, N, N>& m, Array& out) {
  for (int r = 0; r < N; ++r)
    for (int c = 0; c < N; ++c) out[static_cast<std::size_t>(r * N + c)] = m(r, c);
}

template <int N, class Array>
Eigen::Matrix<double, N, N> array_to_matrix(const Array& in) {
  Eigen::Matrix<double, N, N> m;
  for (int r = 0; r < N; ++r)
    for (int c = 0; c < N; ++c) m(r, c) = in[static_cast<std::size_t>(r * N + c)];
  return m;
}

// Wire enums may hold values a newer peer defined: refuse them by name.
template <class CoreEnum>
CoreEnum checked_enum(std::uint32_t wire, std::uint32_t last, const char* field) {
  if (wire > last) {
    throw InputError(std::string(field) + " = " + std::to_string(wire) + ": unknown value (max " +
                     std::to_string(last) + ")");
  }
  return static_cast<CoreEnum>(wire);
}

}  // namespace

std::string printable_id(const Identifier& id) {
  std::string value = id.to_string();
  return is_identifier(value) ? value : printable_excerpt(value);
}

::sarloc::Vector3 to_idl(const Vec3& v) {
  ::sarloc::Vector3 out;
  out.x(v.x());
  out.y(v.y());
  out.z(v.z());
  return out;
}

Vec3 to_core(const ::sarloc::Vector3& v) { return Vec3(v.x(), v.y(), v.z()); }

::sarloc::Quaternion to_idl(const Quat& q) {
  ::sarloc::Quaternion out;
  out.x(q.x());
  out.y(q.y());
  out.z(q.z());
  out.w(q.w());
  return out;
}

Quat to_core(const ::sarloc::Quaternion& q) { return Quat(q.w(), q.x(), q.y(), q.z()); }

::sarloc::PositionWithCovariance to_idl(const GaussianPosition& p) {
  ::sarloc::PositionWithCovariance out;
  out.position(to_idl(p.position));
  matrix_to_array<3>(p.covariance, out.covariance());
  return out;
}

GaussianPosition to_core(const ::sarloc::PositionWithCovariance& p) {
  return GaussianPosition{to_core(p.position()), array_to_matrix<3>(p.covariance())};
}

::sarloc::PoseWithCovariance to_idl(const GaussianPose& p) {
  ::sarloc::PoseWithCovariance out;
  out.position(to_idl(p.position));
  out.orientation(to_idl(p.orientation));
  matrix_to_array<6>(p.covariance, out.covariance());
  return out;
}

GaussianPose to_core(const ::sarloc::PoseWithCovariance& p) {
  return GaussianPose{to_core(p.position()), to_core(p.orientation()), array_to_matrix<6>(p.covariance())};
}

::sarloc::TransmitterSignature to_idl(const responder::TransmitterSignature& s) {
  ::sarloc::TransmitterSignature out;
  out.carrier_offset_hz(s.carrier_offset_hz);
  out.carrier_sigma_hz(s.carrier_sigma_hz);
  out.period_s(s.period_s);
  out.period_sigma_s(s.period_sigma_s);
  return out;
}

responder::TransmitterSignature to_core(const ::sarloc::TransmitterSignature& s, const std::string& where) {
  const responder::TransmitterSignature out{s.carrier_offset_hz(), s.carrier_sigma_hz(), s.period_s(), s.period_sigma_s()};
  responder::check_signature(out, where);
  return out;
}

::sarloc::FieldMeasurement to_idl(const avalanche::FieldMeasurement& m) {
  ::sarloc::FieldMeasurement out;
  out.rescuer_id(to_identifier(m.rescuer_id, "field_measurement.rescuer_id"));
  out.signal_id(m.signal_id);
  out.sequence_number(m.sequence);
  out.stamp(m.stamp);
  out.field(to_idl(m.field));
  out.noise_stddev(to_idl(m.noise_stddev));
  out.valid_axes(m.valid_axes);
  out.signal_event(static_cast<::sarloc::SignalEvent>(m.event));
  out.unattributed_pulses(m.unattributed_pulses);
  out.transmitter(to_idl(m.transmitter));
  out.has_orientation(m.orientation.has_value());
  if (m.orientation) {
    out.orientation_rpy(to_idl(m.orientation->rpy));
    matrix_to_array<3>(m.orientation->covariance, out.orientation_covariance());
  }
  return out;
}

avalanche::FieldMeasurement to_core(const ::sarloc::FieldMeasurement& m) {
  avalanche::FieldMeasurement out;
  out.rescuer_id = from_identifier(m.rescuer_id(), "field_measurement.rescuer_id");
  out.signal_id = m.signal_id();
  out.sequence = m.sequence_number();
  out.stamp = m.stamp();
  out.field = to_core(m.field());
  out.noise_stddev = to_core(m.noise_stddev());
  out.valid_axes = m.valid_axes();  // the filters' gate names a bad mask
  out.event = checked_enum<responder::SignalEvent>(m.signal_event(), ::sarloc::SIGNAL_SEPARATED,
                                                   "field_measurement.signal_event");
  out.unattributed_pulses = m.unattributed_pulses();
  out.transmitter = to_core(m.transmitter(), "field_measurement.transmitter");
  if (m.has_orientation()) {
    out.orientation = avalanche::OrientationObservation{to_core(m.orientation_rpy()),
                                                        array_to_matrix<3>(m.orientation_covariance())};
  }
  return out;
}

::sarloc::Odometry to_idl(const responder::Odometry& o) {
  ::sarloc::Odometry out;
  out.rescuer_id(to_identifier(o.rescuer_id, "odometry.rescuer_id"));
  out.sequence_number(o.sequence);
  out.interval_start(o.interval_start);
  out.interval_end(o.interval_end);
  out.translation(to_idl(o.translation));
  out.rotation_rpy(to_idl(o.rotation_rpy));
  matrix_to_array<6>(o.covariance, out.covariance());
  out.source(static_cast<::sarloc::OdometrySource>(o.source));
  return out;
}

responder::Odometry to_core(const ::sarloc::Odometry& o) {
  responder::Odometry out;
  out.rescuer_id = from_identifier(o.rescuer_id(), "odometry.rescuer_id");
  out.sequence = o.sequence_number();
  out.interval_start = o.interval_start();
  out.interval_end = o.interval_end();
  out.translation = to_core(o.translation());
  out.rotation_rpy = to_core(o.rotation_rpy());
  out.covariance = array_to_matrix<6>(o.covariance());
  out.source = checked_enum<responder::OdometrySource>(o.source(), ::sarloc::ODOMETRY_OTHER, "odometry.source");
  return out;
}

::sarloc::VictimEstimate to_idl(const responder::VictimEstimate& e, std::uint64_t measurement_sequence) {
  ::sarloc::VictimEstimate out;
  out.rescuer_id(to_identifier(e.rescuer_id, "victim_estimate.rescuer_id"));
  out.signal_id(e.signal_id);
  out.stamp(e.stamp);
  out.measurement_sequence(measurement_sequence);
  out.status(static_cast<::sarloc::EstimatorStatus>(e.status));
  out.relative(to_idl(e.relative));
  const std::size_t n = std::min<std::size_t>(e.top_components.size(), ::sarloc::MIXTURE_SUMMARY_MAX);
  out.top_components().reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    ::sarloc::MixtureComponent c;
    c.weight(e.top_components[i].weight);
    c.mean(to_idl(e.top_components[i].mean));
    matrix_to_array<3>(e.top_components[i].covariance, c.covariance());
    out.top_components().push_back(c);
  }
  out.live_components(e.live_components);
  out.moment(to_idl(e.moment));
  out.signal_event(static_cast<::sarloc::SignalEvent>(e.signal_event));
  out.signal_event_stamp(e.signal_event_stamp);
  out.repeat(static_cast<::sarloc::RepeatState>(e.repeat));
  out.repeat_of_signal(e.repeat_of_signal);
  out.transmitter(to_idl(e.transmitter));
  out.reporter_known(e.reporter.has_value());
  if (e.reporter) out.reporter(to_idl(*e.reporter));
  return out;
}

responder::VictimEstimate to_core(const ::sarloc::VictimEstimate& e) {
  responder::VictimEstimate out;
  out.rescuer_id = from_identifier(e.rescuer_id(), "victim_estimate.rescuer_id");
  out.signal_id = e.signal_id();
  out.stamp = e.stamp();
  out.status = checked_enum<responder::EstimatorStatus>(e.status(), ::sarloc::ESTIMATOR_FOUND, "victim_estimate.status");
  out.relative = to_core(e.relative());
  for (const auto& c : e.top_components()) {
    out.top_components.push_back({c.weight(), to_core(c.mean()), array_to_matrix<3>(c.covariance())});
  }
  out.live_components = e.live_components();
  out.moment = to_core(e.moment());
  out.signal_event = checked_enum<responder::SignalEvent>(e.signal_event(), ::sarloc::SIGNAL_SEPARATED,
                                                          "victim_estimate.signal_event");
  out.signal_event_stamp = e.signal_event_stamp();
  out.repeat = checked_enum<responder::RepeatState>(e.repeat(), ::sarloc::REPEAT_CONFIRMED, "victim_estimate.repeat");
  out.repeat_of_signal = e.repeat_of_signal();
  out.transmitter = to_core(e.transmitter(), "victim_estimate.transmitter");
  if (out.repeat != responder::RepeatState::kNone && out.repeat_of_signal == out.signal_id) {
    throw InputError("victim_estimate.repeat_of_signal = " + std::to_string(out.repeat_of_signal) +
                     ": a signal cannot repeat itself");
  }
  if (e.reporter_known()) {
    out.reporter = to_core(e.reporter());
    if (out.reporter->responder_id != out.rescuer_id) {
      throw InputError("victim_estimate.reporter.responder_id = '" + out.reporter->responder_id +
                       "': not the estimate's rescuer '" + out.rescuer_id + "'");
    }
  }
  return out;
}

::sarloc::Guidance to_idl(const responder::Guidance& g, std::uint64_t measurement_sequence) {
  ::sarloc::Guidance out;
  out.rescuer_id(to_identifier(g.rescuer_id, "guidance.rescuer_id"));
  out.signal_id(g.signal_id);
  out.stamp(g.stamp);
  out.measurement_sequence(measurement_sequence);
  // The plan's strip guidance is the device's own (strip_guidance.hpp): no IDL value for it.
  if (g.mode > responder::GuidanceMode::kFound) {
    throw InputError("guidance.mode = " + std::to_string(static_cast<int>(g.mode)) + ": not a daemon's guidance");
  }
  out.mode(static_cast<::sarloc::GuidanceMode>(g.mode));
  out.bearing_rad(g.bearing_rad);
  out.heading_rad(g.heading_rad);
  out.distance_m(g.distance_m);
  out.step_m(g.step_m);
  out.uncertainty_radius_m(g.uncertainty_radius_m);
  return out;
}

responder::Guidance to_core(const ::sarloc::Guidance& g) {
  responder::Guidance out;
  out.rescuer_id = from_identifier(g.rescuer_id(), "guidance.rescuer_id");
  out.signal_id = g.signal_id();
  out.stamp = g.stamp();
  out.mode = checked_enum<responder::GuidanceMode>(g.mode(), ::sarloc::GUIDANCE_FOUND, "guidance.mode");
  out.bearing_rad = g.bearing_rad();
  out.heading_rad = g.heading_rad();
  out.distance_m = g.distance_m();
  out.step_m = g.step_m();
  out.uncertainty_radius_m = g.uncertainty_radius_m();
  return out;
}

::sarloc::ResponderPosition to_idl(const responder::ResponderPosition& r) {
  ::sarloc::ResponderPosition out;
  out.responder_id(to_identifier(r.responder_id, "responder_position.responder_id"));
  out.team_id(to_identifier(r.team_id, "responder_position.team_id"));
  out.stamp(r.stamp);
  out.position(to_idl(r.position));
  out.heading_rad(r.heading_rad);
  out.floor(r.floor);
  out.source(static_cast<::sarloc::PositionSource>(r.source));
  out.flags((r.converged ? ::sarloc::RESPONDER_FLAG_CONVERGED : 0U) |
            (r.map_error_suspected ? ::sarloc::RESPONDER_FLAG_MAP_ERROR_SUSPECTED : 0U) |
            (r.confirmed ? ::sarloc::RESPONDER_FLAG_CONFIRMED : 0U) |
            (r.ambiguous ? ::sarloc::RESPONDER_FLAG_AMBIGUOUS : 0U));
  return out;
}

responder::ResponderPosition to_core(const ::sarloc::ResponderPosition& r) {
  responder::ResponderPosition out;
  out.responder_id = from_identifier(r.responder_id(), "responder_position.responder_id");
  out.team_id = from_identifier(r.team_id(), "responder_position.team_id", true);
  out.stamp = r.stamp();
  out.position = to_core(r.position());
  out.heading_rad = r.heading_rad();
  out.floor = r.floor();
  out.source = checked_enum<responder::PositionSource>(r.source(), ::sarloc::POSITION_MANUAL, "responder_position.source");
  out.converged = (r.flags() & ::sarloc::RESPONDER_FLAG_CONVERGED) != 0;
  out.map_error_suspected = (r.flags() & ::sarloc::RESPONDER_FLAG_MAP_ERROR_SUSPECTED) != 0;
  out.confirmed = (r.flags() & ::sarloc::RESPONDER_FLAG_CONFIRMED) != 0;
  out.ambiguous = (r.flags() & ::sarloc::RESPONDER_FLAG_AMBIGUOUS) != 0;
  return out;
}

::sarloc::ResponderCandidates to_idl(const responder::ResponderCandidates& c) {
  if (c.candidates.size() > ::sarloc::POSITION_CANDIDATES_MAX) {
    throw InputError("responder_candidates.candidates: " + std::to_string(c.candidates.size()) + " places, at most " +
                     std::to_string(::sarloc::POSITION_CANDIDATES_MAX));
  }
  ::sarloc::ResponderCandidates out;
  out.responder_id(to_identifier(c.responder_id, "responder_candidates.responder_id"));
  out.stamp(c.stamp);
  for (const auto& candidate : c.candidates) {
    ::sarloc::PositionCandidate p;
    p.position(to_idl(candidate.position));
    p.floor(candidate.floor);
    p.weight(candidate.weight);
    out.candidates().push_back(p);
  }
  return out;
}

responder::ResponderCandidates to_core(const ::sarloc::ResponderCandidates& c) {
  responder::ResponderCandidates out;
  out.responder_id = from_identifier(c.responder_id(), "responder_candidates.responder_id");
  out.stamp = c.stamp();
  double total = 0.0;
  for (const auto& p : c.candidates()) {
    responder::PositionCandidate candidate;
    candidate.position = to_core(p.position());
    if (!candidate.position.position.allFinite() || !candidate.position.covariance.allFinite()) {
      throw InputError("responder_candidates.candidates.position: non-finite value");
    }
    candidate.floor = p.floor();
    if (!(p.weight() > 0.0 && p.weight() <= 1.0)) {
      throw InputError("responder_candidates.candidates.weight = " + std::to_string(p.weight()) +
                       ": must be in (0, 1]");
    }
    candidate.weight = p.weight();
    total += p.weight();
    out.candidates.push_back(candidate);
  }
  // Shares of one belief: rounding aside, they cannot hold more than all of it.
  if (total > 1.0 + 1e-6) {
    throw InputError("responder_candidates.candidates.weight: they sum to " + std::to_string(total) + ", more than 1");
  }
  return out;
}

::sarloc::FusedVictim to_idl(const incident::FusedVictim& v) {
  ::sarloc::FusedVictim out;
  out.victim_id(v.victim_id);
  out.position(to_idl(v.position));
  out.floor(v.floor);
  const std::size_t n = std::min<std::size_t>(v.sources.size(), ::sarloc::VICTIM_SOURCES_MAX);
  for (std::size_t i = 0; i < n; ++i) {
    ::sarloc::VictimSource s;
    s.rescuer_id(to_identifier(v.sources[i].rescuer_id, "fused_victim.sources.rescuer_id"));
    s.signal_id(v.sources[i].signal_id);
    s.last_update(v.sources[i].last_update);
    s.signal_event(static_cast<::sarloc::SignalEvent>(v.sources[i].signal_event));
    s.signal_event_stamp(v.sources[i].signal_event_stamp);
    out.sources().push_back(s);
  }
  out.state(static_cast<::sarloc::VictimState>(v.state));
  out.first_seen(v.first_seen);
  out.last_update(v.last_update);
  out.located_at(v.located_at);
  out.found_at(v.found_at);
  out.evidence_conflict(v.evidence_conflict);
  out.possibly_same_as(v.possibly_same_as);
  return out;
}

incident::FusedVictim to_core(const ::sarloc::FusedVictim& v) {
  incident::FusedVictim out;
  out.victim_id = v.victim_id();
  out.position = to_core(v.position());
  out.floor = v.floor();
  for (const auto& s : v.sources()) {
    out.sources.push_back({from_identifier(s.rescuer_id(), "fused_victim.sources.rescuer_id"), s.signal_id(), s.last_update(),
                           checked_enum<responder::SignalEvent>(s.signal_event(), ::sarloc::SIGNAL_SEPARATED,
                                                                "fused_victim.sources.signal_event"),
                           s.signal_event_stamp()});
  }
  out.state = checked_enum<incident::VictimState>(v.state(), ::sarloc::VICTIM_RECOVERED, "fused_victim.state");
  out.first_seen = v.first_seen();
  out.last_update = v.last_update();
  out.located_at = v.located_at();
  out.found_at = v.found_at();
  out.evidence_conflict = v.evidence_conflict();
  out.possibly_same_as = v.possibly_same_as();
  return out;
}

::sarloc::TeamStatus to_idl(const incident::TeamStatus& t) {
  ::sarloc::TeamStatus out;
  out.team_id(to_identifier(t.team_id, "team_status.team_id"));
  out.stamp(t.stamp);
  const std::size_t n = std::min<std::size_t>(t.members.size(), ::sarloc::TEAM_MEMBERS_MAX);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& m = t.members[i];
    ::sarloc::MemberStatus s;
    s.responder_id(to_identifier(m.responder_id, "team_status.members.responder_id"));
    s.last_position(to_idl(m.last_position));
    s.last_seen(m.last_seen);
    // Signed off goes on the wire as LINK_LOST (nothing is heard), ACCOUNTED, and the flag.
    const bool signed_off = m.link == incident::LinkState::kSignedOff;
    s.link(signed_off ? ::sarloc::LINK_LOST : static_cast<::sarloc::LinkState>(m.link));
    s.accountability(static_cast<::sarloc::AccountabilityState>(m.accountability));
    s.floor(m.floor);
    s.source(static_cast<::sarloc::PositionSource>(m.source));
    s.flags((m.converged ? ::sarloc::RESPONDER_FLAG_CONVERGED : 0U) |
            (m.map_error_suspected ? ::sarloc::RESPONDER_FLAG_MAP_ERROR_SUSPECTED : 0U) |
            (m.confirmed ? ::sarloc::RESPONDER_FLAG_CONFIRMED : 0U) |
            (m.ambiguous ? ::sarloc::RESPONDER_FLAG_AMBIGUOUS : 0U) |
            (signed_off ? ::sarloc::RESPONDER_FLAG_SIGNED_OFF : 0U));
    out.members().push_back(s);
  }
  return out;
}

incident::TeamStatus to_core(const ::sarloc::TeamStatus& t) {
  incident::TeamStatus out;
  out.team_id = from_identifier(t.team_id(), "team_status.team_id", true);
  out.stamp = t.stamp();
  for (const auto& s : t.members()) {
    incident::MemberStatus m;
    m.responder_id = from_identifier(s.responder_id(), "team_status.members.responder_id");
    m.last_position = to_core(s.last_position());
    m.last_seen = s.last_seen();
    m.link = checked_enum<incident::LinkState>(s.link(), ::sarloc::LINK_LOST, "team_status.members.link");
    if (m.link == incident::LinkState::kLost && (s.flags() & ::sarloc::RESPONDER_FLAG_SIGNED_OFF) != 0) {
      m.link = incident::LinkState::kSignedOff;
    }
    m.accountability = checked_enum<incident::AccountabilityState>(
        s.accountability(), ::sarloc::ACCOUNTABILITY_MISSING, "team_status.members.accountability");
    m.floor = s.floor();
    m.source = checked_enum<responder::PositionSource>(s.source(), ::sarloc::POSITION_MANUAL, "team_status.members.source");
    m.converged = (s.flags() & ::sarloc::RESPONDER_FLAG_CONVERGED) != 0;
    m.map_error_suspected = (s.flags() & ::sarloc::RESPONDER_FLAG_MAP_ERROR_SUSPECTED) != 0;
    m.confirmed = (s.flags() & ::sarloc::RESPONDER_FLAG_CONFIRMED) != 0;
    m.ambiguous = (s.flags() & ::sarloc::RESPONDER_FLAG_AMBIGUOUS) != 0;
    out.members.push_back(m);
  }
  return out;
}

::sarloc::ResponderAlarm to_idl(const responder::ResponderAlarm& a) {
  ::sarloc::ResponderAlarm out;
  out.responder_id(to_identifier(a.responder_id, "responder_alarm.responder_id"));
  out.kind(static_cast<::sarloc::AlarmKind>(a.kind));
  out.team_id(to_identifier(a.team_id, "responder_alarm.team_id"));
  out.raised_at(a.raised_at);
  out.cleared_at(a.cleared_at);
  out.active(a.active);
  out.position_known(a.position_known);
  out.last_position(to_idl(a.last_position));
  out.floor(a.floor);
  return out;
}

responder::ResponderAlarm to_core(const ::sarloc::ResponderAlarm& a) {
  responder::ResponderAlarm out;
  out.responder_id = from_identifier(a.responder_id(), "responder_alarm.responder_id");
  out.kind = checked_enum<responder::AlarmKind>(a.kind(), ::sarloc::ALARM_MAP_ERROR, "responder_alarm.kind");
  out.team_id = from_identifier(a.team_id(), "responder_alarm.team_id", true);
  out.raised_at = a.raised_at();
  out.cleared_at = a.cleared_at();
  out.active = a.active();
  out.position_known = a.position_known();
  out.last_position = to_core(a.last_position());
  out.floor = a.floor();
  return out;
}

::sarloc::IncidentAlarm to_idl(const incident::IncidentAlarm& a) {
  ::sarloc::IncidentAlarm out;
  out.alarm_id(a.alarm_id);
  out.responder_id(to_identifier(a.alarm.responder_id, "incident_alarm.responder_id"));
  out.team_id(to_identifier(a.alarm.team_id, "incident_alarm.team_id"));
  out.kind(static_cast<::sarloc::AlarmKind>(a.alarm.kind));
  out.raised_at(a.alarm.raised_at);
  out.cleared_at(a.alarm.cleared_at);
  out.active(a.alarm.active);
  out.acknowledged(a.acknowledged);
  out.acknowledged_by(to_identifier(a.acknowledged_by, "incident_alarm.acknowledged_by"));
  out.acknowledged_at(a.acknowledged_at);
  out.position_known(a.alarm.position_known);
  out.last_position(to_idl(a.alarm.last_position));
  out.floor(a.alarm.floor);
  return out;
}

incident::IncidentAlarm to_core(const ::sarloc::IncidentAlarm& a) {
  incident::IncidentAlarm out;
  out.alarm_id = a.alarm_id();
  out.alarm.responder_id = from_identifier(a.responder_id(), "incident_alarm.responder_id");
  out.alarm.team_id = from_identifier(a.team_id(), "incident_alarm.team_id", true);
  out.alarm.kind = checked_enum<responder::AlarmKind>(a.kind(), ::sarloc::ALARM_MAP_ERROR, "incident_alarm.kind");
  out.alarm.raised_at = a.raised_at();
  out.alarm.cleared_at = a.cleared_at();
  out.alarm.active = a.active();
  out.acknowledged = a.acknowledged();
  out.acknowledged_by = from_identifier(a.acknowledged_by(), "incident_alarm.acknowledged_by", true);
  out.acknowledged_at = a.acknowledged_at();
  out.alarm.position_known = a.position_known();
  out.alarm.last_position = to_core(a.last_position());
  out.alarm.floor = a.floor();
  return out;
}

::sarloc::IncidentFrame to_idl(const incident::IncidentFrame& f) {
  ::sarloc::IncidentFrame out;
  out.incident_id(f.incident_id);
  out.latitude_deg(f.origin.latitude_deg);
  out.longitude_deg(f.origin.longitude_deg);
  out.altitude_m(f.origin.altitude_m);
  out.name(f.name.substr(0, ::sarloc::TEXT_MAX));
  out.established(f.established);
  return out;
}

incident::IncidentFrame to_core(const ::sarloc::IncidentFrame& f) {
  incident::IncidentFrame out;
  out.incident_id = f.incident_id().to_string();
  out.origin.latitude_deg = f.latitude_deg();
  out.origin.longitude_deg = f.longitude_deg();
  out.origin.altitude_m = f.altitude_m();
  out.name = f.name().to_string();
  out.established = f.established();
  return out;
}

namespace {

using Vec2 = incident::Vec2;

::sarloc::PlanePoint plane_point(const Vec2& v) {
  ::sarloc::PlanePoint out;
  out.x(v.x());
  out.y(v.y());
  return out;
}

Vec2 plane_point(const ::sarloc::PlanePoint& p, const char* field) {
  const Vec2 v(p.x(), p.y());
  if (!v.allFinite()) throw InputError(std::string(field) + ": not finite");
  return v;
}

std::vector<::sarloc::PlanePoint> outline_to_idl(const std::vector<Vec2>& outline, const char* field) {
  if (outline.size() > ::sarloc::OUTLINE_POINTS_MAX)
    throw InputError(std::string(field) + ": " + std::to_string(outline.size()) + " points, at most " +
                     std::to_string(::sarloc::OUTLINE_POINTS_MAX));
  std::vector<::sarloc::PlanePoint> out;
  for (const auto& v : outline) out.push_back(plane_point(v));
  return out;
}

// A non-negative, finite count of minutes or metres (a dig's depth and times: at most a week).
double minutes_or_metres(double v, const char* field) {
  if (!(std::isfinite(v) && v >= 0.0 && v <= 10080.0))
    throw InputError(std::string(field) + " = " + std::to_string(v) + ": must be in [0, 10080]");
  return v;
}

double fraction(double f, const char* field) {
  if (!(f >= 0.0 && f <= 1.0)) throw InputError(std::string(field) + " = " + std::to_string(f) + ": must be in [0, 1]");
  return f;
}

}  // namespace

::sarloc::SearchPlan to_idl(const incident::SearchPlanPicture& p) {
  ::sarloc::SearchPlan out;
  out.incident_id(to_identifier(p.incident_id, "search_plan.incident_id"));
  out.stamp(p.stamp);
  out.revision(p.plan.revision);
  out.deposit(outline_to_idl(p.deposit, "search_plan.deposit"));
  if (p.plan.strips.size() > ::sarloc::SEARCH_STRIPS_MAX)
    throw InputError("search_plan.strips: " + std::to_string(p.plan.strips.size()) + " strips, at most " +
                     std::to_string(::sarloc::SEARCH_STRIPS_MAX));
  for (std::size_t i = 0; i < p.plan.strips.size(); ++i) {
    const auto& s = p.plan.strips[i];
    ::sarloc::SearchStrip strip;
    strip.strip_index(static_cast<std::uint32_t>(s.strip.index));
    strip.outline(outline_to_idl(s.strip.outline, "search_plan.strips.outline"));
    strip.top(plane_point(s.strip.top));
    strip.bottom(plane_point(s.strip.bottom));
    strip.width_m(s.strip.width_m);
    strip.searched_fraction(s.searched);
    strip.done(s.done);
    strip.rescuer_id(to_identifier(s.rescuer_id, "search_plan.strips.rescuer_id"));
    const bool has_next = i < p.next_points.size() && p.next_points[i].has_value();
    strip.has_next_point(has_next);
    if (has_next) strip.next_point(plane_point(*p.next_points[i]));
    strip.helper_id(to_identifier(s.helper_id, "search_plan.strips.helper_id"));
    const bool has_helper_next = i < p.helper_next_points.size() && p.helper_next_points[i].has_value();
    strip.has_helper_next_point(has_helper_next);
    if (has_helper_next) strip.helper_next_point(plane_point(*p.helper_next_points[i]));
    out.strips().push_back(strip);
  }
  out.searched_fraction(p.plan.searched);
  if (p.handed_over.size() > ::sarloc::SEARCH_HANDOVERS_MAX)
    throw InputError("search_plan.handed_over: " + std::to_string(p.handed_over.size()) + " hand-overs, at most " +
                     std::to_string(::sarloc::SEARCH_HANDOVERS_MAX));
  for (const auto& h : p.handed_over) {
    ::sarloc::SignalHandOver m;
    m.rescuer_id(to_identifier(h.rescuer_id, "search_plan.handed_over.rescuer_id"));
    m.signal_id(h.signal_id);
    m.victim_id(h.victim_id);
    m.pursued_by(to_identifier(h.pursued_by, "search_plan.handed_over.pursued_by"));
    out.handed_over().push_back(m);
  }
  if (p.digs.digs.size() > ::sarloc::SEARCH_DIGS_MAX)
    throw InputError("search_plan.digs: " + std::to_string(p.digs.digs.size()) + " digs, at most " +
                     std::to_string(::sarloc::SEARCH_DIGS_MAX));
  for (const auto& d : p.digs.digs) {
    ::sarloc::VictimDig m;
    m.victim_id(d.victim_id);
    m.depth_m(d.depth_m);
    m.buried_min(d.buried_min);
    m.start_min(d.start_min);
    m.done_min(d.done_min);
    m.survival(d.survival);
    m.digger_id(to_identifier(d.digger_id, "search_plan.digs.digger_id"));
    out.digs().push_back(m);
  }
  out.expected_survivors(p.digs.expected_survivors);
  out.incident_start(p.incident_start);
  return out;
}

incident::SearchPlanPicture to_core(const ::sarloc::SearchPlan& p) {
  incident::SearchPlanPicture out;
  out.incident_id = from_identifier(p.incident_id(), "search_plan.incident_id");
  out.stamp = p.stamp();
  out.plan.revision = p.revision();
  for (const auto& v : p.deposit()) out.deposit.push_back(plane_point(v, "search_plan.deposit"));
  for (const auto& s : p.strips()) {
    incident::PlannedStrip strip;
    strip.strip.index = s.strip_index();
    for (const auto& v : s.outline()) strip.strip.outline.push_back(plane_point(v, "search_plan.strips.outline"));
    strip.strip.top = plane_point(s.top(), "search_plan.strips.top");
    strip.strip.bottom = plane_point(s.bottom(), "search_plan.strips.bottom");
    strip.strip.width_m = s.width_m();
    if (!(std::isfinite(strip.strip.width_m) && strip.strip.width_m > 0.0))
      throw InputError("search_plan.strips.width_m: not a positive number");
    strip.searched = fraction(s.searched_fraction(), "search_plan.strips.searched_fraction");
    strip.done = s.done();
    strip.rescuer_id = from_identifier(s.rescuer_id(), "search_plan.strips.rescuer_id", true);
    out.next_points.push_back(s.has_next_point()
                                  ? std::optional<Vec2>(plane_point(s.next_point(), "search_plan.strips.next_point"))
                                  : std::nullopt);
    strip.helper_id = from_identifier(s.helper_id(), "search_plan.strips.helper_id", true);
    out.helper_next_points.push_back(
        s.has_helper_next_point()
            ? std::optional<Vec2>(plane_point(s.helper_next_point(), "search_plan.strips.helper_next_point"))
            : std::nullopt);
    out.plan.strips.push_back(std::move(strip));
  }
  out.plan.searched = fraction(p.searched_fraction(), "search_plan.searched_fraction");
  for (const auto& h : p.handed_over()) {
    out.handed_over.push_back({from_identifier(h.rescuer_id(), "search_plan.handed_over.rescuer_id"), h.signal_id(),
                               h.victim_id(), from_identifier(h.pursued_by(), "search_plan.handed_over.pursued_by")});
  }
  for (const auto& d : p.digs()) {
    incident::VictimDig dig;
    dig.victim_id = d.victim_id();
    dig.depth_m = minutes_or_metres(d.depth_m(), "search_plan.digs.depth_m");
    dig.buried_min = minutes_or_metres(d.buried_min(), "search_plan.digs.buried_min");
    dig.start_min = minutes_or_metres(d.start_min(), "search_plan.digs.start_min");
    dig.done_min = minutes_or_metres(d.done_min(), "search_plan.digs.done_min");
    dig.survival = fraction(d.survival(), "search_plan.digs.survival");
    dig.digger_id = from_identifier(d.digger_id(), "search_plan.digs.digger_id", true);
    out.digs.digs.push_back(std::move(dig));
  }
  out.digs.expected_survivors = minutes_or_metres(p.expected_survivors(), "search_plan.expected_survivors");
  out.incident_start = p.incident_start();
  return out;
}

namespace {

// fastddsgen keys of at most 16 bytes are the big-endian CDR of the key: a 32-bit id first.
// Checked by computing the handle of that id again.
template <class Type, class PubSubType>
std::optional<std::uint32_t> id_key_of(const eprosima::fastrtps::rtps::InstanceHandle_t& instance,
                                       void (Type::*set_id)(std::uint32_t)) {
  std::uint32_t id = 0;
  for (std::size_t i = 0; i < 4; ++i) id = (id << 8) | instance.value[i];
  Type key;
  (key.*set_id)(id);
  PubSubType type;
  eprosima::fastrtps::rtps::InstanceHandle_t expected;
  if (!type.getKey(&key, &expected)) return std::nullopt;
  for (std::size_t i = 0; i < 16; ++i) {
    if (expected.value[i] != instance.value[i]) return std::nullopt;
  }
  return id;
}

}  // namespace

std::optional<std::uint32_t> victim_id_of(const eprosima::fastrtps::rtps::InstanceHandle_t& instance) {
  return id_key_of<::sarloc::FusedVictim, ::sarloc::FusedVictimPubSubType>(instance, &::sarloc::FusedVictim::victim_id);
}

std::optional<std::uint32_t> alarm_id_of(const eprosima::fastrtps::rtps::InstanceHandle_t& instance) {
  return id_key_of<::sarloc::IncidentAlarm, ::sarloc::IncidentAlarmPubSubType>(instance,
                                                                                &::sarloc::IncidentAlarm::alarm_id);
}

}  // namespace sarloc::dds
