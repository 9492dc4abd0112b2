#include "sarloc/core/avalanche/evaluation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <mutex>
#include <vector>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::avalanche {
namespace {

EvaluationSetup small_setup(std::uint32_t trials, std::uint32_t threads) {
  EvaluationSetup s;
  s.sog.initial_components = 500;  // lean: the full-size figures live in sarloc-eval
  // The harness on the ideal receiver (a sample every step), its opening heading from the first.
  s.simulation.receiver.kind = ReceiverKind::kIdeal;
  s.sog.field_carrier_hz = 0.0;  // what the ideal receiver measures: the quasi-static field
  s.search.opening_line_samples = 0;
  s.evaluation.trials = trials;
  s.evaluation.threads = threads;
  s.evaluation.seed = 12345;
  return s;
}

TEST(EvaluationTest, ResultsDoNotDependOnThreadCount) {
  const auto one = run_evaluation(small_setup(4, 1));
  const auto two = run_evaluation(small_setup(4, 2));
  ASSERT_EQ(one.per_trial.size(), two.per_trial.size());
  for (std::size_t i = 0; i < one.per_trial.size(); ++i) {
    EXPECT_EQ(one.per_trial[i].steps, two.per_trial[i].steps);
    EXPECT_DOUBLE_EQ(one.per_trial[i].error_m, two.per_trial[i].error_m);
  }
  EXPECT_DOUBLE_EQ(one.error_m.median, two.error_m.median);
}

// Monte Carlo consistency (seed 001, NEES): a few small trials, position NEES of the mixture in
// the converged phase must sit inside the 95 % bounds on its mean. Wide enough for 6 trials,
// tight enough to catch an over-confident filter (a NEES mean of 3x the dof fails).
TEST(EvaluationTest, MonteCarloNeesIsConsistentAndTrialsFinish) {
  const auto s = run_evaluation(small_setup(6, 2));
  EXPECT_EQ(s.trials, 6u);
  EXPECT_EQ(s.not_found, 0u);
  ASSERT_EQ(s.nees_trials, 6u);
  EXPECT_GT(s.nees_lower, 0.0);
  EXPECT_LT(s.nees_lower, 3.0);
  EXPECT_GT(s.nees_upper, 3.0);
  EXPECT_GE(s.nees_mean, s.nees_lower);
  EXPECT_LE(s.nees_mean, s.nees_upper);
  EXPECT_GT(s.nees_fraction_inside_95, 0.8);
  EXPECT_LT(s.error_m.max, 1.0);
  EXPECT_GE(s.initial_distance_m.median, 40.0);
  EXPECT_GT(s.steps.mean, 35.0);
}

// The step observer (sarloc-eval's traces) sees every step of every trial in order, at the pose
// where the sample was taken, and observing does not change the results.
TEST(EvaluationTest, StepObserverSeesEveryStepWithoutChangingResults) {
  const EvaluationSetup setup = small_setup(3, 2);
  std::mutex mutex;
  std::vector<std::vector<std::uint32_t>> steps(3);
  std::vector<std::vector<double>> distances(3);
  std::vector<double> depth_below_antenna(3);
  const auto observed = run_evaluation(setup, {}, {}, [&](const TrialStep& s) {
    std::lock_guard<std::mutex> lock(mutex);
    steps.at(s.trial).push_back(s.step);
    distances.at(s.trial).push_back(s.sim.true_horizontal_distance());
    depth_below_antenna.at(s.trial) = -s.sim.true_relative_position().z();
    EXPECT_EQ(s.estimate.relative.position, s.filter.estimate(0).relative.position);
  });
  const auto plain = run_evaluation(setup);
  for (std::uint32_t t = 0; t < 3; ++t) {
    const TrialResult& r = observed.per_trial[t];
    ASSERT_EQ(steps[t].size(), r.steps) << "trial " << t;
    for (std::size_t i = 0; i < steps[t].size(); ++i) EXPECT_EQ(steps[t][i], i + 1);
    EXPECT_DOUBLE_EQ(distances[t].front(), r.initial_distance_m);
    // Found: the last sample is a confirming probe beside the victim (search_controller.hpp).
    const double probe = std::max(setup.search.found_distance_m, setup.search.confirm_probe_per_depth * depth_below_antenna[t]);
    EXPECT_LT(distances[t].back(), 2.0 * probe + 0.5) << "trial " << t;
    EXPECT_EQ(r.steps, plain.per_trial[t].steps);
    EXPECT_DOUBLE_EQ(r.error_m, plain.per_trial[t].error_m);
  }
}

// At the default noise the fixed "located" radius is reached while the uncertainty still
// shrinks: the adaptive end changes nothing (same steps, same errors, no probe pattern), and
// the FOUNDs are honest. Not vacuous: an impatient stall rule (1 step, 50 %) does lay out
// probe patterns in these same searches.
TEST(EvaluationTest, TheAdaptiveEndLeavesSearchesThatReachTheFixedRadiusAlone) {
  EvaluationSetup off = small_setup(4, 2);
  off.search.stall_window_steps = 0;
  const auto fixed = run_evaluation(off);
  const auto adaptive = run_evaluation(small_setup(4, 2));
  EXPECT_EQ(adaptive.found_by_probe_pattern, 0u);
  EXPECT_EQ(adaptive.false_found, 0u);
  EXPECT_EQ(adaptive.not_found, 0u);
  for (std::size_t i = 0; i < fixed.per_trial.size(); ++i) {
    EXPECT_EQ(adaptive.per_trial[i].steps, fixed.per_trial[i].steps) << "trial " << i;
    EXPECT_DOUBLE_EQ(adaptive.per_trial[i].error_m, fixed.per_trial[i].error_m) << "trial " << i;
    EXPECT_EQ(adaptive.per_trial[i].probe_points, 0u);
    EXPECT_LE(adaptive.per_trial[i].error_m, adaptive.per_trial[i].radius95_m + kFalseFoundMarginM);
  }
  EvaluationSetup impatient = small_setup(4, 2);
  impatient.search.stall_window_steps = 1;
  impatient.search.stall_min_improvement = 0.5;
  const auto early = run_evaluation(impatient);
  std::uint32_t laid_out = 0;
  for (const auto& t : early.per_trial) laid_out += t.probe_points > 0 ? 1 : 0;
  EXPECT_GT(laid_out, 0u) << "these searches do pass through the fine search the rule watches";
}

// A FOUND farther from the victim than its stated 95 % radius + 0.5 m is a false FOUND. A filter
// told 5 % field noise while the receiver has 15 % is over-confident and declares some once
// the innovation guard is off (search.confirm_max_innovation_ratio); with it, fewer.
TEST(EvaluationTest, CountsFalseFoundsOfAnOverconfidentFilter) {
  EvaluationSetup overconfident = small_setup(6, 2);
  overconfident.simulation.field_noise_relative = 0.15;
  overconfident.sog.noise_relative = 0.05;
  const auto guarded = run_evaluation(overconfident);
  overconfident.search.confirm_max_innovation_ratio = 100.0;
  overconfident.search.confirm_max_last_nis = 1000.0;
  overconfident.search.confirm_probe_gate_probability = 1.0;
  overconfident.search.found_confirmations = 1;
  overconfident.sog.iterated_update_max = 0;
  const auto s = run_evaluation(overconfident);
  EXPECT_LT(guarded.false_found, s.false_found) << "the guards, the confirmations and the iterated update avoid some of them";
  std::uint32_t counted = 0;
  for (const auto& t : s.per_trial) {
    EXPECT_EQ(t.false_found, t.found && t.error_m > t.radius95_m + kFalseFoundMarginM) << "trial " << t.index;
    counted += t.false_found ? 1 : 0;
  }
  EXPECT_EQ(s.false_found, counted);
  EXPECT_GE(s.false_found, 1u);
  EXPECT_EQ(run_evaluation(small_setup(6, 2)).false_found, 0u) << "the filter told the truth: none";
}

TEST(EvaluationTest, ConfigErrorsNameTheKey) {
  EvaluationSetup s;
  s.evaluation.trials = 0;
  try {
    run_evaluation(s);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "evaluation.trials = 0: must be > 0");
  }
}

TEST(EvaluationTest, StatsAndPercentiles) {
  const Stats st = compute_stats({3.0, 1.0, 2.0, 10.0});
  EXPECT_DOUBLE_EQ(st.max, 10.0);
  EXPECT_DOUBLE_EQ(st.mean, 4.0);
  EXPECT_DOUBLE_EQ(st.median, 2.5);
  EXPECT_DOUBLE_EQ(percentile({0.0, 10.0}, 0.95), 9.5);
}

}  // namespace
}  // namespace sarloc::avalanche
