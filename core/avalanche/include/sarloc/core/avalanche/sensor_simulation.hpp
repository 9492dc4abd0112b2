#pragma once
// The simulated sensors of a rescuer's device, one sample at a time: the 3-axis receiver, the
// attitude sensor and the odometry, with the noise model of SimulationConfig (simulator.hpp
// documents every default). Shared by the single-victim evaluation simulator and the
// multi-victim mission world, so both measure exactly the same way.
#include <random>

#include "sarloc/core/avalanche/field_measurement.hpp"
#include "sarloc/core/avalanche/responder_types.hpp"
#include "sarloc/core/avalanche/simulator.hpp"

namespace sarloc::avalanche {

/// True receiver pose in a world frame whose axes are ENU (z up).
struct ReceiverPose {
  Vec3 position = Vec3::Zero();  ///< antenna position (m)
  Vec3 rpy = Vec3::Zero();       ///< roll, pitch, yaw of R in the world (rad)
};

/// Three standard normal draws, x then y then z. Draws written as constructor arguments,
/// Vec3(n(rng), n(rng), n(rng)), happen in an order C++ leaves to the compiler, and a seed
/// must give the same trial with every compiler.
Vec3 normal3(std::mt19937_64& rng);

/// A burial: depth |N(0, s)| with s = burial_depth_p95_m / z_0.975 (95 % shallower than
/// burial_depth_p95_m), at least min_burial_depth_m. The caller's distributions, so that a trial
/// draws the same stream whoever draws (std::normal_distribution keeps a second value).
double draw_burial_depth(const SimulationConfig& config, std::mt19937_64& rng, std::normal_distribution<double>& n01);
/// A transmitter's moment: a direction uniform on the sphere (normal3; a zero draw is drawn
/// again), a magnitude uniform within the standard's range.
Vec3 draw_moment(const SimulationConfig& config, std::mt19937_64& rng, std::uniform_real_distribution<double>& u01);

/// Noisy field of a transmitter (position, moment in the world) at the receiver, in frame R:
/// per axis sigma = field_noise_relative * |H| + field_noise_floor.
Vec3 simulate_field(const SimulationConfig& config, const ReceiverPose& receiver, const Vec3& transmitter,
                    const Vec3& moment, std::mt19937_64& rng);

/// Attitude-sensor reading of the receiver (tilt from the accelerometer, yaw from a compass).
OrientationObservation simulate_attitude(const SimulationConfig& config, const ReceiverPose& receiver,
                                         std::mt19937_64& rng);

/// Turns by bearing_rad from the TRUE heading, walks step_m horizontally (the body sways in
/// roll/pitch), updates `receiver`, and returns the noisy odometry of that step with its
/// covariance (ids, sequence and stamps left for the caller).
Odometry simulate_step(const SimulationConfig& config, ReceiverPose& receiver, double bearing_rad, double step_m,
                       std::mt19937_64& rng);

}  // namespace sarloc::avalanche
