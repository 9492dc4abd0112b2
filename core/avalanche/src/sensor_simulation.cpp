#include "sarloc/core/avalanche/sensor_simulation.hpp"

#include <algorithm>
#include <cmath>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/avalanche/rotation.hpp"

namespace sarloc::avalanche {
namespace {


}  // namespace

Vec3 normal3(std::mt19937_64& rng) {
  std::normal_distribution<double> n01(0.0, 1.0);
  const double x = n01(rng);
  const double y = n01(rng);
  const double z = n01(rng);
  return Vec3(x, y, z);
}

double draw_burial_depth(const SimulationConfig& config, std::mt19937_64& rng, std::normal_distribution<double>& n01) {
  constexpr double kZ975 = 1.959963984540054;  // the standard normal's 97.5 % quantile
  return std::max(config.min_burial_depth_m, std::fabs(n01(rng)) * config.burial_depth_p95_m / kZ975);
}

Vec3 draw_moment(const SimulationConfig& config, std::mt19937_64& rng, std::uniform_real_distribution<double>& u01) {
  Vec3 dir = normal3(rng);
  while (dir.norm() < 1e-9) dir = normal3(rng);
  const double magnitude =
      config.standard.moment_min() + (config.standard.moment_max() - config.standard.moment_min()) * u01(rng);
  return magnitude * dir.normalized();
}

Vec3 simulate_field(const SimulationConfig& config, const ReceiverPose& receiver, const Vec3& transmitter,
                    const Vec3& moment, std::mt19937_64& rng) {
  const Vec3 h_world = DipoleField::field(receiver.position - transmitter, moment);
  const double sigma = config.field_noise().sigma(h_world.norm());
  const Mat3 r_world = rotation_from_rpy(receiver.rpy);
  return r_world.transpose() * h_world + sigma * normal3(rng);
}

OrientationObservation simulate_attitude(const SimulationConfig& config, const ReceiverPose& receiver,
                                         std::mt19937_64& rng) {
  const double s_rp = config.attitude_roll_pitch_sigma_deg * kDeg;
  const double s_y = config.attitude_yaw_sigma_deg * kDeg;
  OrientationObservation o;
  o.rpy = receiver.rpy + Vec3(s_rp, s_rp, s_y).cwiseProduct(normal3(rng));
  o.rpy.z() = wrap_angle(o.rpy.z());
  o.covariance = Vec3(s_rp * s_rp, s_rp * s_rp, s_y * s_y).asDiagonal();
  return o;
}

Odometry simulate_step(const SimulationConfig& config, ReceiverPose& receiver, double bearing_rad, double step_m,
                       std::mt19937_64& rng) {
  const Mat3 r_prev = rotation_from_rpy(receiver.rpy);
  const double heading = wrap_angle(receiver.rpy.z() + bearing_rad);
  const Vec3 delta(step_m * std::cos(heading), step_m * std::sin(heading), 0.0);
  receiver.position += delta;
  const double sway = config.sway_roll_pitch_deg * kDeg;
  const Vec3 sway_draw = normal3(rng);  // roll, pitch (the third draw keeps the stream in threes)
  receiver.rpy = Vec3(sway * sway_draw.x(), sway * sway_draw.y(), heading);
  const Mat3 r_now = rotation_from_rpy(receiver.rpy);
  const Vec3 t_true = r_prev.transpose() * delta;
  const Vec3 rot_true = rpy_from_rotation(r_prev.transpose() * r_now);

  const double s_rp = config.odometry_roll_pitch_sigma_deg * kDeg;
  const double s_y = config.odometry_yaw_sigma_deg * kDeg;
  const double s_t = std::max(config.odometry_translation_relative * t_true.norm(), config.odometry_translation_floor_m);
  Odometry o;
  o.translation = t_true + s_t * normal3(rng);
  o.rotation_rpy = rot_true + Vec3(s_rp, s_rp, s_y).cwiseProduct(normal3(rng));
  for (int k = 0; k < 3; ++k) o.rotation_rpy[k] = wrap_angle(o.rotation_rpy[k]);
  o.covariance.setZero();
  o.covariance.diagonal() << s_t * s_t, s_t * s_t, s_t * s_t, s_rp * s_rp, s_rp * s_rp, s_y * s_y;
  o.source = OdometrySource::kSimulated;
  return o;
}

}  // namespace sarloc::avalanche
