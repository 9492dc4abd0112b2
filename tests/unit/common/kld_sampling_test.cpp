#include "sarloc/core/common/kld_sampling.hpp"

#include <gtest/gtest.h>

#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"

namespace sarloc {
namespace {

// Fox's eq. (13) is the chi-square quantile chi2_{k-1, 1-delta} / (2 epsilon); the
// Wilson-Hilferty form must stay within 1 % of the exact quantile over the bin counts a filter sees.
TEST(KldSampleCount, MatchesTheExactChiSquareQuantile) {
  const KldSampleCount needed(0.05, 0.99);
  for (std::size_t bins : {3U, 10U, 50U, 300U, 2000U, 20000U}) {
    const double exact = chi_square_quantile(0.99, static_cast<double>(bins - 1)) / (2.0 * 0.05);
    EXPECT_NEAR(needed(bins), exact, 0.01 * exact) << bins << " bins";
  }
}

TEST(KldSampleCount, GrowsWithTheBinsAndShrinksWithALooserBound) {
  const KldSampleCount tight(0.02, 0.99), loose(0.1, 0.99);
  EXPECT_EQ(tight(1), 0.0);
  EXPECT_LT(tight(10), tight(100));
  EXPECT_GT(tight(100), loose(100));
  // Roughly (k - 1) / (2 epsilon) for many bins: 20000 bins need about 10^5 samples at 0.1.
  EXPECT_NEAR(loose(20000), 19999 / 0.2, 0.05 * 19999 / 0.2);
}

TEST(KldSampleCount, RejectsABoundOrConfidenceOutsideItsRange) {
  EXPECT_THROW(KldSampleCount(0.0, 0.99), InputError);
  EXPECT_THROW(KldSampleCount(0.05, 1.0), InputError);
  EXPECT_THROW(KldSampleCount(0.05, 0.3), InputError);
}

}  // namespace
}  // namespace sarloc
