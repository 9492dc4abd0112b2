#include "sarloc/core/common/chi_square.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "sarloc/core/common/errors.hpp"

namespace sarloc {
namespace {

// Reference values from standard chi-square tables (R: qchisq).
TEST(ChiSquareTest, QuantilesMatchTables) {
  EXPECT_NEAR(chi_square_quantile(0.95, 1), 3.841459, 1e-5);
  EXPECT_NEAR(chi_square_quantile(0.95, 2), 5.991465, 1e-5);
  EXPECT_NEAR(chi_square_quantile(0.95, 3), 7.814728, 1e-5);
  EXPECT_NEAR(chi_square_quantile(0.025, 3), 0.2157953, 1e-6);
  EXPECT_NEAR(chi_square_quantile(0.975, 3), 9.348404, 1e-5);
  EXPECT_NEAR(chi_square_quantile(0.025, 300), 253.9123, 1e-3);
  EXPECT_NEAR(chi_square_quantile(0.975, 300), 349.8745, 1e-3);
  EXPECT_NEAR(chi_square_quantile(0.5, 10), 9.341818, 1e-5);
}

TEST(ChiSquareTest, CdfInvertsQuantile) {
  for (double dof : {1.0, 2.0, 3.0, 7.5, 60.0, 3000.0})
    for (double p : {0.001, 0.025, 0.3, 0.5, 0.9, 0.975, 0.999})
      EXPECT_NEAR(chi_square_cdf(chi_square_quantile(p, dof), dof), p, 1e-10) << dof << " " << p;
  EXPECT_DOUBLE_EQ(chi_square_cdf(0.0, 3.0), 0.0);
}

TEST(ChiSquareTest, RejectsBadArguments) {
  EXPECT_THROW(chi_square_quantile(0.0, 3), InputError);
  EXPECT_THROW(chi_square_quantile(1.0, 3), InputError);
  EXPECT_THROW(chi_square_quantile(0.5, 0), InputError);
  EXPECT_THROW(chi_square_cdf(-1.0, 3), InputError);
  EXPECT_THROW(chi_square_cdf(1.0, std::numeric_limits<double>::quiet_NaN()), InputError);
}

}  // namespace
}  // namespace sarloc
