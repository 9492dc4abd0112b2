#pragma once
// Avalanche search simulator: one buried transmitter, one rescuer with a 3-axis receiver and
// odometry (seed 000, section V, with the noise floors of the sarloc issue).
//
// World frame W: ENU, snow surface at z = 0, the rescuer's antenna starts at (0, 0, h).
// Per trial (all draws from the RNG seeded by the caller):
//   - transmitter at horizontal distance U(start_distance_min_m, start_distance_max_m), uniform
//     azimuth, burial depth |N(0, s)| with s = burial_depth_p95_m / 1.95996 (95 % shallower than
//     burial_depth_p95_m), clamped to >= min_burial_depth_m;
//   - moment direction uniform on the sphere, magnitude U(m_min, m_max) of the standard;
//   - rescuer heading uniform; roll/pitch sway N(0, sway) redrawn at every step.
// Measurements: z = R_k^T H + n, n_i ~ N(0, (field_noise_relative |H| + floor)^2) per axis.
// Odometry: true displacement in R_{k-1} plus N(0, max(rel |t|, floor)^2) per axis on t and
// N(0, sigma^2) on roll/pitch/yaw of the relative rotation; the reported covariance is the same.
// validate() refuses noise below the minimums, so no config can flatter the filter.
//
//   AvalancheSimulator sim(SimulationConfig{}, seed);
//   FieldMeasurement z = sim.measure();
//   Odometry o = sim.walk(guidance.bearing_rad, guidance.step_m);
#include <cstdint>
#include <optional>
#include <random>

#include <memory>
#include <vector>

#include "sarloc/core/avalanche/field_measurement.hpp"
#include "sarloc/core/avalanche/field_noise_model.hpp"
#include "sarloc/core/avalanche/receiver_model.hpp"
#include "sarloc/core/common/seeds.hpp"
#include "sarloc/core/avalanche/responder_types.hpp"
#include "sarloc/core/avalanche/transmitter_standard.hpp"

namespace sarloc::avalanche {

struct SimulationConfig {
  double start_distance_min_m = 40.0;   ///< seed 000, section V
  double start_distance_max_m = 60.0;
  double burial_depth_p95_m = 3.0;      ///< 95 % shallower (seed 000, ref. [9])
  double min_burial_depth_m = 0.2;      ///< a body is never flush with the surface
  double antenna_height_m = 1.0;        ///< receiver held about 1 m above the snow
  TransmitterStandard standard;         ///< EN 300 718 bounds -> moment magnitude range
  double field_noise_relative = 0.05;   ///< issue minimum: 5 % of |H| per axis
  /// Additive per-axis floor (A/m); issue minimum: strongest on-axis field at 60 m / 10.
  double field_noise_floor_A_per_m = 2.1e-9;
  /// The field noise model of these two keys: what the simulated receiver adds.
  FieldNoiseModel field_noise() const { return FieldNoiseModel{field_noise_relative, field_noise_floor_A_per_m}; }
  double odometry_translation_relative = 0.03;  ///< issue minimum: 3 % of the step
  double odometry_translation_floor_m = 0.01;   ///< sigma when standing still
  double odometry_yaw_sigma_deg = 1.0;          ///< issue minimum: 1 deg per step
  double odometry_roll_pitch_sigma_deg = 0.5;   ///< issue minimum: 0.5 deg per step
  double sway_roll_pitch_deg = 3.0;             ///< true receiver tilt while walking
  double attitude_roll_pitch_sigma_deg = 1.0;   ///< attitude sensor (accelerometer tilt)
  double attitude_yaw_sigma_deg = 5.0;          ///< attitude sensor (compass)
  /// Attach the attitude-sensor reading to every measurement (false: first one only, which
  /// gives the initial misalignment G_1 -> R_1 of seed 000, section III-B).
  bool attitude_updates = true;
  /// The receiver: realistic (pulses, unknown sign, unequal antennas, separation; the
  /// default) or ideal (a signed, separated 3-axis sample per step, seed 000).
  ReceiverModelConfig receiver;
  /// Realistic receiver only: the signal is first heard during the primary search, so a trial
  /// starts walking a search strip whose line passes within this of the victim (m).
  double primary_strip_half_width_m = 20.0;

  /// Throws ConfigError "simulation.<key> = value: rule".
  void validate() const;
};

struct Scenario {
  Vec3 transmitter = Vec3::Zero();  ///< transmitter position in W (m)
  Vec3 moment = Vec3::Zero();       ///< A m^2 in W
  Vec3 receiver = Vec3::Zero();     ///< antenna position in W (m)
  Vec3 receiver_rpy = Vec3::Zero(); ///< receiver orientation R in W = G axes (rad)
};

class BeaconReceiver;
struct Beacon;

class AvalancheSimulator {
 public:
  /// Draws a random scenario from config with the given seed.
  AvalancheSimulator(SimulationConfig config, std::uint64_t seed);
  /// Uses a fixed scenario (tests); seed drives the noise only.
  AvalancheSimulator(SimulationConfig config, Scenario scenario, std::uint64_t seed);

  ~AvalancheSimulator();
  AvalancheSimulator(AvalancheSimulator&&) noexcept;

  /// Ideal receiver: a noisy, signed field sample at the current true pose.
  FieldMeasurement measure();
  /// Realistic receiver: what the device separates while it stands at the current pose for the
  /// second until the next walk(): zero, one or (rarely, a spurious signal) more samples, each
  /// with its signal id, sign unknown, invalid axes marked.
  std::vector<FieldMeasurement> listen();
  /// Realistic receiver: attributed pulses that were not the transmitter's (spurious signals).
  std::uint32_t wrong_attributions() const { return wrong_attributions_; }
  /// Turns by bearing_rad from the TRUE heading, walks step_m horizontally, returns odometry.
  Odometry walk(double bearing_rad, double step_m);

  /// Transmitter in the true rescuer-centred frame G_k (ENU axes, origin at the antenna).
  Vec3 true_relative_position() const { return scenario_.transmitter - scenario_.receiver; }
  double true_horizontal_distance() const { return true_relative_position().head<2>().norm(); }
  const Scenario& scenario() const { return scenario_; }
  const SimulationConfig& config() const { return config_; }

 private:
  SimulationConfig config_;
  Scenario scenario_;
  std::mt19937_64 rng_;
  std::uint64_t sequence_ = 0;
  std::uint64_t odo_sequence_ = 0;
  TimestampNs stamp_ = 0;
  std::unique_ptr<BeaconReceiver> receiver_;  ///< realistic receiver only
  std::vector<Beacon> beacons_;
  std::uint32_t wrong_attributions_ = 0;
};

}  // namespace sarloc::avalanche
