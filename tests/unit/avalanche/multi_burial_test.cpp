// The multiple-burial evaluation: its setup checks and the step-by-step trace of one trial.
#include "sarloc/core/avalanche/multi_burial.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "support/config_messages.hpp"

namespace sarloc::avalanche {
namespace {

MultiBurialSetup two_victims() {
  MultiBurialSetup setup;
  setup.simulation.receiver.kind = ReceiverKind::kRealistic;
  setup.victims = 2;
  setup.spread_m = 5.0;
  setup.evaluation.seed = 3;
  setup.evaluation.step_budget = 400;
  return setup;
}

TEST(MultiBurialTest, SetupErrorsNameTheKey) {
  MultiBurialSetup setup = two_victims();
  EXPECT_NO_THROW(setup.validate());
  setup.victims = 0;
  EXPECT_NE(sarloc::test::validation_error(setup).find("multi_burial.victims = 0"), std::string::npos)
      << sarloc::test::validation_error(setup);
  setup = two_victims();
  setup.simulation.receiver.kind = ReceiverKind::kIdeal;
  EXPECT_THROW(setup.validate(), ConfigError);
}

// The trace sees what the trial did and changes none of it: the same trial traced and untraced
// end alike, one traced line per step, and the last line's count of victims found is the trial's.
// The trial's FOUND consistency (each FOUND's distance to its victim over its stated 95 % radius)
// is what the traced FOUNDs give.
TEST(MultiBurialTest, TheTraceFollowsTheTrialWithoutChangingIt) {
  const MultiBurialSetup setup = two_victims();
  const MultiBurialTrial plain = run_multi_burial_trial(setup, 0);
  std::vector<Vec3> victims;
  std::vector<MultiBurialTraceStep> steps;
  MultiBurialTraceObserver observer;
  observer.victims = [&](const std::vector<MultiBurialTraceVictim>& v) {
    for (const auto& victim : v) victims.push_back(victim.position);
  };
  observer.step = [&](const MultiBurialTraceStep& s) { steps.push_back(s); };
  const MultiBurialTrial traced = run_multi_burial_trial(setup, 0, &observer);

  EXPECT_EQ(traced.found, plain.found);
  EXPECT_EQ(traced.steps, plain.steps);
  EXPECT_DOUBLE_EQ(traced.distance_m, plain.distance_m);
  EXPECT_EQ(traced.signals, plain.signals);
  EXPECT_EQ(victims.size(), setup.victims);
  ASSERT_EQ(steps.size(), traced.steps);
  for (std::size_t k = 0; k < steps.size(); ++k) EXPECT_EQ(steps[k].step, k + 1);
  EXPECT_EQ(steps.back().found, traced.found);
  ASSERT_TRUE(traced.all_found) << "two victims 5 m apart, seed 3, trial 0";
  // Every signal the trial counted appears in the trace, and a FOUND was traced per victim.
  std::set<std::uint32_t> signals;
  std::size_t founds = 0, outside = 0;
  double worst = 0.0;
  for (const MultiBurialTraceStep& s : steps) {
    for (const MultiBurialTraceSample& t : s.samples) {
      signals.insert(t.signal_id);
      if (t.estimate && t.estimate->status == EstimatorStatus::kFound && t.guidance &&
          t.guidance->mode == GuidanceMode::kFound) {
        ++founds;
        double error = 1e9;  // two victims 5 m apart: each FOUND's victim is the nearest
        for (const Vec3& v : victims) error = std::min(error, (v - t.estimate_at).norm());
        const double ratio = error / radius95_3d(t.estimate->relative.covariance);
        if (ratio > 1.0) ++outside;
        worst = std::max(worst, ratio);
      }
    }
  }
  EXPECT_EQ(signals.size(), traced.signals);
  EXPECT_EQ(founds, setup.victims);
  EXPECT_EQ(traced.founds, founds);
  EXPECT_EQ(plain.founds, founds);
  EXPECT_EQ(traced.founds_outside_radius, outside);
  EXPECT_NEAR(traced.worst_found_error_to_radius, worst, 1e-9);
  EXPECT_GT(worst, 0.0);
}

}  // namespace
}  // namespace sarloc::avalanche
