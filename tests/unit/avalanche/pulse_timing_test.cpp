// PulseTiming: the Kalman filter on a transmitter's pulse phase and period.
#include "sarloc/core/avalanche/pulse_timing.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace sarloc::avalanche {
namespace {

TEST(PulseTiming, TwoStartsAPeriodApartSetThePeriod) {
  PulseTiming timing;
  EXPECT_FALSE(timing.fit(0.3, 0.001).has_value());
  timing.update(0.3, 0.001);
  EXPECT_FALSE(timing.has_period());
  timing.update(1.4, 0.001);
  ASSERT_TRUE(timing.has_period());
  EXPECT_NEAR(timing.period_s(), 1.1, 1e-9);
  EXPECT_NEAR(timing.period_sigma_s(), std::sqrt(2.0) * 0.001, 1e-6);
}

TEST(PulseTiming, StartsFartherApartThanAPeriodResetThePhase) {
  PulseTiming timing;
  timing.update(0.3, 0.001);
  timing.update(2.5, 0.001);  // two periods or a lost pulse: no period from it
  EXPECT_FALSE(timing.has_period());
  timing.update(3.5, 0.001);
  ASSERT_TRUE(timing.has_period());
  EXPECT_NEAR(timing.period_s(), 1.0, 1e-9);
}

// The failure it replaced: a period from two weak pulses (edges tens of ms off) predicted 20
// periods ahead missed the transmitter's strong pulses by more than any fixed tolerance, and the
// track was lost while the victim came closer.
TEST(PulseTiming, WeakEdgesFirstThenStrongPulsesStayInsideTheGate) {
  const double period = 1.0918, start = 0.206;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n01(0.0, 1.0);
  PulseTiming timing;
  std::size_t misses = 0;
  for (int k = 0; k < 60; ++k) {
    const double sigma = k < 10 ? 0.017 : 0.0011;  // statistic ~120, then ~10^4
    const double measured = start + k * period + sigma * n01(rng);
    if (const auto fit = timing.fit(measured, sigma); fit && fit->sigmas() > 4.0) ++misses;
    timing.update(measured, sigma);
  }
  EXPECT_EQ(misses, 0U);
  EXPECT_NEAR(timing.period_s(), period, 3.0 * timing.period_sigma_s() + 1e-5);
  EXPECT_LT(timing.period_sigma_s(), 3e-4);  // from 28 ms after two weak pulses; clock jitter bounds it
}

TEST(PulseTiming, GateWidensWithThePeriodsPredicted) {
  PulseTiming timing;
  timing.update(0.0, 0.01);
  timing.update(1.0, 0.01);
  const auto near = timing.fit(2.0, 0.001);
  const auto far = timing.fit(30.0, 0.001);
  ASSERT_TRUE(near && far);
  EXPECT_DOUBLE_EQ(near->periods, 1.0);
  EXPECT_DOUBLE_EQ(far->periods, 29.0);
  EXPECT_GT(far->variance_s2, 100.0 * near->variance_s2);
}

TEST(PulseTiming, ReanchorKeepsThePeriodAndForgetsThePhase) {
  PulseTiming timing;
  for (int k = 0; k < 10; ++k) timing.update(0.1 + 1.2 * k, 0.001);
  timing.reanchor();
  EXPECT_TRUE(timing.has_period());
  EXPECT_FALSE(timing.has_phase());
  EXPECT_FALSE(timing.fit(50.0, 0.001).has_value());
  timing.update(50.0, 0.001);  // a new phase, the old period
  const auto fit = timing.fit(51.2, 0.001);
  ASSERT_TRUE(fit.has_value());
  EXPECT_LT(fit->sigmas(), 1.0);
}

}  // namespace
}  // namespace sarloc::avalanche
