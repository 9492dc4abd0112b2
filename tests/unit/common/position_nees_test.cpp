#include "sarloc/core/common/position_nees.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace sarloc {
namespace {

TEST(PositionNeesTest, MahalanobisDistanceAndInfiniteForAClaimOfCertainty) {
  const Mat3 P = Vec3(0.25, 1.0, 4.0).asDiagonal();
  EXPECT_NEAR(position_nees(Vec3(0.5, 1.0, -2.0), P), 3.0, 1e-12);
  EXPECT_EQ(position_nees(Vec3::Zero(), P), 0.0);
  const Mat3 collapsed = Mat3::Zero();
  EXPECT_EQ(position_nees(Vec3(0.01, 0.0, 0.0), collapsed), std::numeric_limits<double>::infinity());
  EXPECT_EQ(position_nees(Vec3::Zero(), collapsed), 0.0);
}

}  // namespace
}  // namespace sarloc
