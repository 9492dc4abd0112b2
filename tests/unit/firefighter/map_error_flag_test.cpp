#include "sarloc/core/firefighter/map_error_flag.hpp"

#include <gtest/gtest.h>

using namespace sarloc::firefighter;

namespace {

constexpr double kConcentrated = 1.0;  // m2, under converged_variance_m2 (3)

MapErrorFlag converged_flag(double spread_factor = MapErrorFlagConfig{}.spread_factor) {
  MapErrorFlagConfig config;
  config.spread_factor = spread_factor;
  MapErrorFlag flag(config);
  flag.restart(true);
  for (int k = 0; k < 5; ++k) flag.refresh({kConcentrated, false, 0.0});
  return flag;
}

}  // namespace

TEST(MapErrorFlag, ACloudWhoseVarianceHoversAtTheThresholdRaisesNothing) {
  // Seen on plans that were right: a cloud along a corridor went in and out of convergence at
  // 3.1-3.3 m2 and raised a false alarm on incident command's board each time.
  MapErrorFlag flag = converged_flag();
  for (int k = 0; k < 200; ++k) {
    EXPECT_EQ(flag.refresh({k % 2 == 0 ? 3.3 : 2.9, false, 0.0}), k % 2 == 1);
    ASSERT_FALSE(flag.up()) << "refresh " << k;
  }
  EXPECT_FALSE(flag.since_start());
  // Without the deadband (the flag of before) the first crossing raises it.
  MapErrorFlag without = converged_flag(1.0);
  without.refresh({3.3, false, 0.0});
  EXPECT_TRUE(without.up());
}

TEST(MapErrorFlag, ACloudThatSpreadsPastTheDeadbandRaisesItUntilConcentratedForClearUpdates) {
  const MapErrorFlagConfig config;
  MapErrorFlag flag = converged_flag();
  flag.refresh({config.spread_factor * config.converged_variance_m2 + 0.1, false, 0.0});
  EXPECT_TRUE(flag.up());
  for (std::uint32_t k = 0; k + 1 < config.clear_updates; ++k) {
    flag.refresh({kConcentrated, false, 0.0});
    ASSERT_TRUE(flag.up()) << "cleared after " << k + 1 << " concentrated refreshes";
  }
  flag.refresh({kConcentrated, false, 0.0});
  EXPECT_FALSE(flag.up());
  EXPECT_TRUE(flag.since_start()) << "that it was raised stays said";
}

TEST(MapErrorFlag, OnlyRefreshesUnderTheThresholdCountTowardsClearing) {
  const MapErrorFlagConfig config;
  MapErrorFlag flag = converged_flag();
  flag.refresh({10.0, false, 0.0});
  for (std::uint32_t k = 0; k < 2 * config.clear_updates; ++k)
    flag.refresh({k % 10 == 9 ? 4.0 : kConcentrated, false, 0.0});
  EXPECT_TRUE(flag.up()) << "every tenth refresh was not concentrated: never clear_updates in a row";
}

TEST(MapErrorFlag, ACloudThatSpreadsSlowlyThroughTheDeadbandRaisesItOnceThrough) {
  // A real map error may spread the cloud a little each step: it is concentrated at no refresh
  // in between, and the flag still rises once the variance leaves the deadband.
  const MapErrorFlagConfig config;
  MapErrorFlag flag = converged_flag();
  const double edge = config.spread_factor * config.converged_variance_m2;
  for (double variance = 3.5; variance < edge; variance += 0.5) {
    flag.refresh({variance, false, 0.0});
    ASSERT_FALSE(flag.up()) << variance << " m2 is inside the deadband";
  }
  flag.refresh({edge, false, 0.0});
  EXPECT_TRUE(flag.up());
}

TEST(MapErrorFlag, AStepThatRemovesMostOfTheWeightAtWallsRaisesIt) {
  MapErrorFlag flag = converged_flag();
  flag.refresh({kConcentrated, false, 0.4});
  EXPECT_FALSE(flag.up()) << "brushing a wall";
  flag.refresh({kConcentrated, false, 0.6});
  EXPECT_TRUE(flag.up()) << "the survivors are still concentrated: only the removed weight tells";
}

TEST(MapErrorFlag, ACloudSplitAcrossFloorsRaisesIt) {
  MapErrorFlag flag = converged_flag();
  EXPECT_FALSE(flag.refresh({0.5, true, 0.0}));
  EXPECT_TRUE(flag.up());
}

TEST(MapErrorFlag, ACloudNeverConcentratedRaisesNothing) {
  MapErrorFlag flag{MapErrorFlagConfig{}};
  flag.restart(true);
  for (int k = 0; k < 20; ++k) flag.refresh({50.0, k % 3 == 0, 0.9});
  EXPECT_FALSE(flag.up());
  EXPECT_FALSE(flag.ever_concentrated());
}

TEST(MapErrorFlag, APriorToldBySomeoneElseArmsOnceConcentratedForClearUpdates) {
  const MapErrorFlagConfig config;
  MapErrorFlag flag(config);
  flag.restart(false);
  for (std::uint32_t k = 0; k + 1 < config.clear_updates; ++k)
    flag.refresh({kConcentrated, false, k == 10 ? 0.9 : 0.0});
  EXPECT_FALSE(flag.up()) << "a brush with a wall before the map locked the cloud";
  flag.refresh({kConcentrated, false, 0.0});  // armed now
  flag.refresh({kConcentrated, false, 0.9});
  EXPECT_TRUE(flag.up());
  flag.restart(false);
  EXPECT_FALSE(flag.up());
  EXPECT_FALSE(flag.since_start()) << "a new start";
}
