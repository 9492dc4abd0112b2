#include "sarloc/core/avalanche/simulator.hpp"

#include <cmath>
#include <sstream>

#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/common/errors.hpp"

namespace sarloc::avalanche {
namespace {

constexpr double kDeg = kPi / 180.0;

void check(const char* key, double v, double lo, double hi, const char* why = nullptr) {
  if (!std::isfinite(v) || v < lo || v > hi) {
    std::ostringstream os;
    os << "simulation." << key << " = " << v << ": must be in [" << lo << ", " << hi << "]";
    if (why != nullptr) os << " (" << why << ")";
    throw ConfigError(os.str());
  }
}

Scenario draw_scenario(const SimulationConfig& c, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> n01(0.0, 1.0);
  Scenario s;
  const double dist = c.start_distance_min_m + (c.start_distance_max_m - c.start_distance_min_m) * u01(rng);
  const double az = 2.0 * kPi * u01(rng);
  const double depth =
      std::max(c.min_burial_depth_m, std::fabs(n01(rng)) * c.burial_depth_p95_m / 1.959963984540054);
  s.transmitter = Vec3(dist * std::cos(az), dist * std::sin(az), -depth);
  Vec3 dir(n01(rng), n01(rng), n01(rng));
  while (dir.norm() < 1e-9) dir = Vec3(n01(rng), n01(rng), n01(rng));
  const double mag = c.standard.moment_min() + (c.standard.moment_max() - c.standard.moment_min()) * u01(rng);
  s.moment = mag * dir.normalized();
  s.receiver = Vec3(0.0, 0.0, c.antenna_height_m);
  s.receiver_rpy = Vec3(c.sway_roll_pitch_deg * kDeg * n01(rng), c.sway_roll_pitch_deg * kDeg * n01(rng),
                        wrap_angle(2.0 * kPi * u01(rng)));
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
}

std::uint64_t derive_seed(std::uint64_t seed, std::uint64_t index) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (index + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

AvalancheSimulator::AvalancheSimulator(SimulationConfig config, std::uint64_t seed)
    : config_((config.validate(), config)), rng_(seed) {
  scenario_ = draw_scenario(config_, rng_);
}

AvalancheSimulator::AvalancheSimulator(SimulationConfig config, Scenario scenario, std::uint64_t seed)
    : config_((config.validate(), config)), scenario_(scenario), rng_(seed) {}

FieldMeasurement AvalancheSimulator::measure() {
  std::normal_distribution<double> n01(0.0, 1.0);
  const Vec3 r = scenario_.receiver - scenario_.transmitter;
  const Vec3 h_g = DipoleField::field(r, scenario_.moment);
  const Mat3 r_w = rotation_from_rpy(scenario_.receiver_rpy);
  const double floor = config_.field_noise_floor_A_per_m;
  const double sigma = config_.field_noise_relative * h_g.norm() + floor;
  FieldMeasurement m;
  m.rescuer_id = "sim";
  m.signal_id = 1;
  m.sequence = ++sequence_;
  m.stamp = stamp_;
  m.field = r_w.transpose() * h_g + sigma * Vec3(n01(rng_), n01(rng_), n01(rng_));
  m.noise_stddev = Vec3::Constant(floor);  // the device knows its additive floor
  if (sequence_ == 1 || config_.attitude_updates) {
    OrientationObservation o;
    const double srp = config_.attitude_roll_pitch_sigma_deg * kDeg;
    const double sy = config_.attitude_yaw_sigma_deg * kDeg;
    o.rpy = scenario_.receiver_rpy + Vec3(srp * n01(rng_), srp * n01(rng_), sy * n01(rng_));
    o.rpy.z() = wrap_angle(o.rpy.z());
    o.covariance = Vec3(srp * srp, srp * srp, sy * sy).asDiagonal();
    m.orientation = o;
  }
  return m;
}

Odometry AvalancheSimulator::walk(double bearing_rad, double step_m) {
  std::normal_distribution<double> n01(0.0, 1.0);
  const Mat3 r_prev = rotation_from_rpy(scenario_.receiver_rpy);
  const double heading = wrap_angle(scenario_.receiver_rpy.z() + bearing_rad);
  const Vec3 delta(step_m * std::cos(heading), step_m * std::sin(heading), 0.0);
  scenario_.receiver += delta;
  const double sway = config_.sway_roll_pitch_deg * kDeg;
  scenario_.receiver_rpy = Vec3(sway * n01(rng_), sway * n01(rng_), heading);
  const Mat3 r_now = rotation_from_rpy(scenario_.receiver_rpy);
  const Vec3 t_true = r_prev.transpose() * delta;
  const Vec3 rot_true = rpy_from_rotation(r_prev.transpose() * r_now);

  const double s_rp = config_.odometry_roll_pitch_sigma_deg * kDeg;
  const double s_y = config_.odometry_yaw_sigma_deg * kDeg;
  const double s_t = std::max(config_.odometry_translation_relative * t_true.norm(),
                              config_.odometry_translation_floor_m);
  Odometry o;
  o.rescuer_id = "sim";
  o.sequence = ++odo_sequence_;
  o.interval_start = stamp_;
  stamp_ += 1'000'000'000;  // one measurement per second
  o.interval_end = stamp_;
  o.translation = t_true + s_t * Vec3(n01(rng_), n01(rng_), n01(rng_));
  o.rotation_rpy = rot_true + Vec3(s_rp * n01(rng_), s_rp * n01(rng_), s_y * n01(rng_));
  for (int k = 0; k < 3; ++k) o.rotation_rpy[k] = wrap_angle(o.rotation_rpy[k]);
  o.covariance.setZero();
  o.covariance.diagonal() << s_t * s_t, s_t * s_t, s_t * s_t, s_rp * s_rp, s_rp * s_rp, s_y * s_y;
  o.source = OdometrySource::kSimulated;
  return o;
}

}  // namespace sarloc::avalanche
