// The device's half of the search plan (strip_guidance.hpp): rescuers who walk only where the
// guidance points, from the plan incident command publishes, search the whole deposit; the
// guidance is the rescuer's own strip's, relative to its heading, walks on down the strip once
// at the next point, and gives nothing past the bottom, for a strip done or someone else's.
#include "sarloc/core/incident/strip_guidance.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "sarloc/core/common/angle.hpp"

namespace sarloc::incident {
namespace {

responder::ResponderPosition fix_at(const Vec2& p, double heading_rad) {
  responder::ResponderPosition f;
  f.responder_id = "r1";
  f.position.position = Vec3(p.x(), p.y(), 0.0);
  f.position.covariance = Vec3::Constant(4.0).asDiagonal();
  f.heading_rad = heading_rad;
  return f;
}

// One strip 20 m wide, x in [0, 20], top (10, 100), bottom (10, 0), walked by r1.
SearchPlanPicture one_strip(std::optional<Vec2> next) {
  SearchPlanPicture p;
  PlannedStrip s;
  s.strip.outline = {{0, 0}, {20, 0}, {20, 100}, {0, 100}};
  s.strip.top = {10, 100};
  s.strip.bottom = {10, 0};
  s.strip.width_m = 20.0;
  s.rescuer_id = "r1";
  p.plan.strips.push_back(s);
  p.next_points.push_back(next);
  return p;
}

TEST(StripGuidance, PointsToTheNextPointRelativeToTheRescuersHeading) {
  const StripGuidanceConfig config{0.8, 3.0};
  // Facing north at (10, 50); the next point is 20 m east: turn right a quarter.
  const auto g = strip_guidance(one_strip(Vec2(30, 50)), "r1", fix_at({10, 50}, 0.5 * kPi), config);
  ASSERT_TRUE(g);
  EXPECT_EQ(g->mode, responder::GuidanceMode::kPrimarySearch);
  EXPECT_EQ(g->signal_id, 0u);
  EXPECT_NEAR(g->heading_rad, 0.0, 1e-12);
  EXPECT_NEAR(g->bearing_rad, -0.5 * kPi, 1e-12);
  EXPECT_NEAR(g->distance_m, 20.0, 1e-12);
  EXPECT_DOUBLE_EQ(g->step_m, 0.8);
}

TEST(StripGuidance, AtTheNextPointWalksOnDownTheStripAndStopsPastItsBottom) {
  const StripGuidanceConfig config{1.0, 3.0};
  const auto at_point = strip_guidance(one_strip(Vec2(10, 50)), "r1", fix_at({11, 49}, 0.0), config);
  ASSERT_TRUE(at_point);
  EXPECT_NEAR(at_point->heading_rad, -0.5 * kPi, 1e-12) << "down the strip (south)";
  EXPECT_FALSE(strip_guidance(one_strip(Vec2(10, 0)), "r1", fix_at({10, -1}, 0.0), config)) << "past the bottom";
}

// r2 helps on r1's strip: it walks to its own next point, and from there up the strip, not down.
TEST(StripGuidance, AHelperWalksTheStripUpFromTheBottomAndStopsPastItsTop) {
  const StripGuidanceConfig config{1.0, 3.0};
  auto helped = one_strip(Vec2(10, 80));
  helped.plan.strips[0].helper_id = "r2";
  helped.helper_next_points.push_back(Vec2(10, 20));
  const auto to_point = strip_guidance(helped, "r2", fix_at({30, 20}, kPi), config);
  ASSERT_TRUE(to_point);
  EXPECT_NEAR(to_point->distance_m, 20.0, 1e-12) << "to its own next point, not r1's";
  const auto at_point = strip_guidance(helped, "r2", fix_at({10, 21}, 0.0), config);
  ASSERT_TRUE(at_point);
  EXPECT_NEAR(at_point->heading_rad, 0.5 * kPi, 1e-12) << "up the strip (north)";
  const auto walker = strip_guidance(helped, "r1", fix_at({10, 81}, 0.0), config);
  ASSERT_TRUE(walker);
  EXPECT_NEAR(walker->heading_rad, -0.5 * kPi, 1e-12) << "its rescuer still walks down";
  helped.helper_next_points[0] = Vec2(10, 100);
  EXPECT_FALSE(strip_guidance(helped, "r2", fix_at({10, 101}, 0.0), config)) << "past the top";
  helped.helper_next_points.clear();
  EXPECT_FALSE(strip_guidance(helped, "r2", fix_at({10, 20}, 0.0), config))
      << "a plan without the helper's next points";
}

TEST(StripGuidance, GivesNothingForAnotherRescuersADoneOrAFinishedStripOrABadFix) {
  const StripGuidanceConfig config;
  EXPECT_FALSE(strip_guidance(one_strip(Vec2(10, 50)), "r2", fix_at({10, 60}, 0.0), config)) << "not r2's";
  auto done = one_strip(Vec2(10, 50));
  done.plan.strips[0].done = true;
  EXPECT_FALSE(strip_guidance(done, "r1", fix_at({10, 60}, 0.0), config)) << "done";
  EXPECT_FALSE(strip_guidance(one_strip(std::nullopt), "r1", fix_at({10, 60}, 0.0), config)) << "no row left";
  EXPECT_FALSE(strip_guidance(one_strip(Vec2(10, 50)), "r1", fix_at({NAN, 60}, 0.0), config));
  EXPECT_FALSE(strip_guidance(one_strip(Vec2(10, 50)), "r1", fix_at({10, 60}, INFINITY), config));
  auto short_list = one_strip(Vec2(10, 50));
  short_list.next_points.clear();
  EXPECT_FALSE(strip_guidance(short_list, "r1", fix_at({10, 60}, 0.0), config)) << "a plan without next points";
}

// Seven rescuers together at the top of a 150 x 200 m deposit, each turning by the bearing the
// guidance gives from its own heading (as the simulated rescuer walks), the plan re-published
// every second from their fixes: the whole deposit is searched, nobody strays from it.
TEST(StripGuidance, RescuersWhoOnlyFollowItSearchTheWholeDeposit) {
  SearchPlanner planner(Deposit({{0, 0}, {150, 0}, {150, 200}, {0, 200}}, "deposit"), SearchPlanConfig{});
  struct Walker {
    Vec2 at;
    double heading;
  };
  std::map<std::string, Walker> walkers;
  for (int k = 0; k < 7; ++k) walkers["r" + std::to_string(k + 1)] = {Vec2(66.0 + 2.0 * k, 205.0), -0.5 * kPi};
  for (const auto& [id, w] : walkers) planner.on_position(id, w.at);
  planner.update();
  const StripGuidanceConfig config{1.0, 3.0};
  double farthest_outside = 0.0;
  int seconds = 0;
  for (; seconds < 600 && planner.plan().searched < 0.98; ++seconds) {
    const SearchPlanPicture picture = planner.picture("i", seconds);
    for (auto& [id, w] : walkers) {
      const auto g = strip_guidance(picture, id, fix_at(w.at, w.heading), config);
      if (!g) continue;
      w.heading = wrap_angle(w.heading + g->bearing_rad);
      w.at += g->step_m * Vec2(std::cos(w.heading), std::sin(w.heading));
      planner.on_position(id, w.at);
      farthest_outside = std::max({farthest_outside, -w.at.x(), w.at.x() - 150.0, -w.at.y(), w.at.y() - 205.0});
    }
    planner.update();
  }
  EXPECT_GE(planner.plan().searched, 0.98);
  EXPECT_LT(seconds, 300) << "seven 200 m strips walked side by side";
  EXPECT_LT(farthest_outside, 1.0) << "m outside the deposit (or above the rescuers' start)";
}

}  // namespace
}  // namespace sarloc::incident
