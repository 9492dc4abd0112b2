// The SOG filter's priors: the surface and moment support of each component.
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

// Surface term (SogConfig::surface_constraint): after every step, including the components a
// merge produced, each component's log_support is log P(p_z below the surface) of its own
// Gaussian (one implementation, SogFilter::prior_log_support).
TEST(SogFilterTest, SurfaceSupportIsThatOfEachComponentAfterMerging) {
  AvalancheSimulator sim(SimulationConfig{}, fixed_scenario(), 13);
  SogConfig cfg;
  cfg.initial_components = 400;
  cfg.surface_constraint = true;
  cfg.moment_constraint = false;
  cfg.merge_cell_m = 10.0;  // merge often
  cfg.merge_mahalanobis = 50.0;
  SogFilter f(cfg);
  f.process(sim.measure());
  std::size_t merged = 0;
  for (int k = 0; k < 8; ++k) {
    f.add_odometry(sim.walk(bearing_to_truth(sim), 1.0));
    merged += f.process(sim.measure()).merged;
    for (const SogComponent& c : f.components()) {
      const double u = (-cfg.antenna_height_m - c.x[idx::kPos + 2]) /
                       std::sqrt(c.P(idx::kPos + 2, idx::kPos + 2));
      ASSERT_NEAR(c.log_support, log_normal_cdf(u), 1e-12);
    }
  }
  EXPECT_GT(merged, 0u);
}

// Moment term (SogConfig::moment_constraint): each component's log_support (folded into its
// weight) is log P(|m| within the standard's bounds +- moment_margin) of its own Gaussian, |m|
// linearised along its mean, checked against the normal CDF difference directly; far outside it
// stays finite.
TEST(SogFilterTest, MomentSupportIsTheStandardsBoundsUnderEachGaussian) {
  AvalancheSimulator sim(SimulationConfig{}, fixed_scenario(), 13);
  SogConfig cfg;
  cfg.initial_components = 400;
  cfg.moment_constraint = true;
  SogFilter f(cfg);
  f.process(sim.measure());
  const double lo = cfg.standard.moment_min() * (1.0 - cfg.moment_margin);
  const double hi = cfg.standard.moment_max() * (1.0 + cfg.moment_margin);
  auto phi = [](double u) { return 0.5 * std::erfc(-u / std::sqrt(2.0)); };
  std::size_t checked = 0;
  for (int k = 0; k < 6; ++k) {
    f.add_odometry(sim.walk(bearing_to_truth(sim), 1.0));
    f.process(sim.measure());
    for (const SogComponent& c : f.components()) {
      const Vec3 m = c.x.segment<3>(idx::kMom);
      const double sd = std::sqrt(m.normalized().dot(c.P.block<3, 3>(idx::kMom, idx::kMom) * m.normalized()));
      const double p = phi((hi - m.norm()) / sd) - phi((lo - m.norm()) / sd);
      ASSERT_TRUE(std::isfinite(c.log_support));
      if (p < 1e-300) {  // the direct difference underflows; the filter's tail form does not
        EXPECT_LT(c.log_support, -690.0);
        continue;
      }
      ASSERT_NEAR(c.log_support, std::log(p), 1e-9);
      ++checked;
    }
  }
  EXPECT_GT(checked, 100u);
}

}  // namespace
}  // namespace sarloc::avalanche
