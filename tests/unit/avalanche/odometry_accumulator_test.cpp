// OdometryAccumulator: composes odometry samples into one displacement and its covariance.
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

TEST(OdometryAccumulatorTest, ComposesSamplesAndPropagatesCovariance) {
  OdometryAccumulator acc;
  Odometry a;
  a.sequence = 1;
  a.translation = Vec3(1, 0, 0);
  a.rotation_rpy = Vec3(0, 0, kPi / 2);
  a.covariance = Mat6::Identity() * 1e-4;
  Odometry b = a;
  b.sequence = 2;
  acc.add(a);
  acc.add(b);
  const Displacement d = acc.take();
  EXPECT_EQ(d.samples, 2u);
  EXPECT_LT((d.mean.head<3>() - Vec3(1, 1, 0)).norm(), 1e-12);
  EXPECT_NEAR(d.mean[5], kPi, 1e-12);
  // Two steps: more uncertain than one, and the yaw uncertainty leaks into translation.
  EXPECT_GT(d.covariance(1, 1), 1e-4);
  const Displacement idle = acc.take();
  EXPECT_EQ(idle.samples, 0u);
  EXPECT_TRUE(idle.mean.isZero());
  EXPECT_GT(idle.covariance.diagonal().minCoeff(), 0.0);
  Odometry old = a;  // sequence 1 again: out of order
  EXPECT_THROW(acc.add(old), InputError);
}

}  // namespace
}  // namespace sarloc::avalanche
