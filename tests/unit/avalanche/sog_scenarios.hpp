#pragma once
// The SOG filter tests' scenario: one transmitter, a second one 2 m from it, and the bearing
// that walks the simulated rescuer straight at the transmitter.
#include <cmath>
#include <limits>

#include "sarloc/core/avalanche/simulator.hpp"

namespace sarloc::avalanche::test {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

inline Scenario fixed_scenario() {
  Scenario s;
  s.transmitter = Vec3(30.0, 20.0, -1.5);
  s.moment = Vec3(0.01, -0.005, 0.012);
  s.receiver = Vec3(0.0, 0.0, 1.0);
  s.receiver_rpy = Vec3(0.02, -0.03, 0.7);
  return s;
}

// fixed_scenario()'s walk with another transmitter 2 m from its one, with another moment.
inline Scenario second_transmitter() {
  Scenario b = fixed_scenario();
  b.transmitter += Vec3(-1.0, 1.5, -1.0);
  b.moment = Vec3(-0.004, 0.012, 0.006);
  return b;
}

// Receiver-frame bearing that walks the simulated rescuer straight at the transmitter.
inline double bearing_to_truth(const AvalancheSimulator& sim) {
  const Vec3 rel = sim.true_relative_position();
  return std::atan2(rel.y(), rel.x()) - sim.scenario().receiver_rpy.z();
}

}  // namespace sarloc::avalanche::test
