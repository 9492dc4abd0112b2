#pragma once
// The SOG filter tests' scenario: one transmitter, a second one 2 m from it, and the bearing
// that walks the simulated rescuer straight at the transmitter.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

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

// A victim `horizontal_m` from a rescuer standing at the origin (antenna 1 m up), at a random
// azimuth, `depth_m` deep, with a random moment within the standard's and a random heading of
// the rescuer: the draws, in this order, from `rng`.
inline Scenario random_victim_nearby(std::mt19937_64& rng, double horizontal_m, double depth_m, double moment_min,
                                     double moment_max) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double az = 2.0 * kPi * u(rng);
  Scenario s;
  s.transmitter = Vec3(horizontal_m * std::cos(az), horizontal_m * std::sin(az), -depth_m);
  const Vec3 dir = Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized();
  s.moment = dir * (moment_min + u(rng) * (moment_max - moment_min));
  s.receiver = Vec3(0.0, 0.0, 1.0);
  s.receiver_rpy = Vec3(0.0, 0.0, 2.0 * kPi * u(rng));
  return s;
}

// The walk a rescuer makes at a victim: `onto` steps of at most 1 m onto it, then 12 around it
// 1.5 m out. After each step, `update(odometry)` (the caller adds it and takes a sample).
template <typename Update>
void walk_onto_and_around(AvalancheSimulator& sim, const Vec3& victim, int onto, Update&& update) {
  auto walk_to = [&](const Vec3& point) {
    const Vec3 rel = point - sim.scenario().receiver;
    const double step = std::min(1.0, rel.head<2>().norm());
    update(sim.walk(std::atan2(rel.y(), rel.x()) - sim.scenario().receiver_rpy.z(), step));
  };
  for (int k = 0; k < onto; ++k) walk_to(victim);
  for (int k = 0; k < 12; ++k) walk_to(victim + 1.5 * Vec3(std::cos(k * kPi / 3.0), std::sin(k * kPi / 3.0), 0.0));
}

}  // namespace sarloc::avalanche::test
