// QuietSpan (issue 12, negative information across windows): when do the clear start times of a
// silent carrier hold a whole pulse for every phase of its train?
#include <gtest/gtest.h>

#include "sarloc/core/avalanche/quiet_span.hpp"

namespace sarloc::avalanche {
namespace {

constexpr double kOnTime = 0.1;

// Back-to-back 1 s windows with nothing else heard: a pulse train of 0.99 s walks its phase
// back by 10 ms a window, so the 0.1 s of phase a window cannot hold whole (a pulse cut by the
// window's end) is covered after about ten windows, never after one.
TEST(QuietSpan, APeriodOffTheWindowsCoversEveryPhaseAfterSomeWindows) {
  QuietSpan span;
  int covered_after = -1;
  for (int k = 0; k < 40 && covered_after < 0; ++k) {
    span.add_window(k, k + 1.0, kOnTime, {}, 0.0);
    if (span.every_phase_covered(0.99, 1e-4)) covered_after = k + 1;
  }
  EXPECT_GE(covered_after, 9);
  EXPECT_LE(covered_after, 15);
}

// A period equal to the window's: the same 0.1 s of phase is cut by every window's end, so no
// span ever proves a miss; and the span stays bounded however long the silence.
TEST(QuietSpan, APeriodEqualToTheWindowNeverCoversTheCutPhase) {
  QuietSpan span;
  for (int k = 0; k < 2000; ++k) {
    span.add_window(k, k + 1.0, kOnTime, {}, 0.0);
    ASSERT_FALSE(span.every_phase_covered(1.0, 1e-4)) << "window " << k;
  }
  EXPECT_LE(span.clear_starts().size(), QuietSpan::kMaxIntervals);
}

// One window longer than a period and an on-time holds a whole pulse for any phase.
TEST(QuietSpan, AWindowLongerThanAPeriodCoversAtOnce) {
  QuietSpan span;
  span.add_window(0.0, 2.0, kOnTime, {}, 0.0);
  EXPECT_TRUE(span.every_phase_covered(0.9, 1e-3));
  EXPECT_FALSE(span.every_phase_covered(1.95, 1e-3));
}

// Another transmitter's pulse could hide a weak one: starts whose pulse would overlap it (with
// the margin) are not clear, and a span made only of such windows never covers.
TEST(QuietSpan, StartsUnderAnotherPulseAreNotClear) {
  QuietSpan span;
  span.add_window(0.0, 1.0, kOnTime, {{0.4, 0.5}}, 0.01);
  ASSERT_EQ(span.clear_starts().size(), 2U);
  EXPECT_DOUBLE_EQ(span.clear_starts()[0].first, 0.0);
  EXPECT_NEAR(span.clear_starts()[0].second, 0.4 - kOnTime - 0.01, 1e-12);
  EXPECT_NEAR(span.clear_starts()[1].first, 0.51, 1e-12);
  EXPECT_NEAR(span.clear_starts()[1].second, 0.9, 1e-12);
  // The other pulse on the same period in every window: that phase is never clear.
  QuietSpan covered;
  for (int k = 0; k < 60; ++k) {
    covered.add_window(k, k + 1.0, kOnTime, {{k + 0.4 - 0.01 * k, k + 0.5 - 0.01 * k}}, 0.01);
    EXPECT_FALSE(covered.every_phase_covered(0.99, 1e-4)) << "window " << k;
  }
}

// A vague period narrows what each window says (its phase drifts by the spread every period
// since the span began): with a spread of a twentieth of the period nothing is ever proved.
TEST(QuietSpan, AVaguePeriodProvesNothing) {
  QuietSpan span;
  for (int k = 0; k < 60; ++k) {
    span.add_window(k, k + 1.0, kOnTime, {}, 0.0);
    EXPECT_FALSE(span.every_phase_covered(0.99, 0.05)) << "window " << k;
  }
  span.reset();
  EXPECT_TRUE(span.clear_starts().empty());
}

}  // namespace
}  // namespace sarloc::avalanche
