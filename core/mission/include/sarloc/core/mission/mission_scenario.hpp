#pragma once
// A simulated multi-victim, multi-rescuer avalanche mission: who is buried where, who searches
// from where, and how the rescuers' sensors behave. Incident frame: ENU, snow surface z = 0.
#include <string>
#include <vector>

#include "sarloc/core/avalanche/simulator.hpp"

namespace sarloc::mission {

struct VictimSpec {
  std::string name;              ///< for reports only; rescuers never see it
  Vec3 position = Vec3::Zero();  ///< transmitter in the incident frame (m), z < 0 = buried
  Vec3 moment = Vec3::Zero();    ///< magnetic moment in the incident frame (A m^2)
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
  /// Noise of receivers, attitude sensors and odometry. Live missions still give each device
  /// separated, signed samples (the ideal receiver): the realistic receiver and its signal
  /// separation are evaluated in sarloc-eval but not yet on the devices (issue 12, open).
  avalanche::SimulationConfig sensors = [] {
    avalanche::SimulationConfig c;
    c.receiver.kind = avalanche::ReceiverKind::kIdeal;
    return c;
  }();
  double detection_range_m = 60.0;      ///< a receiver separates signals within this range (NOTES: 40-70 m)
  /// GNSS error of a rescuer's fix: a slowly drifting bias (first-order Gauss-Markov, as
  /// real receivers' errors are) plus a little white noise. The default 0.3 m is a
  /// dual-frequency / SBAS-corrected handheld; consumer phones are nearer 1.5-3 m, which then
  /// dominates the incident-frame error (docs/benchmarks.md). Vertical: twice the horizontal.
  double gnss_sigma_m = 0.3;
  double gnss_correlation_s = 60.0;     ///< time constant of the drifting bias (s)
  double gnss_white_sigma_m = 0.05;     ///< epoch-to-epoch jitter on top of the bias (m)
  std::uint64_t seed = 1;               ///< every rescuer's noise derives from it

  /// Throws ConfigError naming the entry ("victims[1].position = ...: must be below the surface").
  void validate() const;
  /// Index of the rescuer with this id; throws ConfigError when unknown.
  std::size_t rescuer_index(const std::string& id) const;
};

}  // namespace sarloc::mission
