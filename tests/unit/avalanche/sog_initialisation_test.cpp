// The SOG filter's ring: around the truth within the moment bounds, and deep enough near a
// deep victim that its covariance holds the truth.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "sarloc/core/avalanche/odometry_accumulator.hpp"
#include "sarloc/core/avalanche/simulator.hpp"
#include "sarloc/core/avalanche/sog_filter.hpp"
#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "sarloc/core/common/position_nees.hpp"
#include "sog_scenarios.hpp"

namespace sarloc::avalanche {
namespace {

using namespace test;  // sog_scenarios.hpp

TEST(SogFilterTest, InitialisesRingAroundTruthWithMomentBounds) {
  SimulationConfig sc;
  AvalancheSimulator sim(sc, fixed_scenario(), 3);
  SogConfig cfg;
  SogFilter f(cfg);
  EXPECT_FALSE(f.initialised());
  EXPECT_EQ(f.estimate().status, EstimatorStatus::kInitialising);
  const auto r = f.process(sim.measure());
  EXPECT_TRUE(r.initialised_now);
  // About initial_components (the spacing is adapted to the accepted count).
  EXPECT_NEAR(static_cast<double>(f.size()), cfg.initial_components, 0.06 * cfg.initial_components);
  const double d_true = sim.true_relative_position().head<2>().norm();
  double rho_min = 1e9, rho_max = 0.0, wsum = 0.0;
  for (const auto& c : f.components()) {
    const double rho = c.x.segment<2>(idx::kPos).norm();
    rho_min = std::min(rho_min, rho);
    rho_max = std::max(rho_max, rho);
    const double m = c.x.segment<3>(idx::kMom).norm();
    EXPECT_GE(m, cfg.standard.moment_min() * (1 - cfg.moment_margin) - 1e-12);
    EXPECT_LE(m, cfg.standard.moment_max() * (1 + cfg.moment_margin) + 1e-12);
    EXPECT_TRUE(c.P.allFinite());
    EXPECT_GT(c.P.diagonal().minCoeff(), 0.0);
    wsum += std::exp(c.log_weight);
  }
  EXPECT_NEAR(wsum, 1.0, 1e-9);
  EXPECT_LT(rho_min, d_true);
  EXPECT_GT(rho_max, d_true);
}

// The NEES of a filter first heard a few metres from a victim 4 m deep, after the walk a
// rescuer makes there (onto it, then around it 1.5 m out), over runs with random azimuths,
// moments and noise: the filter's mixture of depth layers must cover that victim with
// Gaussians narrow enough for 1/r^3 to be near linear over each.
double mean_nees_near_a_deep_victim(const SogConfig& cfg, int runs) {
  double sum = 0.0;
  for (int run = 0; run < runs; ++run) {
    std::mt19937_64 rng(700 + run);
    const Scenario s = test::random_victim_nearby(rng, 4.5, 4.0, cfg.standard.moment_min(), cfg.standard.moment_max());
    AvalancheSimulator sim(SimulationConfig{}, s, 900 + run);
    SogFilter f(cfg);
    f.process(sim.measure());
    test::walk_onto_and_around(sim, s.transmitter, 6, [&](const Odometry& odometry) {
      f.add_odometry(odometry);
      f.process(sim.measure());
    });
    const VictimEstimate e = f.estimate();
    sum += position_nees(e.relative.position - sim.true_relative_position(), e.relative.covariance);
  }
  return sum / runs;
}

TEST(SogFilterTest, FirstHeardNearADeepVictimTheCovarianceHoldsTheTruth) {
  constexpr int kRuns = 12;
  const double upper = chi_square_quantile(0.975, 3 * kRuns) / kRuns;
  SogConfig cfg;
  cfg.initial_components = 900;  // keep the unit test fast
  cfg.near_field_initial_components = 900;
  EXPECT_LT(mean_nees_near_a_deep_victim(cfg, kRuns), upper);
  // One 0-3 m layer at every range, as before the near-field layers: overconfident there.
  cfg.near_field_depth_sigma_per_range = 0.0;
  EXPECT_GT(mean_nees_near_a_deep_victim(cfg, kRuns), upper);
}

// A ring heard from afar opens with initial_components; one heard a few metres from a victim is
// cut into depth layers and opens with near_field_initial_components, shared among them.
TEST(SogFilterTest, ANearFieldRingOpensWithItsOwnCount) {
  SogConfig cfg;
  cfg.initial_components = 300;
  cfg.near_field_initial_components = 900;
  SimulationConfig sc;
  AvalancheSimulator far(sc, fixed_scenario(), 3);
  SogFilter f_far(cfg);
  f_far.process(far.measure());
  EXPECT_NEAR(static_cast<double>(f_far.size()), 300.0, 30.0);
  std::mt19937_64 rng(701);
  const Scenario s = test::random_victim_nearby(rng, 4.5, 4.0, cfg.standard.moment_min(), cfg.standard.moment_max());
  AvalancheSimulator near(sc, s, 901);
  SogFilter f_near(cfg);
  f_near.process(near.measure());
  EXPECT_GT(f_near.size(), 600U) << "a near-field ring of " << f_near.size() << " Gaussians";
  EXPECT_LE(f_near.size(), 990U);
}

}  // namespace
}  // namespace sarloc::avalanche
