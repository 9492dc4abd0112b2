// SogFilter as a whole: it converges walking to the transmitter, keeps its belief without
// motion, copies independently, and takes another filter's hypotheses.
#include "sarloc/core/avalanche/sog_filter.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "sarloc/core/avalanche/odometry_accumulator.hpp"
#include "sarloc/core/avalanche/simulator.hpp"
#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "sog_scenarios.hpp"

namespace sarloc::avalanche {
namespace {

using namespace test;  // sog_scenarios.hpp

TEST(SogFilterTest, ConvergesOnTruthWhileWalkingTowardsIt) {
  // A straight walk towards the transmitter (no controller): the filter alone must localise.
  SimulationConfig sc;
  AvalancheSimulator sim(sc, fixed_scenario(), 11);
  SogConfig cfg;
  cfg.initial_components = 600;  // keep the unit test fast
  SogFilter f(cfg);
  f.process(sim.measure());
  for (int k = 0; k < 33; ++k) {
    f.add_odometry(sim.walk(bearing_to_truth(sim), 1.0));
    f.process(sim.measure());
  }
  const VictimEstimate e = f.estimate(3);
  const Vec3 err = e.relative.position - sim.true_relative_position();
  EXPECT_LT(err.norm(), 0.5) << "estimate " << e.relative.position.transpose() << " truth "
                             << sim.true_relative_position().transpose();
  EXPECT_EQ(e.status, EstimatorStatus::kConverged);
  EXPECT_LT(f.size(), 100u);
  // The opening's memory is given back as the mixture narrows (a daemon holds one filter per
  // rescuer and signal for the whole incident).
  EXPECT_LE(f.components().capacity(), 4 * f.size() + 64) << "kept room for " << f.components().capacity();
  ASSERT_FALSE(e.top_components.empty());
  EXPECT_GE(e.top_components.front().weight, e.top_components.back().weight);
  // The error is consistent with the reported covariance (generous: one trial, 3 dof).
  EXPECT_LT(err.dot(e.relative.covariance.ldlt().solve(err)), 16.0);
}

TEST(SogFilterTest, ZeroDisplacementWithoutOdometryKeepsBelief) {
  AvalancheSimulator sim(SimulationConfig{}, fixed_scenario(), 5);
  SogConfig cfg;
  cfg.initial_components = 200;
  SogFilter f(cfg);
  f.process(sim.measure());
  const Vec3 before = f.estimate().relative.position;
  f.process(sim.measure());  // no odometry in between: idle displacement
  EXPECT_LT((f.estimate().relative.position - before).norm(), 15.0);
  EXPECT_EQ(f.steps(), 2u);
}

TEST(SogFilterTest, CopiesAreIndependent) {
  AvalancheSimulator sim(SimulationConfig{}, fixed_scenario(), 9);
  SogConfig cfg;
  cfg.initial_components = 150;
  SogFilter a(cfg);
  a.process(sim.measure());
  SogFilter b = a;
  a.add_odometry(sim.walk(0.0, 1.0));
  a.process(sim.measure());
  EXPECT_EQ(b.steps(), 1u);
  EXPECT_EQ(a.steps(), 2u);
}

// Evidence that conflicts (RescuerSearch's found witness): two filters of one signal, given the
// same odometry, converged 2 m apart, one on the transmitter heard (A), one on another (B). Each
// takes half of the joined mixture, and A's samples that follow decide for A, whichever filter
// the other's hypotheses were added to.
TEST(SogFilterTest, AddedHypothesesKeepHalfTheMassAndTheSamplesToComeDecide) {
  for (const bool into_right : {true, false}) {
    AvalancheSimulator sim_a(SimulationConfig{}, fixed_scenario(), 21);
    AvalancheSimulator sim_b(SimulationConfig{}, second_transmitter(), 21);  // one walk, two fields
    SogConfig cfg;
    cfg.initial_components = 600;
    SogFilter right(cfg), wrong(cfg);
    right.process(sim_a.measure());
    wrong.process(sim_b.measure());
    for (int k = 0; k < 40; ++k) {
      const double step = sim_a.true_horizontal_distance() > 2.0 ? 1.0 : 0.3;
      const Odometry o = sim_a.walk(bearing_to_truth(sim_a), step);
      sim_b.walk(bearing_to_truth(sim_a), step);
      right.add_odometry(o);
      wrong.add_odometry(o);
      right.process(sim_a.measure());
      wrong.process(sim_b.measure());
    }
    const Vec3 truth = sim_a.true_relative_position();
    ASSERT_LT((right.estimate(0).relative.position - truth).norm(), 0.5);
    ASSERT_GT((wrong.estimate(0).relative.position - truth).norm(), 1.0) << "the other filter converged elsewhere";
    SogFilter joined = into_right ? right : wrong;
    const SogFilter& added = into_right ? wrong : right;
    ASSERT_TRUE(joined.add_hypotheses(added));
    EXPECT_EQ(joined.size(), right.size() + wrong.size());
    double mass = 0.0, of_added = 0.0;
    for (std::size_t i = 0; i < joined.size(); ++i) {
      const double w = std::exp(joined.components()[i].log_weight);
      mass += w;
      if (i >= joined.size() - added.size()) of_added += w;
    }
    EXPECT_NEAR(mass, 1.0, 1e-9);
    EXPECT_NEAR(of_added, 0.5, 1e-9);
    EXPECT_GT(radius95_3d(joined.estimate(0).relative.covariance), 1.0) << "two places, not one";
    // A's samples from around it decide.
    for (int k = 0; k < 12; ++k) {
      const Odometry o = sim_a.walk(bearing_to_truth(sim_a) + 2.0 * k, 0.5);
      joined.add_odometry(o);
      joined.process(sim_a.measure());
    }
    const VictimEstimate e = joined.estimate(0);
    EXPECT_LT((e.relative.position - sim_a.true_relative_position()).norm(), 0.5) << "joined into the right one: " << into_right;
    EXPECT_LT(radius95_3d(e.relative.covariance), 1.0);
  }
  // Only filters of one frame join: another stamp is refused, and so is an empty filter.
  SogFilter one, other, empty;
  AvalancheSimulator sim(SimulationConfig{}, fixed_scenario(), 3);
  one.process(sim.measure());
  sim.walk(0.0, 1.0);
  other.process(sim.measure());
  EXPECT_FALSE(one.add_hypotheses(other));
  EXPECT_FALSE(one.add_hypotheses(empty));
  EXPECT_FALSE(empty.add_hypotheses(one));
}

}  // namespace
}  // namespace sarloc::avalanche
