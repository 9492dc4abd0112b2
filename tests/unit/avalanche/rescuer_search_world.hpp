#pragma once
// The rescuer-search tests' world: two victims, one rescuer walking north, a quick filter.
#include <gtest/gtest.h>

#include <variant>
#include <vector>

#include "sarloc/core/avalanche/rescuer_search.hpp"
#include "sarloc/core/mission/simulated_rescuer.hpp"

namespace sarloc::avalanche::test {

inline mission::MissionScenario scenario() {
  mission::MissionScenario s;
  // A is much closer than B: its signal is the strongest.
  s.victims = {{"A", Vec3(0.0, 15.0, -1.0), Vec3(0.01, -0.005, 0.004), {}, {}},
               {"B", Vec3(30.0, 35.0, -1.5), Vec3(-0.004, 0.003, 0.015), {}, {}}};
  s.rescuers = {{"r", "t", Vec3(0.0, 0.0, 0.0), 90.0}};
  s.seed = 5;
  s.sensors.receiver.kind = ReceiverKind::kIdeal;  // the search logic, not the separation
  return s;
}

inline RescuerSearchConfig quick() {
  RescuerSearchConfig c;
  c.sog.initial_components = 300;
  return c;
}

constexpr TimestampNs kSecond = 1'000'000'000;

// Feeds `epochs` epochs walking straight north, the guidance ignored; returns the last epoch.
inline std::vector<FieldMeasurement> feed(RescuerSearch& search, mission::SimulatedRescuer& sim, int epochs) {
  std::vector<FieldMeasurement> last;
  for (int k = 0; k < epochs; ++k) {
    if (k > 0) {
      EXPECT_FALSE(search.add_odometry(sim.walk(0.0, 0.5, k * kSecond, (k + 1) * kSecond)).has_value());
    }
    last = sim.measure((k + 1) * kSecond);
    for (const auto& m : last) EXPECT_TRUE(std::holds_alternative<SearchUpdate>(search.process(m)));
  }
  return last;
}

}  // namespace sarloc::avalanche::test
