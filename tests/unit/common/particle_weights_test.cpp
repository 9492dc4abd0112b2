#include "sarloc/core/common/particle_weights.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace sarloc {
namespace {

TEST(ParticleWeightsTest, NormalisedWeightsSurviveHugeLogWeights) {
  const std::vector<double> w = normalised_weights({-1e6, -1e6 + std::log(3.0), -std::numeric_limits<double>::infinity()});
  EXPECT_NEAR(w[0], 0.25, 1e-9);
  EXPECT_NEAR(w[1], 0.75, 1e-9);
  EXPECT_EQ(w[2], 0.0);
  EXPECT_THROW(normalised_weights({-std::numeric_limits<double>::infinity()}), std::invalid_argument);
}

TEST(ParticleWeightsTest, EffectiveSampleSizeIsEquationTwenty) {
  EXPECT_DOUBLE_EQ(effective_sample_size(std::vector<double>(8, 0.125)), 8.0);
  EXPECT_DOUBLE_EQ(effective_sample_size({1.0, 0.0, 0.0}), 1.0);
  EXPECT_NEAR(effective_sample_size({0.5, 0.25, 0.25}), 1.0 / 0.375, 1e-12);
}

// Systematic resampling gives each particle floor or ceiling of n w_i copies.
TEST(ParticleWeightsTest, SystematicResamplingKeepsEachShareWithinOneCopy) {
  std::mt19937_64 rng(3);
  const std::vector<double> w = {0.1, 0.45, 0.05, 0.3, 0.1};
  for (int trial = 0; trial < 100; ++trial) {
    const std::vector<std::size_t> drawn = systematic_resample(w, 40, rng);
    ASSERT_EQ(drawn.size(), 40U);
    std::vector<int> copies(w.size(), 0);
    for (std::size_t k : drawn) ++copies[k];
    for (std::size_t i = 0; i < w.size(); ++i) EXPECT_LE(std::abs(copies[i] - 40.0 * w[i]), 1.0) << i;
    for (std::size_t j = 1; j < drawn.size(); ++j) EXPECT_LE(drawn[j - 1], drawn[j]);
  }
  EXPECT_THROW(systematic_resample({0.0, 0.0}, 3, rng), std::invalid_argument);
}

TEST(ParticleWeightsTest, DrawIndexFollowsTheWeights) {
  std::mt19937_64 rng(5);
  const std::vector<double> cumulative = {1.0, 1.0, 4.0};  // weights 1, 0, 3
  std::vector<int> count(3, 0);
  for (int i = 0; i < 40000; ++i) ++count[draw_index(cumulative, rng)];
  EXPECT_EQ(count[1], 0);
  EXPECT_NEAR(count[2] / 40000.0, 0.75, 0.01);
}

}  // namespace
}  // namespace sarloc
