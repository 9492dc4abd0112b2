#include "sarloc/core/avalanche/search_controller.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "sarloc/core/avalanche/bearing_density.hpp"
#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/avalanche/simulator.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"

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
  EXPECT_NEAR(radius95_3d(Mat3::Identity()), std::sqrt(7.814727903), 1e-6);
}

// An estimate above the receiver is a filter's mirror solution (H(r) = H(-r)), not a victim:
// never located or found, however small its covariance or large its range.
TEST(SearchControllerTest, AnEstimateAboveTheReceiverIsNeverLocated) {
  SearchController ctl;
  VictimEstimate e;
  e.status = EstimatorStatus::kConverged;
  e.relative.covariance = Mat3::Identity() * 0.01;
  e.relative.position = Vec3(0.1, 0.1, 30.0);  // straight up: "found" by radius and distance
  EXPECT_EQ(ctl.assess(e), EstimatorStatus::kConverged);
  e.relative.position = Vec3(0.1, 0.1, -0.1);  // below, but not by 2 sigma (0.2 m)
  EXPECT_EQ(ctl.assess(e), EstimatorStatus::kConverged);
  e.relative.position = Vec3(0.1, 0.1, -1.5);
  EXPECT_EQ(ctl.assess(e), EstimatorStatus::kFound);
  e.status = EstimatorStatus::kMultimodal;
  e.relative.position = Vec3(0.1, 0.1, 3.0);
  EXPECT_EQ(ctl.assess(e), EstimatorStatus::kMultimodal) << "never raised";
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


// Precision scales with range, so "located" does too: a deep burial is located at a radius a
// shallow one is not (a fixed radius left a 5.6 m burial unfound for 150 steps).
TEST(SearchControllerLocated, RadiusScalesWithRangeAboveTheNearRangeFloor) {
  SearchController controller;  // defaults: 0.4 m floor, 10 % of range
  VictimEstimate e;
  e.status = EstimatorStatus::kConverged;
  // A 95 % 3-D radius of 0.48 m: sqrt(chi2_3(0.95) * sigma^2) = 0.48 -> sigma^2 = 0.48^2 / 7.815.
  e.relative.covariance = Mat3::Identity() * (0.48 * 0.48 / 7.8147);
  ASSERT_NEAR(radius95_3d(e.relative.covariance), 0.48, 1e-3);

  e.relative.position = Vec3(1.5, 0.0, -2.0);  // 2.5 m away: the 0.4 m floor applies
  EXPECT_EQ(controller.assess(e), EstimatorStatus::kConverged);
  e.relative.position = Vec3(1.5, 0.0, -6.6);  // 6.8 m away: 10 % of it is 0.68 m
  EXPECT_EQ(controller.assess(e), EstimatorStatus::kLocated);
  e.relative.position = Vec3(0.2, 0.0, -6.6);  // on top of it
  EXPECT_EQ(controller.assess(e), EstimatorStatus::kFound);

  SearchConfig fixed;
  fixed.located_radius_per_range = 0.0;
  EXPECT_EQ(SearchController(fixed).assess(e), EstimatorStatus::kConverged);
  fixed.located_radius_per_range = 1.5;
  EXPECT_THROW(fixed.validate(), ConfigError);
}


TEST(SearchControllerOpening, ParsesHeadingSourceAndNamesABadOne) {
  EXPECT_EQ(parse_opening_heading("flux_line"), OpeningHeading::kFluxLine);
  EXPECT_EQ(parse_opening_heading("lookahead"), OpeningHeading::kLookahead);
  EXPECT_EQ(parse_opening_heading(to_string(OpeningHeading::kLookahead)), OpeningHeading::kLookahead);
  EXPECT_EQ(parse_opening_heading(to_string(OpeningHeading::kPosteriorBearing)),
            OpeningHeading::kPosteriorBearing);
  try {
    parse_opening_heading("north");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("search.opening_heading = 'north'"), std::string::npos);
  }
  SearchConfig c;
  c.bearing_switch_ratio = 0.5;  // < 1 would turn towards a less probable bearing
  EXPECT_THROW(c.validate(), ConfigError);
}

// The opening heading is the most probable bearing of the mixture, held until another bearing
// is bearing_switch_ratio times as probable; checked step by step against an independent
// BearingDensity over a weak-signal walk (where the ring stays wide for many steps).
TEST(SearchControllerOpening, HeadsForTheMostProbableBearingWithHysteresis) {
  Scenario s;
  s.transmitter = Vec3(35.0, -30.0, -1.5);
  s.moment = Vec3(0.006, 0.0, 0.004);
  s.receiver = Vec3(0, 0, 1);
  AvalancheSimulator sim(SimulationConfig{}, s, 5);  // a walk that both holds and turns
  SogConfig cfg;
  cfg.initial_components = 600;
  SogFilter f(cfg);
  SearchConfig sc;
  sc.opening_heading = OpeningHeading::kPosteriorBearing;
  sc.approach_mahalanobis = 0.5;  // the opening this walk was picked for
  SearchController ctl(sc);
  const double kernel = sc.bearing_kernel_deg * kPi / 180.0;
  std::optional<double> held;
  int opening_steps = 0, turns = 0, holds = 0;
  for (int k = 0; k < 40; ++k) {
    const FieldMeasurement z = sim.measure();
    f.process(z);
    const BearingDensity density(f.components(), kernel);
    const Guidance g = ctl.guide(f, z);
    if (g.mode != GuidanceMode::kOpening) break;
    ++opening_steps;
    if (!held) {
      EXPECT_NEAR(g.heading_rad, wrap_angle(density.peak()), 1e-12);
    } else if (density.at(density.peak()) > sc.bearing_switch_ratio * density.at(*held)) {
      EXPECT_NEAR(g.heading_rad, wrap_angle(density.peak()), 1e-12) << "step " << k;
      ++turns;
    } else {
      EXPECT_NEAR(g.heading_rad, wrap_angle(*held), 1e-12) << "step " << k;
      ++holds;
    }
    held = g.heading_rad;
    f.add_odometry(sim.walk(g.bearing_rad, g.step_m));
  }
  // Both branches were exercised (the scenario and seed were picked for that).
  EXPECT_GE(opening_steps, 5);
  EXPECT_GE(turns, 1);
  EXPECT_GE(holds, 3);
}

}  // namespace
}  // namespace sarloc::avalanche
