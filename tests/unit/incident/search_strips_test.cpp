// The deposit, its strips along the fall line, who walks which, and what has been searched
// (issue 63, item 2), on rectangles whose answers can be counted by hand and a concave deposit.
#include "sarloc/core/incident/search_strips.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/incident/search_coverage.hpp"

namespace sarloc::incident {
namespace {

// 150 m east-west, 200 m north-south, its south-west corner at the origin.
std::vector<Vec2> rectangle() { return {{0, 0}, {150, 0}, {150, 200}, {0, 200}}; }

double total_area(const std::vector<Strip>& strips) {
  double a = 0.0;
  for (const Strip& s : strips) a += s.area_m2;
  return a;
}

TEST(Deposit, RefusesWhatIsNotASimplePolygonNamingTheKey) {
  EXPECT_THROW(Deposit({{0, 0}, {10, 0}}, "deposit"), ConfigError);
  EXPECT_THROW(Deposit({{0, 0}, {10, 0}, {std::nan(""), 5}}, "deposit"), ConfigError);
  try {
    Deposit({{0, 0}, {10, 10}, {10, 0}, {0, 10}}, "mission.deposit");  // a bow tie: its edges cross
    FAIL() << "a bow tie was taken for a deposit";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("mission.deposit: not a simple polygon (its edges cross)"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(Deposit({{0, 0}, {10, 0}, {20, 0}}, "deposit"), ConfigError) << "no area";
}

TEST(Deposit, TakesEitherOrientationClosedOrNot) {
  std::vector<Vec2> clockwise = rectangle();
  std::reverse(clockwise.begin(), clockwise.end());
  clockwise.push_back(clockwise.front());
  const Deposit d(clockwise, "deposit");
  EXPECT_EQ(d.vertices().size(), 4u);
  EXPECT_NEAR(d.area_m2(), 30000.0, 1e-6);
  EXPECT_TRUE(d.contains({75, 100}));
  EXPECT_TRUE(d.contains({0, 100})) << "the boundary is the deposit's";
  EXPECT_FALSE(d.contains({-1, 100}));
}

// Without a fall line the strips run along the long axis (north-south here), entered from the
// end nearer the rescuers, as few as fit at most 40 m wide: 150 / 40 -> 4 strips of 37.5 m.
TEST(SearchStrips, RunAlongTheLongAxisFromTheRescuersEnd) {
  const Deposit d(rectangle(), "deposit");
  const auto strips = plan_strips(d, StripPlanConfig{}, Vec2(75, 230));  // rescuers north of it
  ASSERT_EQ(strips.size(), 4u);
  EXPECT_NEAR(total_area(strips), d.area_m2(), 1e-6);
  for (const Strip& s : strips) {
    EXPECT_NEAR(s.width_m, 37.5, 1e-9);
    EXPECT_NEAR(s.top.y(), 200.0, 1e-6) << "entered from the north";
    EXPECT_NEAR(s.bottom.y(), 0.0, 1e-6);
    EXPECT_NEAR(s.top.x(), s.bottom.x(), 1e-6) << "down the fall line";
  }
  std::vector<double> centres;
  for (const Strip& s : strips) centres.push_back(s.top.x());
  std::sort(centres.begin(), centres.end());
  EXPECT_NEAR(centres.front(), 18.75, 1e-6);
  EXPECT_NEAR(centres.back(), 131.25, 1e-6);
  // The same rescuers south of it enter from the south.
  EXPECT_NEAR(plan_strips(d, StripPlanConfig{}, Vec2(75, -30)).front().top.y(), 0.0, 1e-6);
}

TEST(SearchStrips, FollowAGivenFallLineAndRefuseAWidthOutOfRange) {
  const Deposit d(rectangle(), "deposit");
  StripPlanConfig east;
  east.fall_line_deg = 0.0;  // downhill to the east: strips across the 200 m, 5 of 40 m
  const auto strips = plan_strips(d, east, Vec2(75, 230));
  ASSERT_EQ(strips.size(), 5u);
  for (const Strip& s : strips) {
    EXPECT_NEAR(s.width_m, 40.0, 1e-9);
    EXPECT_NEAR(s.top.x(), 0.0, 1e-6) << "the west end is the top";
  }
  StripPlanConfig narrow;
  narrow.strip_width_m = 2.0;
  EXPECT_THROW(plan_strips(d, narrow, Vec2::Zero()), ConfigError);
}

// A U-shaped deposit: the bands through its two arms are cut in two, each piece a strip.
TEST(SearchStrips, AConcaveDepositGivesAStripPerPiece) {
  const Deposit u({{0, 0}, {120, 0}, {120, 100}, {80, 100}, {80, 30}, {40, 30}, {40, 100}, {0, 100}}, "deposit");
  StripPlanConfig across;
  across.fall_line_deg = 0.0;  // strips run east-west, cut by the notch above y = 30
  across.strip_width_m = 25.0;
  const auto strips = plan_strips(u, across, Vec2(-20, 50));
  EXPECT_NEAR(total_area(strips), u.area_m2(), 1e-6);
  EXPECT_EQ(strips.size(), 6u) << "4 bands of 25 m: the 2 above the notch's floor (y 30) cut in two, 2 whole";
}

TEST(SearchStrips, EachRescuerTakesAStripNearestTogetherAndClosedStripsAreLeft) {
  const Deposit d(rectangle(), "deposit");
  const auto strips = plan_strips(d, StripPlanConfig{}, Vec2(75, 230));
  // Strip tops at x = 18.75, 56.25, 93.75, 131.25 (some order); rescuers above three of them.
  std::vector<Vec2> rescuers{{20, 210}, {130, 210}, {95, 210}};
  const auto of = assign_strips(strips, rescuers);
  for (std::size_t r = 0; r < rescuers.size(); ++r) {
    ASSERT_TRUE(of[r].has_value());
    EXPECT_NEAR(strips[*of[r]].top.x(), rescuers[r].x(), 2.0) << "rescuer " << r;
  }
  std::vector<bool> open(strips.size(), true);
  open[*of[0]] = false;  // searched already: rescuer 0 takes the next nearest open one
  const auto next = assign_strips(strips, {rescuers[0]}, open);
  ASSERT_TRUE(next[0].has_value());
  EXPECT_NE(*next[0], *of[0]);
  EXPECT_NEAR(strips[*next[0]].top.x(), 56.25, 1e-6);
  // Five rescuers, four strips: one is free.
  const auto five = assign_strips(strips, {{0, 210}, {40, 210}, {80, 210}, {120, 210}, {160, 210}});
  EXPECT_EQ(std::count(five.begin(), five.end(), std::nullopt), 1);
  EXPECT_THROW(assign_strips(strips, {Vec2(std::nan(""), 0)}), InputError);
}

// Walking every strip's centreline hearing half a strip to either side searches the deposit;
// one strip walked is that strip's share.
TEST(SearchCoverage, WalkingEveryCentrelineSearchesTheWholeDeposit) {
  const Deposit d(rectangle(), "deposit");
  const auto strips = plan_strips(d, StripPlanConfig{}, Vec2(75, 230));
  SearchCoverage coverage(d, strips, 1.0);
  EXPECT_EQ(coverage.cells(), 150u * 200u);
  coverage.add_walk(strips[0].top, strips[0].bottom, 0.5 * strips[0].width_m);
  EXPECT_NEAR(coverage.searched(0), 1.0, 1e-9);
  EXPECT_NEAR(coverage.searched(), 0.25, 0.01);
  EXPECT_LT(coverage.searched(1), 0.03) << "at most its column of cells on the line between the two (1 of 38)";
  for (std::size_t s = 1; s < strips.size(); ++s)
    coverage.add_walk(strips[s].top, strips[s].bottom, 0.5 * strips[s].width_m);
  EXPECT_NEAR(coverage.searched(), 1.0, 1e-9);
  EXPECT_THROW(coverage.add_walk(Vec2::Zero(), Vec2(std::nan(""), 0), 20.0), InputError);
  EXPECT_THROW(SearchCoverage(d, strips, 0.1), InputError);
  EXPECT_THROW((void)coverage.searched(9), InputError);
}

// An outline redrawn with its south-east corner pulled 30 m out: what was searched inside the
// old outline stays searched in the new grid, what the new outline adds is not.
TEST(SearchCoverage, ARedrawnOutlineTakesOverWhatWasSearchedInsideTheOldOne) {
  const Deposit before_deposit(rectangle(), "deposit");
  const auto before_strips = plan_strips(before_deposit, StripPlanConfig{}, Vec2(75, 230));
  SearchCoverage before(before_deposit, before_strips, 1.0);
  before.add_walk({130, 200}, {130, 60}, 20.0);  // the eastern strip, down to y = 40 with its reach
  const Deposit after_deposit({{0, 0}, {180, -30}, {150, 200}, {0, 200}}, "deposit_drawing.outline");
  const auto after_strips = plan_strips(after_deposit, StripPlanConfig{}, Vec2(75, 230));
  SearchCoverage after(after_deposit, after_strips, 1.0);
  after.carry_over(before);
  EXPECT_TRUE(after.searched_at({130.5, 100.5}));
  EXPECT_TRUE(after.searched_at({149.5, 70.5}));
  EXPECT_FALSE(after.searched_at({150.5, 70.5})) << "new ground: nobody walked there for it";
  EXPECT_FALSE(after.searched_at({130.5, 30.5})) << "below the walk's reach";
  EXPECT_FALSE(after.searched_at({60.5, 100.5}));
  // The same cells, counted against the larger outline.
  const double searched_m2 = before.searched() * static_cast<double>(before.cells());
  EXPECT_NEAR(after.searched() * static_cast<double>(after.cells()), searched_m2, 0.02 * searched_m2);
  after.carry_over(before);  // twice: nothing counted twice
  EXPECT_NEAR(after.searched() * static_cast<double>(after.cells()), searched_m2, 0.02 * searched_m2);
}

}  // namespace
}  // namespace sarloc::incident
