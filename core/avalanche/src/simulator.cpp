#include "sarloc/core/avalanche/simulator.hpp"

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/avalanche/sensor_simulation.hpp"

#include "sarloc/core/avalanche/beacon_receiver.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::avalanche {
namespace {


void check(const char* key, double v, double lo, double hi, const char* why = nullptr) {
  require(std::isfinite(v) && v >= lo && v <= hi, std::string("simulation.") + key, v,
          "must be in [" + config_value(lo) + ", " + config_value(hi) + "]" +
              (why != nullptr ? std::string(" (") + why + ")" : std::string()));
}

Scenario draw_scenario(const SimulationConfig& c, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> n01(0.0, 1.0);
  Scenario s;
  const double dist = c.start_distance_min_m + (c.start_distance_max_m - c.start_distance_min_m) * u01(rng);
  const double az = 2.0 * kPi * u01(rng);
  const double depth = draw_burial_depth(c, rng, n01);
  s.transmitter = Vec3(dist * std::cos(az), dist * std::sin(az), -depth);
  s.moment = draw_moment(c, rng, u01);
  s.receiver = Vec3(0.0, 0.0, c.antenna_height_m);
  const double sway_roll = c.sway_roll_pitch_deg * kDeg * n01(rng);
  const double sway_pitch = c.sway_roll_pitch_deg * kDeg * n01(rng);
  const double heading = wrap_angle(2.0 * kPi * u01(rng));
  s.receiver_rpy = Vec3(sway_roll, sway_pitch, heading);
  return s;
}

}  // namespace

void SimulationConfig::validate() const {
  check("start_distance_min_m", start_distance_min_m, 1.0, 200.0);
  check("start_distance_max_m", start_distance_max_m, start_distance_min_m, 200.0,
        "must be >= start_distance_min_m");
  check("burial_depth_p95_m", burial_depth_p95_m, 0.0, 20.0);
  check("min_burial_depth_m", min_burial_depth_m, 0.0, 20.0);
  check("antenna_height_m", antenna_height_m, 0.1, 10.0);
  standard.validate("simulation.standard");
  check("field_noise_relative", field_noise_relative, 0.05, 1.0, "issue minimum 5 % per axis");
  const double min_floor = standard.strongest_on_axis_field(60.0) / 10.0;
  check("field_noise_floor_A_per_m", field_noise_floor_A_per_m, min_floor, 1e-3,
        "SNR of the strongest transmitter on-axis at 60 m must be <= 10");
  check("odometry_translation_relative", odometry_translation_relative, 0.03, 1.0,
        "issue minimum 3 % of the step");
  check("odometry_translation_floor_m", odometry_translation_floor_m, 1e-4, 1.0);
  check("odometry_yaw_sigma_deg", odometry_yaw_sigma_deg, 1.0, 90.0, "issue minimum 1 deg");
  check("odometry_roll_pitch_sigma_deg", odometry_roll_pitch_sigma_deg, 0.5, 90.0,
        "issue minimum 0.5 deg");
  check("sway_roll_pitch_deg", sway_roll_pitch_deg, 0.0, 30.0);
  check("attitude_roll_pitch_sigma_deg", attitude_roll_pitch_sigma_deg, 0.01, 90.0);
  check("attitude_yaw_sigma_deg", attitude_yaw_sigma_deg, 0.01, 180.0);
  check("primary_strip_half_width_m", primary_strip_half_width_m, 0.0, 100.0);
  receiver.validate();
}

AvalancheSimulator::AvalancheSimulator(SimulationConfig config, std::uint64_t seed)
    : config_((config.validate(), config)), rng_(seed) {
  scenario_ = draw_scenario(config_, rng_);
  if (config_.receiver.kind != ReceiverKind::kRealistic) return;
  // Its own stream: the ideal receiver's trials stay exactly what they were.
  std::mt19937_64 rng(derive_seed(seed, 0xBEAC0));
  receiver_ = std::make_unique<BeaconReceiver>(config_, derive_seed(seed, 0xBEAC1));
  beacons_.push_back({scenario_.transmitter, scenario_.moment, TransmitterTiming::draw(config_.receiver, rng)});
  // Walking a strip of the primary search: the line passes within the half width of the victim.
  std::uniform_real_distribution<double> lateral(-config_.primary_strip_half_width_m, config_.primary_strip_half_width_m);
  const Vec3 to_victim = scenario_.transmitter - scenario_.receiver;
  const double d = to_victim.head<2>().norm();
  const double offset = std::asin(std::clamp(lateral(rng) / d, -1.0, 1.0));
  scenario_.receiver_rpy.z() = wrap_angle(std::atan2(to_victim.y(), to_victim.x()) + offset);
}

AvalancheSimulator::AvalancheSimulator(SimulationConfig config, Scenario scenario, std::uint64_t seed)
    : config_((config.validate(), config)), scenario_(scenario), rng_(seed) {
  if (config_.receiver.kind != ReceiverKind::kRealistic) return;
  std::mt19937_64 rng(derive_seed(seed, 0xBEAC0));
  receiver_ = std::make_unique<BeaconReceiver>(config_, derive_seed(seed, 0xBEAC1));
  beacons_.push_back({scenario_.transmitter, scenario_.moment, TransmitterTiming::draw(config_.receiver, rng)});
}

AvalancheSimulator::~AvalancheSimulator() = default;
AvalancheSimulator::AvalancheSimulator(AvalancheSimulator&&) noexcept = default;

std::vector<FieldMeasurement> AvalancheSimulator::listen() {
  if (!receiver_) return {};
  const ReceiverPose pose{scenario_.receiver, scenario_.receiver_rpy};
  const Listening heard = receiver_->listen(pose, beacons_, static_cast<double>(stamp_) * 1e-9, 1.0);
  wrong_attributions_ += heard.wrong_attributions;
  ++sequence_;
  std::optional<OrientationObservation> attitude;
  if (sequence_ == 1 || config_.attitude_updates) attitude = simulate_attitude(config_, pose, rng_);
  return to_measurements(heard, "sim", sequence_, stamp_, attitude);
}


FieldMeasurement AvalancheSimulator::measure() {
  const ReceiverPose pose{scenario_.receiver, scenario_.receiver_rpy};
  FieldMeasurement m;
  m.rescuer_id = "sim";
  m.signal_id = 1;
  m.sequence = ++sequence_;
  m.stamp = stamp_;
  m.field = simulate_field(config_, pose, scenario_.transmitter, scenario_.moment, rng_);
  m.noise_stddev = Vec3::Constant(config_.field_noise_floor_A_per_m);  // the device knows its additive floor
  if (sequence_ == 1 || config_.attitude_updates) m.orientation = simulate_attitude(config_, pose, rng_);
  return m;
}

Odometry AvalancheSimulator::walk(double bearing_rad, double step_m) {
  ReceiverPose pose{scenario_.receiver, scenario_.receiver_rpy};
  Odometry o = simulate_step(config_, pose, bearing_rad, step_m, rng_);
  scenario_.receiver = pose.position;
  scenario_.receiver_rpy = pose.rpy;
  o.rescuer_id = "sim";
  o.sequence = ++odo_sequence_;
  o.interval_start = stamp_;
  stamp_ += 1'000'000'000;  // one measurement per second
  o.interval_end = stamp_;
  return o;
}

}  // namespace sarloc::avalanche
