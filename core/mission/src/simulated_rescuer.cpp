#include "sarloc/core/mission/simulated_rescuer.hpp"

#include "sarloc/core/avalanche/dipole_model.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace sarloc::mission {

SimulatedRescuer::SimulatedRescuer(const MissionScenario& scenario, const std::string& rescuer_id)
    : scenario_(scenario),
      spec_(scenario.rescuers.at(scenario.rescuer_index(rescuer_id))),
      rng_(derive_seed(scenario.seed, scenario.rescuer_index(rescuer_id))),
      switched_off_(scenario.victims.size(), false) {
  pose_.position = Vec3(spec_.start.x(), spec_.start.y(), scenario.sensors.antenna_height_m);
  pose_.rpy = Vec3(0.0, 0.0, spec_.heading_deg * kPi / 180.0);
  if (scenario.sensors.receiver.kind != avalanche::ReceiverKind::kRealistic) return;
  // The transmitters are the victims': every rescuer hears the same timing (from the mission
  // seed), each through its own device (hardware errors and noise from its own seed).
  for (std::size_t v = 0; v < scenario.victims.size(); ++v) {
    const VictimSpec& victim = scenario.victims[v];
    std::mt19937_64 timing_rng(derive_seed(scenario.seed, 0xBEAC0000ULL + v));
    avalanche::Beacon b;
    b.position = victim.position;
    b.moment = victim.moment;
    b.timing = avalanche::TransmitterTiming::draw(scenario.sensors.receiver, timing_rng);
    if (victim.period_ms) b.timing.period_s = 1e-3 * *victim.period_ms;
    if (victim.carrier_offset_hz) b.timing.carrier_offset_hz = *victim.carrier_offset_hz;
    beacons_.push_back(b);
  }
  receiver_.emplace(scenario.sensors,
                    derive_seed(scenario.seed, 0x5EED0000ULL + scenario.rescuer_index(rescuer_id)));
}

std::vector<avalanche::FieldMeasurement> SimulatedRescuer::measure(TimestampNs stamp) {
  ++measurement_sequence_;
  const auto attitude = avalanche::simulate_attitude(scenario_.sensors, pose_, rng_);
  if (!receiver_) return measure_ideal(stamp, attitude);
  constexpr double kNsPerS = 1e9;
  const double window_s =
      last_listened_ ? std::clamp(static_cast<double>(stamp - *last_listened_) / kNsPerS, 0.1, 2.0) : 1.0;
  last_listened_ = stamp;
  const avalanche::Listening heard =
      receiver_->listen(pose_, beacons_, static_cast<double>(stamp) / kNsPerS - window_s, window_s);
  wrong_attributions_ += heard.wrong_attributions;
  std::optional<avalanche::OrientationObservation> orientation;
  if (scenario_.sensors.attitude_updates || measurement_sequence_ == 1) orientation = attitude;
  // One epoch, one sequence number across signals.
  return avalanche::to_measurements(heard, spec_.id, measurement_sequence_, stamp, orientation);
}

std::vector<avalanche::FieldMeasurement> SimulatedRescuer::measure_ideal(
    TimestampNs stamp, const avalanche::OrientationObservation& attitude) {
  std::vector<avalanche::FieldMeasurement> out;
  for (std::size_t v = 0; v < scenario_.victims.size(); ++v) {
    const auto& victim = scenario_.victims[v];
    if (switched_off_[v] || (victim.position - pose_.position).norm() > scenario_.detection_range_m) continue;
    auto it = signal_of_victim_.find(v);
    if (it == signal_of_victim_.end()) {
      it = signal_of_victim_.emplace(v, static_cast<std::uint32_t>(signal_of_victim_.size() + 1)).first;
    }
    avalanche::FieldMeasurement m;
    m.rescuer_id = spec_.id;
    m.signal_id = it->second;
    m.sequence = measurement_sequence_;  // one epoch, one sequence number across signals
    m.stamp = stamp;
    m.field = avalanche::simulate_field(scenario_.sensors, pose_, victim.position, victim.moment, rng_);
    m.noise_stddev = Vec3::Constant(scenario_.sensors.field_noise_floor_A_per_m);
    if (scenario_.sensors.attitude_updates || measurement_sequence_ == 1) m.orientation = attitude;
    out.push_back(m);
  }
  return out;
}

responder::Odometry SimulatedRescuer::walk(double bearing_rad, double step_m, TimestampNs start, TimestampNs end) {
  const Vec3 before = pose_.position;
  responder::Odometry o = avalanche::simulate_step(scenario_.sensors, pose_, bearing_rad, step_m, rng_);
  walked_m_ += (pose_.position - before).norm();
  o.rescuer_id = spec_.id;
  o.sequence = ++odometry_sequence_;
  o.interval_start = start;
  o.interval_end = end;
  return o;
}

responder::ResponderPosition SimulatedRescuer::gnss(TimestampNs stamp) {
  const double s = scenario_.gnss_sigma_m;
  const Vec3 sigma(s, s, 2.0 * s);
  const Vec3 draw = avalanche::normal3(rng_);
  if (!last_fix_) {
    gnss_bias_ = sigma.cwiseProduct(draw);  // stationary from the first fix on
  } else {
    // First-order Gauss-Markov: keeps variance sigma^2 whatever the fix rate.
    const double dt = static_cast<double>(stamp - *last_fix_) * 1e-9;
    const double phi = std::exp(-std::max(dt, 0.0) / scenario_.gnss_correlation_s);
    gnss_bias_ = phi * gnss_bias_ + std::sqrt(1.0 - phi * phi) * sigma.cwiseProduct(draw);
  }
  last_fix_ = stamp;
  const double w = scenario_.gnss_white_sigma_m;
  responder::ResponderPosition p;
  p.responder_id = spec_.id;
  p.team_id = spec_.team;
  p.stamp = stamp;
  p.position.position = pose_.position + gnss_bias_ + w * avalanche::normal3(rng_);
  p.position.covariance = (sigma.cwiseAbs2() + Vec3::Constant(w * w)).asDiagonal();
  p.heading_rad = pose_.rpy.z();
  p.source = responder::PositionSource::kGnss;
  p.converged = true;
  return p;
}

void SimulatedRescuer::set_consistency(avalanche::FieldConsistency consistency) {
  if (receiver_) receiver_->separator().set_consistency(std::move(consistency));
}

std::optional<std::size_t> SimulatedRescuer::switch_off_transmitter_near(const Vec3& where, double radius_m) {
  std::optional<std::size_t> nearest;
  double best = radius_m;
  for (std::size_t v = 0; v < scenario_.victims.size(); ++v) {
    const double d = (scenario_.victims[v].position - where).norm();
    if (!switched_off_[v] && d <= best) {
      best = d;
      nearest = v;
    }
  }
  if (!nearest) return std::nullopt;
  switch_off_transmitter(*nearest);
  return nearest;
}

bool SimulatedRescuer::switch_off_transmitter(std::size_t index) {
  if (index >= switched_off_.size() || switched_off_[index]) return false;
  switched_off_[index] = true;
  if (receiver_) beacons_[index].transmitting = false;
  return true;
}

std::optional<std::size_t> SimulatedRescuer::victim_of_signal(std::uint32_t signal_id) const {
  if (receiver_) return receiver_->majority_beacon_of_signal(signal_id);
  for (const auto& [victim, signal] : signal_of_victim_) {
    if (signal == signal_id) return victim;
  }
  return std::nullopt;
}

}  // namespace sarloc::mission
