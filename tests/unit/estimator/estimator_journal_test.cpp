// A responder handed from one daemon to another keeps its estimator (issue 64, item 4): the
// journal of the calls that made it, replayed into a new estimator, gives one that answers as the
// old one would have, to the last bit, for the rest of the search.
#include "sarloc/core/estimator/estimator_journal.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "sarloc/core/avalanche/simulator.hpp"
#include "sarloc/core/common/errors.hpp"

namespace sarloc::estimator {
namespace {

constexpr std::size_t kRoomy = 100000;

void expect_same(const EstimatorOutput& a, const EstimatorOutput& b, int step) {
  ASSERT_EQ(a.estimates.size(), b.estimates.size()) << "step " << step;
  for (std::size_t i = 0; i < a.estimates.size(); ++i) {
    const auto& x = a.estimates[i];
    const auto& y = b.estimates[i];
    EXPECT_EQ(x.signal_id, y.signal_id) << "step " << step;
    EXPECT_EQ(x.status, y.status) << "step " << step;
    EXPECT_EQ(x.live_components, y.live_components) << "step " << step;
    // Bit for bit: the same arithmetic in the same order, not merely close.
    EXPECT_EQ(x.relative.position, y.relative.position) << "step " << step;
    EXPECT_EQ(x.relative.covariance, y.relative.covariance) << "step " << step;
  }
  ASSERT_EQ(a.guidance.has_value(), b.guidance.has_value()) << "step " << step;
  if (a.guidance) {
    EXPECT_EQ(a.guidance->mode, b.guidance->mode) << "step " << step;
    EXPECT_EQ(a.guidance->bearing_rad, b.guidance->bearing_rad) << "step " << step;
    EXPECT_EQ(a.guidance->step_m, b.guidance->step_m) << "step " << step;
  }
}

// One closed-loop search with the realistic receiver, guided by the first daemon's estimator;
// at `handover_step` a second daemon resumes from its journal and takes the same inputs.
struct HandedSearch {
  int compared_steps = 0;
  std::size_t journal_entries = 0;
  responder::EstimatorStatus last_status = responder::EstimatorStatus::kInitialising;
};

HandedSearch run_handed_search(std::uint64_t seed, int handover_step, int steps) {
  const EstimatorConfigs configs;  // the product's defaults
  avalanche::SimulationConfig world;
  avalanche::AvalancheSimulator sim(world, seed);
  auto first =
      std::make_unique<JournaledEstimator>(make_estimator(ResponderRole::kAvalancheRescuer, "r1", configs), kRoomy);
  std::unique_ptr<JournaledEstimator> second;
  HandedSearch result;
  TimestampNs now = 0;
  for (int step = 0; step < steps; ++step) {
    if (step == handover_step) {
      result.journal_entries = first->journal().entries.size();
      second = resume_estimator(first->journal(), configs, kRoomy);
      EXPECT_EQ(second->active_filters(), first->active_filters());
    }
    std::optional<responder::Guidance> guidance;
    for (auto& sample : sim.listen()) {
      sample.rescuer_id = "r1";
      now = sample.stamp;
      const Outcome a = first->process(sample);
      const auto* out = std::get_if<EstimatorOutput>(&a);
      if (second) {
        const Outcome b = second->process(sample);
        EXPECT_EQ(a.index(), b.index()) << "step " << step;
        if (out != nullptr && std::holds_alternative<EstimatorOutput>(b)) {
          expect_same(*out, std::get<EstimatorOutput>(b), step);
          ++result.compared_steps;
        }
      }
      if (out != nullptr && out->guidance) guidance = out->guidance;
      if (out != nullptr && !out->estimates.empty()) result.last_status = out->estimates.front().status;
    }
    if (!guidance) {
      guidance = first->coast(now);
      if (second) {
        const auto other = second->coast(now);
        EXPECT_EQ(guidance.has_value(), other.has_value()) << "step " << step;
        if (guidance && other) {
          EXPECT_EQ(guidance->bearing_rad, other->bearing_rad) << "step " << step;
        }
      }
    }
    responder::Odometry odometry = guidance ? sim.walk(guidance->bearing_rad, guidance->step_m) : sim.walk(0.0, 1.0);
    odometry.rescuer_id = "r1";
    now = odometry.interval_end;
    const Outcome a = first->add_odometry(odometry);
    EXPECT_TRUE(std::holds_alternative<EstimatorOutput>(a)) << "step " << step;
    if (second) {
      EXPECT_EQ(a.index(), second->add_odometry(odometry).index()) << "step " << step;
    }
  }
  return result;
}

TEST(EstimatorJournal, ARescuerHandedOverMidSearchIsGuidedAsIfNeverHanded) {
  // Handed over during the opening (a wide ring) and again near the end of the approach.
  for (const int handover : {12, 35}) {
    const HandedSearch run = run_handed_search(3, handover, 70);
    EXPECT_GT(run.journal_entries, static_cast<std::size_t>(handover)) << "handed at " << handover;
    EXPECT_GT(run.compared_steps, 10) << "handed at " << handover << ": the signal was heard too seldom to compare";
    std::printf("handed over at step %d: %zu journal entries, %d answers compared, status at the end %d\n", handover,
                run.journal_entries, run.compared_steps, static_cast<int>(run.last_status));
  }
}

// The new daemon meets the rescuer a few epochs before the old daemon's journal arrives: it has
// run a fresh estimator on them. The journal, then its own calls after the journal's reach,
// give the estimator that never changed daemons; the calls both saw are not applied twice.
TEST(EstimatorJournal, ANewDaemonsOwnCallsAfterTheJournalAreAppliedOnceAndInOrder) {
  const EstimatorConfigs configs;
  avalanche::AvalancheSimulator sim(avalanche::SimulationConfig{}, 5);
  auto never_handed =
      std::make_unique<JournaledEstimator>(make_estimator(ResponderRole::kAvalancheRescuer, "r1", configs), kRoomy);
  auto old_daemon =
      std::make_unique<JournaledEstimator>(make_estimator(ResponderRole::kAvalancheRescuer, "r1", configs), kRoomy);
  auto new_daemon =
      std::make_unique<JournaledEstimator>(make_estimator(ResponderRole::kAvalancheRescuer, "r1", configs), kRoomy);
  constexpr int kSwitch = 20, kJournalArrives = 24, kEnd = 45;
  std::unique_ptr<JournaledEstimator> merged;
  TimestampNs now = 0;
  int compared = 0;
  for (int step = 0; step < kEnd; ++step) {
    if (step == kJournalArrives) {
      auto result = resume_with_newer(old_daemon->journal(), new_daemon->journal(), configs, kRoomy);
      EXPECT_GT(result.applied, 4U) << "the new daemon's epochs since the switch";
      EXPECT_GE(result.skipped, 1U) << "the sample both daemons took at the switch";
      merged = std::move(result.estimator);
    }
    // Who takes this epoch: the old daemon before the switch, both at it (a sample in flight),
    // the new one after, and from the journal's arrival the merged estimator.
    std::vector<JournaledEstimator*> takers{never_handed.get()};
    if (step <= kSwitch) takers.push_back(old_daemon.get());
    if (step >= kSwitch && !merged) takers.push_back(new_daemon.get());
    if (merged) takers.push_back(merged.get());
    std::optional<responder::Guidance> guidance;
    for (auto& sample : sim.listen()) {
      sample.rescuer_id = "r1";
      now = sample.stamp;
      const Outcome reference = never_handed->process(sample);
      for (std::size_t k = 1; k < takers.size(); ++k) {
        const Outcome other = takers[k]->process(sample);
        if (takers[k] == merged.get() && std::holds_alternative<EstimatorOutput>(reference) &&
            std::holds_alternative<EstimatorOutput>(other)) {
          expect_same(std::get<EstimatorOutput>(reference), std::get<EstimatorOutput>(other), step);
          ++compared;
        }
      }
      if (const auto* out = std::get_if<EstimatorOutput>(&reference); out != nullptr && out->guidance) {
        guidance = out->guidance;
      }
    }
    if (!guidance) {
      for (auto* taker : takers) {
        const auto g = taker->coast(now);
        if (taker == never_handed.get()) guidance = g;
      }
    }
    responder::Odometry odometry = guidance ? sim.walk(guidance->bearing_rad, guidance->step_m) : sim.walk(0.0, 1.0);
    odometry.rescuer_id = "r1";
    now = odometry.interval_end;
    for (auto* taker : takers) EXPECT_TRUE(std::holds_alternative<EstimatorOutput>(taker->add_odometry(odometry)));
  }
  EXPECT_GT(compared, 10);
}

// A device restarted on its way to the new sector numbers its steps and signals afresh: the old
// daemon's journal is not its estimator any more, and is not resumed (the refused steps would
// leave the new daemon answering nothing).
TEST(EstimatorJournal, AJournalIsNotResumedForADeviceThatNumbersItsStepsAfresh) {
  const EstimatorConfigs configs;
  JournaledEstimator old_daemon(make_estimator(ResponderRole::kAvalancheRescuer, "r1", configs), kRoomy);
  JournaledEstimator new_daemon(make_estimator(ResponderRole::kAvalancheRescuer, "r1", configs), kRoomy);
  responder::Odometry step;
  step.rescuer_id = "r1";
  step.translation = Vec3(0.8, 0.0, 0.0);
  for (std::uint64_t k = 1; k <= 30; ++k) {
    step.sequence = k;
    step.interval_start = static_cast<TimestampNs>(k - 1) * 1'000'000'000;
    step.interval_end = static_cast<TimestampNs>(k) * 1'000'000'000;
    ASSERT_TRUE(std::holds_alternative<EstimatorOutput>(old_daemon.add_odometry(step)));
  }
  step.sequence = 1;  // restarted: numbered afresh, stamped later
  step.interval_start = 40'000'000'000;
  step.interval_end = 41'000'000'000;
  ASSERT_TRUE(std::holds_alternative<EstimatorOutput>(new_daemon.add_odometry(step)));
  EXPECT_EQ(resume_with_newer(old_daemon.journal(), new_daemon.journal(), configs, kRoomy).estimator, nullptr);
  step.sequence = 31;  // the same device, on: resumed
  JournaledEstimator on(make_estimator(ResponderRole::kAvalancheRescuer, "r1", configs), kRoomy);
  ASSERT_TRUE(std::holds_alternative<EstimatorOutput>(on.add_odometry(step)));
  const auto merged = resume_with_newer(old_daemon.journal(), on.journal(), configs, kRoomy);
  ASSERT_NE(merged.estimator, nullptr);
  EXPECT_EQ(merged.applied, 1U);
}

TEST(EstimatorJournal, KeepsOnlyTheCallsThatChangedTheEstimatorAndOverflowsByItsLimit) {
  const EstimatorConfigs configs;
  JournaledEstimator journaled(make_estimator(ResponderRole::kAvalancheRescuer, "r1", configs), 3);
  responder::Odometry absurd;
  absurd.rescuer_id = "r1";
  absurd.sequence = 1;
  absurd.interval_end = 1'000'000'000;
  absurd.translation = Vec3(1e3, 0.0, 0.0);
  ASSERT_TRUE(std::holds_alternative<responder::Rejection>(journaled.add_odometry(absurd)));
  EXPECT_TRUE(journaled.journal().entries.empty()) << "a refused step changed nothing, so it is not kept";

  journaled.mark_done(4);
  journaled.leave_to_others({5}, 2'000'000'000);
  journaled.coast(2'000'000'000);
  EXPECT_EQ(journaled.journal().entries.size(), 3U);
  EXPECT_FALSE(journaled.journal().overflowed);
  journaled.mark_done(6);
  EXPECT_TRUE(journaled.journal().overflowed);
  EXPECT_TRUE(journaled.journal().entries.empty()) << "an overflowed journal frees its memory";
  try {
    resume_estimator(journaled.journal(), configs, 3);
    FAIL() << "an overflowed journal must be refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("journal of 'r1': overflowed"), std::string::npos) << e.what();
  }
}

TEST(EstimatorJournal, AJournalTheNewDaemonsConfigurationRefusesIsNamedByItsEntry) {
  EstimatorConfigs configs;
  auto first =
      std::make_unique<JournaledEstimator>(make_estimator(ResponderRole::kAvalancheRescuer, "r1", configs), kRoomy);
  responder::Odometry step;
  step.rescuer_id = "r1";
  step.sequence = 1;
  step.interval_end = 1'000'000'000;
  step.translation = Vec3(3.0, 0.0, 0.0);
  ASSERT_TRUE(std::holds_alternative<EstimatorOutput>(first->add_odometry(step)));
  EstimatorConfigs stricter = configs;
  stricter.avalanche_rescuer.max_step_m = 2.0;  // the other daemon would refuse a 3 m step
  try {
    resume_estimator(first->journal(), stricter, kRoomy);
    FAIL() << "a journal the other configuration refuses must not be half replayed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("journal of 'r1', entry 0 (odometry): refused"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace sarloc::estimator
