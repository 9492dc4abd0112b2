#pragma once
// A simulated multi-victim, multi-rescuer avalanche mission: who is buried where, who searches
// from where, and how the rescuers' sensors behave. Incident frame: ENU, snow surface z = 0.
#include <optional>
#include <string>
#include <vector>

#include "sarloc/core/avalanche/simulator.hpp"

namespace sarloc::mission {

struct VictimSpec {
  std::string name;              ///< for reports only; rescuers never see it
  Vec3 position = Vec3::Zero();  ///< transmitter in the incident frame (m), z < 0 = buried
  Vec3 moment = Vec3::Zero();    ///< magnetic moment in the incident frame (A m^2)
  /// The transmitter's pulse period and carrier offset (realistic receiver); unset: drawn from
  /// the mission seed within the standard. Set them to make victims' pulses overlap.
  std::optional<double> period_ms;
  std::optional<double> carrier_offset_hz;
};

struct RescuerSpec {
  std::string id;
  std::string team;
  Vec3 start = Vec3::Zero();     ///< x, y of the start in the incident frame (z ignored)
  double heading_deg = 0.0;      ///< initial facing, ENU yaw (0 = east)
};

struct MissionScenario {
  std::vector<VictimSpec> victims;
  std::vector<RescuerSpec> rescuers;
  /// Receivers, attitude sensors and odometry. A mission's receiver is realistic: each device
  /// hears the pulses of every transmitter, summed on its coils, and separates them itself
  /// (avalanche/beacon_receiver.hpp). The ideal receiver (separated, signed samples of every
  /// victim within detection_range_m) stays for comparison and for unit tests.
  avalanche::SimulationConfig sensors;
  /// Ideal receiver only: it separates signals within this range (NOTES: 40-70 m). The
  /// realistic receiver's range follows from its noise floor.
  double detection_range_m = 60.0;
  /// GNSS error of a rescuer's fix: a slowly drifting bias (first-order Gauss-Markov, as
  /// real receivers' errors are) plus a little white noise. The default 0.3 m is a
  /// dual-frequency / SBAS-corrected handheld; consumer phones are nearer 1.5-3 m, which then
  /// dominates the incident-frame error (docs/benchmarks.md). Vertical: twice the horizontal.
  double gnss_sigma_m = 0.3;
  double gnss_correlation_s = 60.0;     ///< time constant of the drifting bias (s)
  double gnss_white_sigma_m = 0.05;     ///< epoch-to-epoch jitter on top of the bias (m)
  std::uint64_t seed = 1;               ///< every rescuer's noise derives from it
  /// A simulated device that FOUND a victim reports it dug out this many mission seconds later
  /// (VictimRecovery), and every simulated receiver stops hearing its transmitter once the
  /// picture says so. Compressed: a real dig takes 10-40 minutes (triage.dig_min_per_m). 0: no
  /// victim is dug out.
  double dig_out_after_s = 0.0;

  /// Throws ConfigError naming the entry ("victims[1].position = ...: must be below the surface").
  void validate() const;
  /// Index of the rescuer with this id; throws ConfigError when unknown.
  std::size_t rescuer_index(const std::string& id) const;
};

}  // namespace sarloc::mission
