// The multiple-burial evaluation: its setup checks and the step-by-step trace of one trial.
#include "sarloc/core/avalanche/multi_burial.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "sarloc/core/common/errors.hpp"

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
  try {
    setup.validate();
    FAIL() << "0 victims accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("multi_burial.victims = 0"), std::string::npos) << e.what();
  }
  setup = two_victims();
  setup.simulation.receiver.kind = ReceiverKind::kIdeal;
  EXPECT_THROW(setup.validate(), ConfigError);
}

// The trace sees what the trial did and changes none of it: the same trial traced and untraced
// end alike, one traced line per step, and the last line's count of victims found is the trial's.
TEST(MultiBurialTest, TheTraceFollowsTheTrialWithoutChangingIt) {
  const MultiBurialSetup setup = two_victims();
  const MultiBurialTrial plain = run_multi_burial_trial(setup, 0);
  std::size_t victims_seen = 0;
  std::vector<MultiBurialTraceStep> steps;
  MultiBurialTraceObserver observer;
  observer.victims = [&](const std::vector<MultiBurialTraceVictim>& v) { victims_seen = v.size(); };
  observer.step = [&](const MultiBurialTraceStep& s) { steps.push_back(s); };
  const MultiBurialTrial traced = run_multi_burial_trial(setup, 0, &observer);

  EXPECT_EQ(traced.found, plain.found);
  EXPECT_EQ(traced.steps, plain.steps);
  EXPECT_DOUBLE_EQ(traced.distance_m, plain.distance_m);
  EXPECT_EQ(traced.signals, plain.signals);
  EXPECT_EQ(victims_seen, setup.victims);
  ASSERT_EQ(steps.size(), traced.steps);
  for (std::size_t k = 0; k < steps.size(); ++k) EXPECT_EQ(steps[k].step, k + 1);
  EXPECT_EQ(steps.back().found, traced.found);
  ASSERT_TRUE(traced.all_found) << "two victims 5 m apart, seed 3, trial 0";
  // Every signal the trial counted appears in the trace, and a FOUND was traced per victim.
  std::set<std::uint32_t> signals;
  std::size_t founds = 0;
  for (const MultiBurialTraceStep& s : steps) {
    for (const MultiBurialTraceSample& t : s.samples) {
      signals.insert(t.signal_id);
      if (t.estimate && t.estimate->status == EstimatorStatus::kFound && t.guidance &&
          t.guidance->mode == GuidanceMode::kFound)
        ++founds;
    }
  }
  EXPECT_EQ(signals.size(), traced.signals);
  EXPECT_EQ(founds, setup.victims);
}

}  // namespace
}  // namespace sarloc::avalanche
