// Triage: the survival curve as published, the dig time growing with depth, and the order that
// keeps most alive, counted by hand on two victims.
#include "sarloc/core/incident/dig_order.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::incident {
namespace {

TEST(TriageConfig, ReadsTheSurvivalCurveBetweenItsPointsAndRefusesOneThatRises) {
  const TriageConfig c;
  EXPECT_DOUBLE_EQ(c.survival(10.0), 0.92);
  EXPECT_NEAR(c.survival(25.0), 0.61, 1e-12) << "halfway from 92 % at 15 min to 30 % at 35";
  EXPECT_DOUBLE_EQ(c.survival(300.0), 0.07) << "the last value beyond the last point";
  EXPECT_DOUBLE_EQ(c.dig_minutes(2.0), 30.0);
  TriageConfig rising;
  rising.survival_curve = {{0.0, 0.5}, {10.0, 0.6}};
  EXPECT_THROW(rising.validate(), ConfigError);
  TriageConfig late;
  late.survival_curve = {{5.0, 0.9}, {10.0, 0.5}};
  EXPECT_THROW(late.validate(), ConfigError);
  TriageConfig one;
  one.survival_curve = {{0.0, 0.9}};
  EXPECT_THROW(one.validate(), ConfigError);
  TriageConfig negative;
  negative.dig_min_per_m = -1.0;
  EXPECT_THROW(negative.validate(), ConfigError);
}

// Buried 10 min: the 0.5 m victim takes 3.75 min, the 2 m one 30 min. Shallow first: 0.92 and
// the curve at 43.75 min (0.2952); deep first: 0.2973 and 0.2952. One team digs the shallow one
// first; two teams dig both at once.
TEST(DigOrder, DigsTheShallowVictimFirstWhenThatSavesMore) {
  const std::vector<DigCandidate> victims{{"deep", 2.0, 10.0}, {"shallow", 0.5, 10.0}};
  const DigPlan one = plan_digs(victims, 1, TriageConfig{});
  ASSERT_EQ(one.digs.size(), 2u);
  EXPECT_EQ(one.digs[0].victim_id, "shallow");
  EXPECT_DOUBLE_EQ(one.digs[0].done_min, 3.75);
  EXPECT_DOUBLE_EQ(one.digs[1].start_min, 3.75);
  const double plateau = 0.30 - 0.03 * (43.75 - 35.0) / 55.0;
  EXPECT_NEAR(one.expected_survivors, 0.92 + plateau, 1e-12);
  const DigPlan two = plan_digs(victims, 2, TriageConfig{});
  for (const Dig& d : two.digs) EXPECT_EQ(d.start_min, 0.0) << d.victim_id;
  EXPECT_NE(two.digs[0].team, two.digs[1].team);
  EXPECT_GT(two.expected_survivors, one.expected_survivors);
}

// An operator's victims go first, in the operator's order; the rest is still the best order of
// what is left (after the deep one, 40 min buried: shallow then mid keeps 0.2952 + 0.2898, mid
// then shallow 0.2918 + 0.2898).
TEST(DigOrder, AnOperatorsVictimsGoFirstAndTheRestIsPlanned) {
  const std::vector<DigCandidate> victims{{"deep", 2.0, 10.0}, {"shallow", 0.5, 10.0}, {"mid", 1.0, 10.0}};
  const DigPlan own = plan_digs(victims, 1, TriageConfig{});
  ASSERT_EQ(own.digs[0].victim_id, "shallow");
  const DigPlan given = plan_digs(victims, 1, TriageConfig{}, {"deep", "nobody"});
  ASSERT_EQ(given.digs.size(), 3u);
  EXPECT_EQ(given.digs[0].victim_id, "deep") << "an id that is not a candidate is skipped";
  EXPECT_DOUBLE_EQ(given.digs[0].done_min, 30.0);
  EXPECT_EQ(given.digs[1].victim_id, "shallow") << "the rest as planned: shortest first here";
  EXPECT_DOUBLE_EQ(given.digs[1].start_min, 30.0);
  EXPECT_LT(given.expected_survivors, own.expected_survivors) << "the operator's call costs what it costs";
  const DigPlan both = plan_digs(victims, 1, TriageConfig{}, {"mid", "deep"});
  EXPECT_EQ(both.digs[0].victim_id, "mid");
  EXPECT_EQ(both.digs[1].victim_id, "deep");
  EXPECT_EQ(both.digs[2].victim_id, "shallow");
}

// Beyond seven victims the order is shortest dig first; below, no order the search skips keeps
// more alive than the one it returns.
TEST(DigOrder, NoOtherOrderKeepsMoreAlive) {
  const std::vector<DigCandidate> victims{{"a", 1.6, 6.0}, {"b", 0.3, 6.0}, {"c", 1.0, 6.0}, {"d", 2.4, 6.0}};
  const TriageConfig config;
  const DigPlan best = plan_digs(victims, 1, config);
  std::vector<std::size_t> order{0, 1, 2, 3};
  do {
    double t = 0.0, survivors = 0.0;
    for (std::size_t i : order) {
      t += config.dig_minutes(victims[i].depth_m);
      survivors += config.survival(victims[i].buried_min + t);
    }
    EXPECT_LE(survivors, best.expected_survivors + 1e-12);
  } while (std::next_permutation(order.begin(), order.end()));
  std::vector<DigCandidate> many;
  for (int k = 0; k < 9; ++k) many.push_back({"v" + std::to_string(k), 0.2 * (9 - k), 0.0});
  const DigPlan spt = plan_digs(many, 2, config);
  EXPECT_EQ(spt.digs.front().victim_id, "v8") << "the shallowest first";
}

TEST(DigOrder, RefusesNoTeamAndImpossibleVictims) {
  EXPECT_THROW(plan_digs({{"a", 1.0, 0.0}}, 0, TriageConfig{}), InputError);
  EXPECT_THROW(plan_digs({{"a", -1.0, 0.0}}, 1, TriageConfig{}), InputError);
  EXPECT_THROW(plan_digs({{"a", 1.0, std::nan("")}}, 1, TriageConfig{}), InputError);
  EXPECT_THROW(plan_digs({{"a", 1.0, 0.0}, {"a", 2.0, 0.0}}, 1, TriageConfig{}), InputError);
  EXPECT_TRUE(plan_digs({}, 1, TriageConfig{}).digs.empty());
}

}  // namespace
}  // namespace sarloc::incident
