#include "sarloc/core/firefighter/imu_error_model.hpp"

#include <cmath>
#include <string>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::firefighter {
namespace {

Eigen::Vector3d gaussian3(std::mt19937_64& rng, double sigma) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Vector3d(n(rng), n(rng), n(rng)) * sigma;
}

}  // namespace

void ImuErrorConfig::validate() const {
  auto check = [](const char* key, double v, double lo, double hi) { check_range("imu", key, v, lo, hi); };
  check("rate_hz", rate_hz, 20.0, 2000.0);
  check("accel_noise_density", accel_noise_density, 0.0, 1.0);
  check("accel_bias_instability", accel_bias_instability, 0.0, 1.0);
  check("accel_turn_on_bias", accel_turn_on_bias, 0.0, 1.0);
  check("accel_scale_factor", accel_scale_factor, 0.0, 0.1);
  check("gyro_noise_density", gyro_noise_density, 0.0, 0.1);
  check("gyro_bias_instability", gyro_bias_instability, 0.0, 0.1);
  check("gyro_turn_on_bias", gyro_turn_on_bias, 0.0, 0.5);
  check("gyro_scale_factor", gyro_scale_factor, 0.0, 0.1);
  check("bias_correlation_time_s", bias_correlation_time_s, 1.0, 1e5);
}

ImuErrors::ImuErrors(const ImuErrorConfig& config, std::mt19937_64& rng) : config_(config) {
  config_.validate();
  accel_turn_on_ = gaussian3(rng, config_.accel_turn_on_bias);
  gyro_turn_on_ = gaussian3(rng, config_.gyro_turn_on_bias);
  accel_scale_ = gaussian3(rng, config_.accel_scale_factor);
  gyro_scale_ = gaussian3(rng, config_.gyro_scale_factor);
  // The in-run part starts from its stationary distribution.
  accel_drift_ = gaussian3(rng, config_.accel_bias_instability);
  gyro_drift_ = gaussian3(rng, config_.gyro_bias_instability);
  accel_bias_ = accel_turn_on_ + accel_drift_;
  gyro_bias_ = gyro_turn_on_ + gyro_drift_;
}

ImuSample ImuErrors::apply(const ImuSample& ideal, std::mt19937_64& rng) {
  const double dt = 1.0 / config_.rate_hz;
  // Gauss-Markov: x <- phi x + sqrt(1 - phi^2) sigma n keeps the stationary sigma.
  const double phi = std::exp(-dt / config_.bias_correlation_time_s);
  const double keep = std::sqrt(1.0 - phi * phi);
  accel_drift_ = phi * accel_drift_ + gaussian3(rng, keep * config_.accel_bias_instability);
  gyro_drift_ = phi * gyro_drift_ + gaussian3(rng, keep * config_.gyro_bias_instability);
  accel_bias_ = accel_turn_on_ + accel_drift_;
  gyro_bias_ = gyro_turn_on_ + gyro_drift_;
  // White noise: density * sqrt(rate) per sample.
  const double sqrt_rate = std::sqrt(config_.rate_hz);
  ImuSample out = ideal;
  out.specific_force = ideal.specific_force.cwiseProduct(Eigen::Vector3d::Ones() + accel_scale_) + accel_bias_ +
                       gaussian3(rng, config_.accel_noise_density * sqrt_rate);
  out.angular_rate = ideal.angular_rate.cwiseProduct(Eigen::Vector3d::Ones() + gyro_scale_) + gyro_bias_ +
                     gaussian3(rng, config_.gyro_noise_density * sqrt_rate);
  return out;
}

}  // namespace sarloc::firefighter
