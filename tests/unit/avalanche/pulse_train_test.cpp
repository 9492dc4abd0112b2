// Pulse trains in lockstep: the truth the multiple-burial evaluation classifies its trials by.
#include "sarloc/core/avalanche/pulse_train.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace sarloc::avalanche {
namespace {

TransmitterTiming train(double period_s, double on_time_s, double first_start_s) {
  TransmitterTiming t;
  t.period_s = period_s;
  t.on_time_s = on_time_s;
  t.first_start_s = first_start_s;
  return t;
}

// Brute force: a's pulses, from its first, that each overlap some pulse of b, in a row.
int overlapping_pulses_by_listing(const TransmitterTiming& a, const TransmitterTiming& b, int most) {
  for (int k = 0; k < most; ++k) {
    const double start = a.first_start_s + k * a.period_s;
    const auto others = b.starts_in(start - b.period_s, start + a.on_time_s + b.period_s);
    const bool hit = std::any_of(others.begin(), others.end(), [&](double s) {
      return s < start + a.on_time_s && s + b.on_time_s > start;
    });
    if (!hit) return k;
  }
  return most;
}

TEST(PulseTrainTest, TrainsWhosePeriodsDifferByLittleOverlapForOnTimeOverTheDifferencePeriods) {
  // 0.2 ms apart, b 9.5 ms ahead of a, 130 ms pulses: b drifts 0.2 ms a period until it starts
  // 130 ms after a, 697.5 periods later.
  EXPECT_NEAR(pulses_overlap_for_s(train(1.0505, 0.130, 0.30), train(1.0507, 0.134, 0.2905)), 698 * 1.0505, 1e-6);
  // 2 ms apart, b 20.5 ms behind: 54.75 periods.
  EXPECT_NEAR(pulses_overlap_for_s(train(1.0505, 0.130, 0.30), train(1.0525, 0.134, 0.3205)), 55 * 1.0505, 1e-6);
  // Not overlapping at first: none (b half a period off, drifting towards a).
  EXPECT_EQ(pulses_overlap_for_s(train(1.0, 0.1, 0.0), train(1.0001, 0.1, 0.5)), 0.0);
  // The offset is taken to the nearest pulse: b a whole period later is as good as together,
  // and equal periods stay together for good.
  EXPECT_TRUE(std::isinf(pulses_overlap_for_s(train(1.0, 0.1, 0.05), train(1.0, 0.1, 1.08))));
}

TEST(PulseTrainTest, OverlapAgreesWithListingThePulses) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  constexpr int kMost = 2000;
  int agreed = 0, overlapping = 0;
  for (int k = 0; k < 400; ++k) {
    const double period = 0.7 + 0.6 * u(rng);
    const TransmitterTiming a = train(period, 0.07 + 0.13 * u(rng), period * u(rng));
    const TransmitterTiming b =
        train(period * (1.0 + 0.001 * (2.0 * u(rng) - 1.0)), 0.07 + 0.13 * u(rng), a.first_start_s + 0.4 * (u(rng) - 0.5));
    const double fast = pulses_overlap_for_s(a, b);
    const int pulses = static_cast<int>(std::lround(std::min(fast / a.period_s, double{kMost})));
    if (pulses == overlapping_pulses_by_listing(a, b, kMost)) ++agreed;
    if (pulses > 0) ++overlapping;
  }
  EXPECT_EQ(agreed, 400);
  EXPECT_GT(overlapping, 40);  // both outcomes are exercised
  EXPECT_LT(overlapping, 360);
}

}  // namespace
}  // namespace sarloc::avalanche
