#pragma once
// Search scenarios shared by the search controller's tests.
#include "sarloc/core/avalanche/simulator.hpp"

namespace sarloc::avalanche::test {

// One victim 15 m away, 1.8 m deep: the scenario of the search-loop tests.
inline Scenario victim_15_m_away() {
  Scenario s;
  s.transmitter = Vec3(12.0, -9.0, -1.8);
  s.moment = Vec3(0.01, 0.004, -0.006);
  s.receiver = Vec3(0, 0, 1);
  s.receiver_rpy = Vec3(0, 0, 0.4);
  return s;
}

}  // namespace sarloc::avalanche::test
