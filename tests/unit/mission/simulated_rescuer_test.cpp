// The mission world's sensors: signals numbered in order of detection, detection range,
// distance walked, and a GNSS error with the configured statistics.
#include "sarloc/core/mission/simulated_rescuer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "sarloc/core/common/errors.hpp"
#include "support/config_messages.hpp"

namespace sarloc::mission {
namespace {

MissionScenario scenario(std::uint64_t seed) {
  MissionScenario s;
  s.victims = {{"near", Vec3(0.0, 20.0, -1.0), Vec3(0.01, 0.0, 0.005), {}, {}},
               {"far", Vec3(0.0, 120.0, -1.0), Vec3(0.01, 0.0, 0.005), {}, {}}};
  s.rescuers = {{"r", "t", Vec3(0.0, 0.0, 0.0), 90.0}};
  s.seed = seed;
  return s;
}

constexpr TimestampNs kSecond = 1'000'000'000;

TEST(SimulatedRescuer, IdealReceiverMeasuresOnlyVictimsInRangeAndNumbersSignalsAsDetected) {
  MissionScenario s = scenario(1);
  s.sensors.receiver.kind = avalanche::ReceiverKind::kIdeal;
  SimulatedRescuer sim(s, "r");
  const auto first = sim.measure(kSecond);
  ASSERT_EQ(first.size(), 1U) << "the far victim is 120 m away, beyond detection_range_m";
  EXPECT_EQ(first[0].signal_id, 1U);
  EXPECT_EQ(sim.victim_of_signal(1), 0U);
  for (int k = 0; k < 70; ++k) sim.walk(0.0, 1.0, (k + 1) * kSecond, (k + 2) * kSecond);  // north, 70 m
  EXPECT_NEAR(sim.distance_walked_m(), 70.0, 1e-9);
  const auto later = sim.measure(80 * kSecond);
  ASSERT_EQ(later.size(), 2U);
  EXPECT_EQ(sim.victim_of_signal(2), 1U) << "the second signal detected is the far victim";
}

TEST(SimulatedRescuer, GnssErrorHasTheConfiguredSpreadAndDriftsSlowly) {
  // Many independent rescuers (seeds), 1 Hz fixes standing still: per-axis RMS of the
  // horizontal error ~ gnss_sigma_m, and consecutive errors strongly correlated (a drifting
  // bias, not white noise that averaging would remove).
  double sum2 = 0.0;
  double lag1 = 0.0;
  int n = 0;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    auto s = scenario(seed);
    SimulatedRescuer sim(s, "r");
    const Vec3 truth = sim.pose().position;
    std::optional<Vec3> previous;
    for (int k = 0; k < 20; ++k) {
      const Vec3 e = sim.gnss((k + 1) * kSecond).position.position - truth;
      sum2 += e.x() * e.x() + e.y() * e.y();
      if (previous) lag1 += e.x() * previous->x() + e.y() * previous->y();
      previous = e;
      ++n;
    }
  }
  const double sigma = std::sqrt(sum2 / (2.0 * n));
  EXPECT_NEAR(sigma, scenario(1).gnss_sigma_m, 0.1 * scenario(1).gnss_sigma_m);
  EXPECT_GT(lag1 / sum2, 0.9) << "GNSS error should be a slowly drifting bias";
}

TEST(SimulatedRescuer, RealisticReceiverSeparatesEveryVictimItHearsIntoOneSignalEach) {
  // Two victims 4 m apart, their pulses on the same period (they overlap for long stretches
  // when their phases meet), and one 120 m away that the receiver's noise floor hides.
  MissionScenario s = scenario(3);
  s.victims.insert(s.victims.begin() + 1, VictimSpec{"beside", Vec3(4.0, 20.0, -1.5), Vec3(-0.004, 0.003, 0.015), {}, {}});
  s.victims[0].period_ms = 1000.0;
  s.victims[1].period_ms = 1000.0;
  ASSERT_EQ(s.sensors.receiver.kind, avalanche::ReceiverKind::kRealistic) << "a mission's receiver is realistic";
  s.validate();
  SimulatedRescuer sim(s, "r");
  std::map<std::uint32_t, int> samples, news;
  for (int k = 1; k <= 40; ++k) {
    for (const auto& m : sim.measure(k * kSecond)) {
      ++samples[m.signal_id];
      if (m.event == avalanche::SignalEvent::kNew) ++news[m.signal_id];
      EXPECT_EQ(m.sequence, static_cast<std::uint64_t>(k));
      EXPECT_NE(m.valid_axes, 0U);
      EXPECT_TRUE(m.field.allFinite());
    }
  }
  ASSERT_EQ(samples.size(), 2U) << "the 120 m victim is out of range, the two near ones are two signals";
  std::set<std::size_t> victims;
  for (const auto& [signal, n] : samples) {
    EXPECT_GE(n, 20) << "signal " << signal << ": most epochs carry a sample of each";
    EXPECT_EQ(news[signal], 1) << "signal " << signal << ": announced new exactly once";
    const auto victim = sim.victim_of_signal(signal);
    ASSERT_TRUE(victim.has_value());
    EXPECT_LT(*victim, 2U);
    victims.insert(*victim);
  }
  EXPECT_EQ(victims.size(), 2U) << "each signal is a different victim";
  EXPECT_EQ(sim.wrong_attributions(), 0U);
}

// A victim dug out: its transmitter is switched off, and neither receiver hears it again; the
// other victim beside it is still heard.
TEST(SimulatedRescuer, ASwitchedOffTransmitterIsHeardNoMore) {
  MissionScenario s = scenario(3);
  s.victims.insert(s.victims.begin() + 1,
                   VictimSpec{"beside", Vec3(4.0, 20.0, -1.5), Vec3(-0.004, 0.003, 0.015), {}, {}});
  for (const auto kind : {avalanche::ReceiverKind::kRealistic, avalanche::ReceiverKind::kIdeal}) {
    s.sensors.receiver.kind = kind;
    SimulatedRescuer sim(s, "r");
    std::map<std::size_t, int> before, after;
    for (int k = 1; k <= 20; ++k)
      for (const auto& m : sim.measure(k * kSecond)) ++before[sim.victim_of_signal(m.signal_id).value_or(9)];
    EXPECT_FALSE(sim.switch_off_transmitter_near(Vec3(2.0, 40.0, -1.0), 3.0)) << "no transmitter within 3 m";
    ASSERT_EQ(sim.switch_off_transmitter_near(Vec3(4.5, 20.3, -1.2), 3.0), std::optional<std::size_t>(1));
    EXPECT_FALSE(sim.switch_off_transmitter_near(Vec3(4.5, 20.3, -1.2), 3.0)) << "off already; the other is 4 m away";
    EXPECT_FALSE(sim.switch_off_transmitter(1)) << "off already (another rescuer's dig names it by index)";
    EXPECT_FALSE(sim.switch_off_transmitter(s.victims.size())) << "no such victim";
    sim.measure(21 * kSecond);  // the window that straddles the switch-off
    for (int k = 22; k <= 41; ++k)
      for (const auto& m : sim.measure(k * kSecond))
        if (m.valid_axes != 0) ++after[sim.victim_of_signal(m.signal_id).value_or(9)];  // 0: a pulse due, not heard
    EXPECT_GE(before[1], 10) << "heard before";
    EXPECT_EQ(after.count(1), 0U) << "heard after it was switched off";
    EXPECT_GE(after[0], 10) << "the victim beside it is still heard";
  }
}

TEST(SimulatedRescuer, VictimTimingOutsideTheStandardIsRefusedByName) {
  MissionScenario s = scenario(1);
  s.victims[1].period_ms = 500.0;
  EXPECT_NE(sarloc::test::validation_error(s).find("victims[1].period_ms = 500"), std::string::npos)
      << sarloc::test::validation_error(s);
  s.victims[1].period_ms.reset();
  s.victims[0].carrier_offset_hz = 120.0;
  EXPECT_THROW(s.validate(), ConfigError);
}

}  // namespace
}  // namespace sarloc::mission
