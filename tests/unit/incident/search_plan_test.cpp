// Incident command's primary-search plan (search_plan.hpp): rescuers who walk where the plan
// sends them search the whole deposit with nobody idle; a strip done frees its rescuer for an
// open one; a released rescuer's strip opens; late arrivals re-cut the strips only while the
// search has barely begun; a gap in the fixes is not a walk; bad keys are named.
#include "sarloc/core/incident/search_plan.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::incident {
namespace {

// 150 m east-west, 200 m north-south; rescuers arrive at its north edge.
Deposit rectangle() { return Deposit({{0, 0}, {150, 0}, {150, 200}, {0, 200}}, "deposit"); }

// Every rescuer with a strip walks 1 m towards its next point; true while any walked.
bool step(SearchPlanner& planner, std::map<std::string, Vec2>& at) {
  bool walked = false;
  for (auto& [id, p] : at) {
    const auto target = planner.next_point(id);
    if (!target) continue;
    const Vec2 d = *target - p;
    p += d.norm() <= 1.0 ? d : d.normalized();
    planner.on_position(id, p);
    walked = true;
  }
  planner.update();
  return walked;
}

// Rescuers without a strip while a strip is open (not done, nobody's).
std::size_t idle_while_open(const SearchPlanner& planner, const std::map<std::string, Vec2>& at) {
  bool open = false;
  for (const auto& s : planner.plan().strips) open = open || (!s.done && s.rescuer_id.empty());
  if (!open) return 0;
  std::size_t n = 0;
  for (const auto& [id, p] : at) n += planner.strip_of(id) ? 0 : 1;
  return n;
}

// Seven rescuers together at the top of a 150 m wide deposit: seven strips of 21.4 m (not the
// fewest, four of 37.5 m, which would leave three waiting), one each; walking where the plan
// says searches all of it, and nobody is idle while a strip is open. (One whose strip is done
// first, at the bottom beside the others, helps nobody: the strips end together, and helping
// saves no time where the others have less left than the walk to their bottoms.)
TEST(SearchPlanner, SevenRescuersFromTheTopSearchTheWholeDepositWithNobodyIdle) {
  SearchPlanner planner(rectangle(), SearchPlanConfig{});
  std::map<std::string, Vec2> at;
  for (int k = 0; k < 7; ++k) {
    const std::string id = "r" + std::to_string(k + 1);
    at[id] = Vec2(66.0 + 2.0 * k, 205.0);
    planner.on_position(id, at[id]);
  }
  EXPECT_TRUE(planner.update());
  const SearchPlan& plan = planner.plan();
  ASSERT_EQ(plan.strips.size(), 7u);
  std::set<std::string> walkers;
  for (const auto& s : plan.strips) {
    EXPECT_NEAR(s.strip.width_m, 150.0 / 7.0, 1e-6);
    EXPECT_NEAR(s.strip.top.y(), 200.0, 1e-6) << "entered from the rescuers' end";
    walkers.insert(s.rescuer_id);
  }
  EXPECT_EQ(walkers.size(), 7u) << "each strip its own rescuer";
  // The leftmost rescuer (west) takes a western strip: no two cross each other's paths.
  for (int k = 0; k + 1 < 7; ++k) {
    const auto a = planner.strip_of("r" + std::to_string(k + 1)), b = planner.strip_of("r" + std::to_string(k + 2));
    ASSERT_TRUE(a && b);
    EXPECT_LT(plan.strips[*a].strip.top.x(), plan.strips[*b].strip.top.x());
  }
  int seconds = 0;
  std::size_t idle = 0;
  while (step(planner, at) && seconds < 2000) {
    ++seconds;
    idle += idle_while_open(planner, at);
  }
  EXPECT_GE(planner.plan().searched, 0.98);
  for (const auto& s : planner.plan().strips) EXPECT_TRUE(s.done) << s.strip.index << ": " << s.searched;
  EXPECT_EQ(idle, 0u) << "rescuer-seconds idle while a strip was open";
  // About the 200 m strip plus the walk to its top: every rescuer walked its strip once.
  EXPECT_LT(seconds, 260) << "walking 200 m strips side by side";
}

// Three rescuers, a deposit 200 m across (300 m long) at 40 m: five strips. A rescuer whose strip is done
// takes an open one; at the end all five are searched.
TEST(SearchPlanner, ARescuerWhoseStripIsDoneTakesAnOpenOne) {
  SearchPlanner planner(Deposit({{0, 0}, {200, 0}, {200, 300}, {0, 300}}, "deposit"), SearchPlanConfig{});
  std::map<std::string, Vec2> at{{"a", {20, 305}}, {"b", {100, 305}}, {"c", {180, 305}}};
  for (const auto& [id, p] : at) planner.on_position(id, p);
  ASSERT_TRUE(planner.update());
  ASSERT_EQ(planner.plan().strips.size(), 5u);
  std::size_t assigned = 0;
  for (const auto& s : planner.plan().strips) assigned += s.rescuer_id.empty() ? 0 : 1;
  EXPECT_EQ(assigned, 3u);
  std::set<std::size_t> walked_by_a;
  std::size_t idle = 0;
  for (int seconds = 0; seconds < 3000 && step(planner, at); ++seconds) {
    if (const auto s = planner.strip_of("a")) walked_by_a.insert(*s);
    idle += idle_while_open(planner, at);
  }
  EXPECT_EQ(idle, 0u) << "rescuer-seconds idle while a strip was open";
  for (const auto& s : planner.plan().strips) EXPECT_TRUE(s.done) << s.strip.index;
  EXPECT_GE(planner.plan().searched, 0.98);
  EXPECT_GE(walked_by_a.size(), 2u) << "a took another strip after its first";
}

// Three rescuers, three strips of 40 m down a 300 m deposit; c is away on a signal for the first
// 120 s, while a and b walk on beside its open strip, and then walks its strip. a and b end theirs at the bottom, next
// to the bottom of c's, with 160 m of it left: one of them helps from the bottom up, and the deposit is searched about
// 50 s before c alone would have searched its strip. The helper is freed when it is done.
TEST(SearchPlanner, WithNoStripOpenAFreeRescuerHelpsFromTheBottomOfTheStripWithTheMostLeft) {
  SearchPlanner planner(Deposit({{0, 0}, {120, 0}, {120, 300}, {0, 300}}, "deposit"), SearchPlanConfig{});
  std::map<std::string, Vec2> at{{"a", {20, 305}}, {"b", {60, 305}}, {"c", {100, 305}}};
  for (const auto& [id, p] : at) planner.on_position(id, p);
  ASSERT_TRUE(planner.update());
  ASSERT_EQ(planner.plan().strips.size(), 3u);
  const auto strip_c = planner.strip_of("c");
  ASSERT_TRUE(strip_c);
  planner.release("c");
  std::map<std::string, Vec2> walking{{"a", at["a"]}, {"b", at["b"]}};
  for (int seconds = 0; seconds < 120; ++seconds) step(planner, walking);
  // Beside the open strip, its neighbours walk on: a row of theirs does not wait for the open
  // strip's cells at their common edge (before 2026-12-04 both stopped within 11 m).
  EXPECT_LT(walking["a"].y(), 200.0);
  EXPECT_LT(walking["b"].y(), 200.0);
  planner.resume("c");
  planner.update();
  ASSERT_EQ(planner.strip_of("c"), strip_c) << "c takes its open strip back";
  at = walking;
  at["c"] = Vec2(100, 305);
  std::optional<std::string> helper;
  double helper_lowest_y = 1e9, helper_y = 0.0;
  bool helper_walked_up = false;
  int seconds = 0;
  for (; seconds < 1000 && step(planner, at); ++seconds) {
    if (!helper) {
      for (const char* id : {"a", "b"})
        if (planner.strip_helped_by(id)) helper = id;
      if (helper) {
        EXPECT_EQ(planner.strip_helped_by(*helper), strip_c) << "the strip with the most left";
      }
    }
    if (helper && planner.strip_helped_by(*helper)) {
      helper_lowest_y = std::min(helper_lowest_y, at[*helper].y());
      helper_walked_up = helper_walked_up || at[*helper].y() > helper_lowest_y + 10.0;
      helper_y = at[*helper].y();
    }
  }
  ASSERT_TRUE(helper) << "nobody helped on c's strip";
  EXPECT_TRUE(helper_walked_up) << "the helper walks up from the bottom; it reached " << helper_y;
  for (const auto& s : planner.plan().strips) {
    EXPECT_TRUE(s.done) << s.strip.index;
    EXPECT_TRUE(s.helper_id.empty()) << "freed when the strip is done";
  }
  EXPECT_GE(planner.plan().searched, 0.98);
  // Alone, c needs about 280 s for its strip after its 120 s away.
  // Alone, c needs about 285 s for its strip after its 120 s away (405 s in all); helped, the
  // deposit was searched by 359 s when this test was written.
  EXPECT_LT(120 + seconds, 385) << "the help saved nothing";
}

// A standby's planner takes the active one's helpers with its walkers.
TEST(SearchPlanner, AdoptingTheActivePlanTakesItsHelpersToo) {
  const Deposit deposit({{0, 0}, {80, 0}, {80, 300}, {0, 300}}, "deposit");
  SearchPlanner active(deposit, SearchPlanConfig{}), standby(deposit, SearchPlanConfig{});
  for (SearchPlanner* p : {&active, &standby}) {
    p->on_position("a", {20, 305});
    p->on_position("b", {60, 305});
    p->update();
  }
  SearchPlan plan = active.plan();
  plan.strips[0].helper_id = "c";
  ASSERT_TRUE(standby.adopt_assignments(plan));
  EXPECT_EQ(standby.strip_helped_by("c"), std::optional<std::size_t>(0));
  EXPECT_EQ(standby.plan().strips[0].rescuer_id, plan.strips[0].rescuer_id);
  standby.release("c");
  EXPECT_FALSE(standby.strip_helped_by("c")) << "a helper released is no helper";
}

// A strip whose bottom is farther from the free rescuer than the stretch it has left is not
// helped: the walk there would take longer than its rescuer needs. A latecomer at the top, with
// both strips 30 m under way (too late to re-cut): each bottom is ~300 m away, ~250 m are left.
TEST(SearchPlanner, NoHelpWhereTheWalkToTheBottomTakesLongerThanTheStripHasLeft) {
  SearchPlanner planner(Deposit({{0, 0}, {80, 0}, {80, 300}, {0, 300}}, "deposit"), SearchPlanConfig{});
  std::map<std::string, Vec2> at{{"a", {20, 305}}, {"b", {60, 305}}};
  for (const auto& [id, p] : at) planner.on_position(id, p);
  ASSERT_TRUE(planner.update());
  for (int seconds = 0; seconds < 30; ++seconds) step(planner, at);
  planner.on_position("c", {40, 305});
  planner.update();
  EXPECT_EQ(planner.plan().strips.size(), 2u) << "not re-cut";
  EXPECT_FALSE(planner.strip_of("c"));
  EXPECT_FALSE(planner.strip_helped_by("c"));
}

// A released rescuer (on a signal, link lost) gives its strip back; the next free rescuer takes
// it; resumed, it gets a strip again.
TEST(SearchPlanner, AReleasedRescuersStripOpensForTheNextFreeOne) {
  SearchPlanner planner(rectangle(), SearchPlanConfig{});
  planner.on_position("a", {40, 205});
  planner.on_position("b", {110, 205});
  ASSERT_TRUE(planner.update());
  // Two rescuers, four strips (37.5 m): two open.
  const auto strip_a = planner.strip_of("a");
  ASSERT_TRUE(strip_a);
  const std::uint32_t revision = planner.plan().revision;
  planner.release("a");
  EXPECT_GT(planner.plan().revision, revision);
  EXPECT_FALSE(planner.strip_of("a"));
  EXPECT_TRUE(planner.plan().strips[*strip_a].rescuer_id.empty());
  planner.update();
  EXPECT_FALSE(planner.strip_of("a")) << "not searching: no strip";
  planner.resume("a");
  EXPECT_TRUE(planner.update());
  EXPECT_TRUE(planner.strip_of("a"));
}

// A lone first rescuer gets the fewest strips; five more arriving before anything is searched
// re-cut them into six; after the search has begun, a late one only waits for a free strip.
TEST(SearchPlanner, LateArrivalsRecutTheStripsOnlyWhileTheSearchHasBarelyBegun) {
  SearchPlanner planner(Deposit({{0, 0}, {200, 0}, {200, 300}, {0, 300}}, "deposit"), SearchPlanConfig{});
  planner.on_position("r1", {100, 305});
  ASSERT_TRUE(planner.update());
  EXPECT_EQ(planner.plan().strips.size(), 5u);
  for (int k = 2; k <= 6; ++k) planner.on_position("r" + std::to_string(k), {90.0 + 4.0 * k, 305.0});
  ASSERT_TRUE(planner.update());
  EXPECT_EQ(planner.plan().strips.size(), 6u);
  for (const auto& s : planner.plan().strips) EXPECT_FALSE(s.rescuer_id.empty());
  // r1 walks 120 m down its strip: 120 x 40 m of 60 000 m^2 is beyond 5 %.
  const Vec2 start = *planner.next_point("r1");
  for (int k = 0; k <= 120; ++k) planner.on_position("r1", start + Vec2(0, -k));
  planner.update();
  EXPECT_GT(planner.plan().searched, 0.05);
  planner.on_position("r7", {150, 305});
  planner.update();
  EXPECT_EQ(planner.plan().strips.size(), 6u) << "not re-cut once the search is under way";
  EXPECT_FALSE(planner.strip_of("r7")) << "every strip taken: r7 waits for one";
}

// Twenty rescuers on a 150 m deposit: fifteen strips of 10 m (none narrower), cut once; the
// plan does not change from one update to the next while nobody moves.
TEST(SearchPlanner, MoreRescuersThanStripsCanHoldCutOnceAndShare) {
  SearchPlanner planner(rectangle(), SearchPlanConfig{});
  for (int k = 0; k < 20; ++k) planner.on_position("r" + std::to_string(k), {40.0 + 3.0 * k, 205.0});
  ASSERT_TRUE(planner.update());
  EXPECT_EQ(planner.plan().strips.size(), 15u);
  const std::uint32_t revision = planner.plan().revision;
  EXPECT_FALSE(planner.update());
  EXPECT_EQ(planner.plan().revision, revision) << "no re-cut, no re-assignment";
}

// A jump between fixes longer than max_walk_step_m is a gap (a fade), not a walk across the
// deposit; what a rescuer walked before the strips were cut still counts after.
TEST(SearchPlanner, AGapInTheFixesIsNotAWalk) {
  SearchPlanner planner(rectangle(), SearchPlanConfig{});
  planner.on_position("a", {75, 200});
  planner.on_position("a", {75, 100});  // 100 m in one step
  planner.update();
  EXPECT_EQ(planner.plan().searched, 0.0);
  SearchPlanner walked(rectangle(), SearchPlanConfig{});
  for (int y = 200; y >= 180; --y) walked.on_position("a", {75.0, static_cast<double>(y)});
  walked.update();
  EXPECT_GT(walked.plan().searched, 0.02) << "20 m walked before the first update counts";
  EXPECT_THROW(walked.on_position("a", {NAN, 0.0}), InputError);
}

// Four rescuers 60 s into their strips when the operator pulls a corner of the outline out:
// the plan over the new outline keeps what they searched, so they finish with less walking than
// over the same outline planned afresh, and they still search all of it.
TEST(SearchPlanner, AnOutlineRedrawnMidSearchKeepsWhatWasSearched) {
  SearchPlanner first(rectangle(), SearchPlanConfig{});
  std::map<std::string, Vec2> at;
  for (int k = 0; k < 4; ++k) {
    const std::string id = "r" + std::to_string(k + 1);
    at[id] = Vec2(60.0 + 10.0 * k, 205.0);
    first.on_position(id, at[id]);
  }
  first.update();
  for (int t = 0; t < 60; ++t) step(first, at);
  const double searched_before_m2 = first.plan().searched * 150.0 * 200.0;
  ASSERT_GT(first.plan().searched, 0.15);

  const Deposit redrawn({{0, 0}, {180, -30}, {150, 200}, {0, 200}}, "deposit_drawing.outline");
  auto finish = [&](SearchPlanner planner, std::map<std::string, Vec2> from, int& seconds) {
    for (const auto& [id, p] : from) planner.on_position(id, p);
    planner.update();
    const double start = planner.plan().searched;
    seconds = 0;
    while (step(planner, from) && seconds < 4000) ++seconds;
    for (const auto& strip : planner.plan().strips) EXPECT_TRUE(strip.done) << strip.strip.index;
    EXPECT_GE(planner.plan().searched, 0.95) << "the slanted edge leaves slivers off the strips' bands";
    return start;
  };
  int kept_s = 0, afresh_s = 0;
  const double kept = finish(SearchPlanner(redrawn, SearchPlanConfig{}, first), at, kept_s);
  const double afresh = finish(SearchPlanner(redrawn, SearchPlanConfig{}), at, afresh_s);
  EXPECT_NEAR(kept * redrawn.area_m2(), searched_before_m2, 0.03 * searched_before_m2)
      << "everything searched lay inside the new outline";
  EXPECT_LT(afresh, 0.01);
  EXPECT_LT(kept_s, afresh_s - 30) << "kept " << kept_s << " s, afresh " << afresh_s << " s";
  RecordProperty("kept_s", kept_s);
  RecordProperty("afresh_s", afresh_s);
  RecordProperty("kept_searched_percent", static_cast<int>(std::lround(100.0 * kept)));
}

TEST(SearchPlanner, BadConfigurationNamesTheKey) {
  const auto message = [](SearchPlanConfig c) {
    try {
      SearchPlanner(rectangle(), c);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  SearchPlanConfig c;
  c.coverage_cell_m = 0.1;
  EXPECT_NE(message(c).find("search.coverage_cell_m"), std::string::npos) << message(c);
  c = {};
  c.strip_done_fraction = 1.5;
  EXPECT_NE(message(c).find("search.strip_done_fraction"), std::string::npos) << message(c);
  c = {};
  c.max_walk_step_m = NAN;
  EXPECT_NE(message(c).find("search.max_walk_step_m"), std::string::npos) << message(c);
  c = {};
  c.recut_below_searched = -1;
  EXPECT_NE(message(c).find("search.recut_below_searched"), std::string::npos) << message(c);
  c = {};
  c.strips.strip_width_m = 200;
  EXPECT_NE(message(c).find("search.strip_width_m"), std::string::npos) << message(c);
}

}  // namespace
}  // namespace sarloc::incident
