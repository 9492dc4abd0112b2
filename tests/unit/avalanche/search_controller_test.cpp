#include "sarloc/core/avalanche/search_controller.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/avalanche/simulator.hpp"
#include "sarloc/core/common/errors.hpp"

namespace sarloc::avalanche {
namespace {

TEST(SearchConfigTest, ValidatesWithKeyAndValue) {
  EXPECT_NO_THROW(SearchConfig{}.validate());
  SearchConfig c;
  c.located_radius_m = 0.0;
  try {
    c.validate();
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("search.located_radius_m = 0"), std::string::npos);
  }
}

TEST(SearchControllerTest, AssessAppliesLocatedAndFoundCriteria) {
  SearchController ctl;
  VictimEstimate e;
  e.status = EstimatorStatus::kConverged;
  e.relative.position = Vec3(3.0, 0.0, -2.0);
  e.relative.covariance = Mat3::Identity() * 0.01;  // 95 % radius 0.28 m
  EXPECT_EQ(ctl.assess(e), EstimatorStatus::kLocated);
  e.relative.position = Vec3(0.2, 0.1, -2.0);
  EXPECT_EQ(ctl.assess(e), EstimatorStatus::kFound);
  e.relative.covariance = Mat3::Identity() * 0.1;  // 95 % radius 0.88 m
  EXPECT_EQ(ctl.assess(e), EstimatorStatus::kConverged);
  EXPECT_NEAR(SearchController::radius95_3d(Mat3::Identity()), std::sqrt(7.814727903), 1e-6);
}

TEST(SearchControllerTest, BearingIsRelativeToReceiverForwardAxis) {
  // A converged filter: walk the real loop until the controller leaves the flux line, then
  // the bearing must point the receiver at the estimate.
  Scenario s;
  s.transmitter = Vec3(-20.0, 25.0, -1.0);
  s.moment = Vec3(0.0, 0.015, 0.01);
  s.receiver = Vec3(0, 0, 1);
  s.receiver_rpy = Vec3(0, 0, -2.0);
  AvalancheSimulator sim(SimulationConfig{}, s, 21);
  SogConfig cfg;
  cfg.initial_components = 500;
  SogFilter f(cfg);
  SearchController ctl;
  Guidance g;
  int approach_steps = 0;
  for (int k = 0; k < 60; ++k) {
    const FieldMeasurement z = sim.measure();
    f.process(z);
    g = ctl.guide(f, z);
    if (g.mode == GuidanceMode::kApproach) {
      ++approach_steps;
      const double yaw = f.moments().mean[idx::kAtt + 2];
      EXPECT_NEAR(wrap_angle(g.bearing_rad + yaw - g.heading_rad), 0.0, 1e-9);
      const Vec3 mean = f.estimate().relative.position;
      EXPECT_NEAR(wrap_angle(g.heading_rad - std::atan2(mean.y(), mean.x())), 0.0, 1e-9);
      EXPECT_DOUBLE_EQ(g.step_m, 1.0);
    }
    if (g.mode == GuidanceMode::kFound) break;
    f.add_odometry(sim.walk(g.bearing_rad, g.step_m));
  }
  EXPECT_GT(approach_steps, 5);
  EXPECT_EQ(g.mode, GuidanceMode::kFound);
  EXPECT_DOUBLE_EQ(g.step_m, 0.0);
  EXPECT_LT(sim.true_horizontal_distance(), 1.0);
}

}  // namespace
}  // namespace sarloc::avalanche
