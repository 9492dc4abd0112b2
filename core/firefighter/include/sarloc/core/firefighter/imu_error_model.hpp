#pragma once
// Error model of a consumer MEMS IMU of the class seed 004 used (Xsens MTi-3, section V-A).
// Per axis: white noise (noise density), in-run bias instability (a first-order Gauss-Markov
// process whose stationary sigma is the datasheet's in-run bias stability), a turn-on bias drawn
// once per power-up, and a scale-factor error drawn once. docs/estimation/firefighter.md
// gives the sources: noise density and in-run stability are the Xsens MTi 1-series datasheet's;
// turn-on bias and scale factor are not in it and are this project's assumptions for the class.
//
//   ImuErrors errors(ImuErrorConfig{}, rng);        // draws turn-on bias and scale factors
//   ImuSample measured = errors.apply(ideal, rng);   // one 100 Hz sample
#include <random>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/firefighter/imu_sample.hpp"

namespace sarloc::firefighter {

struct ImuErrorConfig {
  double rate_hz = 100.0;
  // Accelerometer (MTi 1-series: 120 ug/sqrt(Hz), in-run bias stability 0.03 mg).
  double accel_noise_density = 120e-6 * kGravity;      ///< m/s^2/sqrt(Hz)
  double accel_bias_instability = 0.03e-3 * kGravity;  ///< m/s^2
  double accel_turn_on_bias = 5e-3 * kGravity;         ///< m/s^2, 1 sigma (assumed)
  double accel_scale_factor = 2e-3;                    ///< 1 sigma, fraction (assumed)
  // Gyroscope (MTi 1-series: 0.007 deg/s/sqrt(Hz), in-run bias stability 10 deg/h).
  double gyro_noise_density = 0.007 * kPi / 180.0;      ///< rad/s/sqrt(Hz)
  double gyro_bias_instability = 10.0 / 3600.0 * kPi / 180.0;  ///< rad/s
  double gyro_turn_on_bias = 0.2 * kPi / 180.0;         ///< rad/s, 1 sigma (assumed)
  double gyro_scale_factor = 1e-3;                                   ///< 1 sigma (assumed)
  double bias_correlation_time_s = 100.0;  ///< of the Gauss-Markov in-run bias
  void validate() const;
};

class ImuErrors {
 public:
  ImuErrors(const ImuErrorConfig& config, std::mt19937_64& rng);
  ImuSample apply(const ImuSample& ideal, std::mt19937_64& rng);

  const Eigen::Vector3d& accel_bias() const { return accel_bias_; }
  const Eigen::Vector3d& gyro_bias() const { return gyro_bias_; }

 private:
  ImuErrorConfig config_;
  Eigen::Vector3d accel_turn_on_, gyro_turn_on_, accel_scale_, gyro_scale_;
  Eigen::Vector3d accel_drift_ = Eigen::Vector3d::Zero(), gyro_drift_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_bias_, gyro_bias_;
};

}  // namespace sarloc::firefighter
