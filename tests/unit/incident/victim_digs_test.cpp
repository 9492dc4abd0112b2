// Incident command's dig order: only FOUND victims, each at its estimate's depth, the free
// rescuers as diggers (the nearest to each team's first dig), and in the plan every cycle with
// the minutes buried counted from the first cycle.
#include "sarloc/core/incident/victim_digs.hpp"

#include <gtest/gtest.h>

#include "incident_commands.hpp"

namespace sarloc::incident {
namespace {

using test::at;

FusedVictim victim(std::uint32_t id, const Vec3& p, VictimState state) {
  FusedVictim v;
  v.victim_id = id;
  v.position.position = p;
  v.state = state;
  return v;
}

// Buried 10 min: 0.5 m (7.5 min to dig) and 2 m (30 min). One team: the shallow one first
// keeps 1.215 alive (dig_order_test counts it by hand), the deep one first 0.59.
const std::vector<FusedVictim> kVictims = {
    victim(4, Vec3(0, 0, -2.0), VictimState::kFound), victim(5, Vec3(30, 0, -0.5), VictimState::kFound),
    victim(6, Vec3(60, 0, -1.0), VictimState::kLocated), victim(7, Vec3(90, 0, -1.0), VictimState::kRecovered)};

TEST(VictimDigs, OnlyFoundVictimsShallowFirstWithTheNearestFreeRescuer) {
  const auto digs = plan_victim_digs(kVictims, {{"r1", Vec2(0, 5)}}, 10.0, TriageConfig{});
  ASSERT_EQ(digs.digs.size(), 2u) << "a LOCATED victim is not dug yet, a recovered one is out";
  EXPECT_EQ(digs.digs[0].victim_id, 5u);
  EXPECT_DOUBLE_EQ(digs.digs[0].depth_m, 0.5);
  EXPECT_DOUBLE_EQ(digs.digs[0].done_min, 3.75);
  EXPECT_EQ(digs.digs[1].victim_id, 4u);
  EXPECT_DOUBLE_EQ(digs.digs[1].start_min, 3.75);
  EXPECT_EQ(digs.digs[0].digger_id, "r1");
  EXPECT_EQ(digs.digs[1].digger_id, "r1") << "one team digs both";
  EXPECT_DOUBLE_EQ(digs.digs[0].buried_min, 10.0);
  EXPECT_NEAR(digs.expected_survivors, digs.digs[0].survival + digs.digs[1].survival, 1e-12);
}

TEST(VictimDigs, TwoFreeRescuersDigBothAtOnceEachTheNearest) {
  const auto digs = plan_victim_digs(kVictims, {{"far", Vec2(200, 0)}, {"near4", Vec2(1, 0)}, {"near5", Vec2(29, 0)}},
                                     10.0, TriageConfig{});
  ASSERT_EQ(digs.digs.size(), 2u);
  for (const auto& d : digs.digs) {
    EXPECT_DOUBLE_EQ(d.start_min, 0.0) << "two teams for two victims";
    EXPECT_EQ(d.digger_id, d.victim_id == 4u ? "near4" : "near5");
  }
}

TEST(VictimDigs, WithNobodyFreeTheOrderStandsAndWaitsForADigger) {
  const auto digs = plan_victim_digs(kVictims, {}, 10.0, TriageConfig{});
  ASSERT_EQ(digs.digs.size(), 2u);
  EXPECT_EQ(digs.digs[0].victim_id, 5u);
  EXPECT_TRUE(digs.digs[0].digger_id.empty());
  EXPECT_TRUE(plan_victim_digs({kVictims[2]}, {}, 10.0, TriageConfig{}).digs.empty());
}

// In the plan: a FOUND victim's dig, buried the configured minutes plus the time since
// incident command's first cycle; its finder walks a strip, so nobody is free to dig.
TEST(VictimDigs, IncidentCommandPublishesTheDigOrderInItsPlan) {
  auto config = test::command_config();
  config.deposit.emplace(std::vector<Vec2>{{0, 0}, {150, 0}, {150, 200}, {0, 200}}, "incident.deposit");
  config.triage.buried_before_start_min = 5.0;
  IncidentCommand command(config, at(0));
  command.on_position(test::gnss_fix("r1", at(1), Vec3(40, 205, 0)), "w-r1", at(1));
  auto out = command.cycle(at(1.5), at(1.5));
  ASSERT_TRUE(out.search_plan);
  EXPECT_TRUE(out.search_plan->digs.digs.empty());
  command.on_position(test::gnss_fix("r1", at(61), Vec3(40, 190, 0)), "w-r1", at(61));
  command.on_estimate(test::estimate_of("r1", 1, at(61), responder::EstimatorStatus::kFound), "w-r1", true, at(61));
  out = command.cycle(at(61.5), at(61.5));
  ASSERT_EQ(out.victims.size(), 1u);
  ASSERT_EQ(out.victims[0].state, VictimState::kFound);
  ASSERT_TRUE(out.search_plan);
  const auto& digs = out.search_plan->digs.digs;
  ASSERT_EQ(digs.size(), 1u);
  EXPECT_EQ(digs[0].victim_id, out.victims[0].victim_id);
  EXPECT_NEAR(digs[0].depth_m, 1.0, 1e-9) << "antenna 1 m above the snow, the victim 2 m below it";
  EXPECT_NEAR(digs[0].buried_min, 6.0, 1e-9);
  EXPECT_NEAR(digs[0].survival, TriageConfig{}.survival(16.0), 1e-9);
  EXPECT_TRUE(digs[0].digger_id.empty()) << "r1 walks its strip";
  EXPECT_EQ(out.search_plan->incident_start, at(1.5));
  EXPECT_TRUE(test::has_event(out, IncidentEvent::Kind::kInfo, "dig order: victims"));
}

// The operator's order holds while the FOUND victims are those it was given for; a new FOUND
// makes incident command re-plan, and its order is the last writer. Both are events.
TEST(VictimDigs, AnOperatorsOrderHoldsUntilTheFoundVictimsChange) {
  auto config = test::command_config();
  config.deposit.emplace(std::vector<Vec2>{{0, 0}, {150, 0}, {150, 200}, {0, 200}}, "incident.deposit");
  IncidentCommand command(config, at(0));
  // Victims 2 m and 4 m below the antennas, which are 1 m above the snow: 1 m and 3 m deep.
  auto found = [&](const std::string& rescuer, double t, const Vec3& fix, double depth_below_antenna) {
    command.on_position(test::gnss_fix(rescuer, at(t), fix), "w-" + rescuer, at(t));
    auto e = test::estimate_of(rescuer, 1, at(t), responder::EstimatorStatus::kFound);
    e.relative.position.z() = -depth_below_antenna;
    command.on_estimate(e, "w-" + rescuer, true, at(t));
  };
  found("r1", 1, Vec3(40, 190, 0), 2.0);
  found("r2", 1, Vec3(100, 190, 0), 4.0);
  auto out = command.cycle(at(1.5), at(1.5));
  ASSERT_EQ(out.victims.size(), 2u);
  ASSERT_EQ(out.search_plan->digs.digs.size(), 2u);
  const std::uint32_t shallow = out.search_plan->digs.digs[0].victim_id, deep = out.search_plan->digs.digs[1].victim_id;
  ASSERT_LT(out.search_plan->digs.digs[0].depth_m, out.search_plan->digs.digs[1].depth_m)
      << "the plan's own: shallow first";

  command.on_dig_order("another-incident", {deep}, "ic-chief");
  command.on_dig_order(config.incident_id, {deep, deep}, "ic-chief");
  command.on_dig_order(config.incident_id, {deep, 99}, "ic-chief");
  out = command.cycle(at(2), at(2));
  EXPECT_TRUE(test::has_event(out, IncidentEvent::Kind::kRejected, "is listed twice"));
  EXPECT_TRUE(test::has_event(out, IncidentEvent::Kind::kRejected, "victim 99: no such victim"));
  EXPECT_EQ(out.search_plan->digs.digs[0].victim_id, shallow) << "refused orders change nothing";

  command.on_dig_order(config.incident_id, {deep}, "ic-chief");
  out = command.cycle(at(3), at(3));
  EXPECT_TRUE(test::has_event(out, IncidentEvent::Kind::kInfo,
                              "dig order from 'ic-chief': victims " + std::to_string(deep) + " first"));
  ASSERT_EQ(out.search_plan->digs.digs.size(), 2u);
  EXPECT_EQ(out.search_plan->digs.digs[0].victim_id, deep) << "the operator's order";
  out = command.cycle(at(4), at(4));
  EXPECT_EQ(out.search_plan->digs.digs[0].victim_id, deep) << "it holds over cycles";

  found("r3", 5, Vec3(130, 190, 0), 1.5);  // a third victim FOUND: incident command re-plans
  out = command.cycle(at(5.5), at(5.5));
  ASSERT_EQ(out.search_plan->digs.digs.size(), 3u);
  EXPECT_TRUE(test::has_event(out, IncidentEvent::Kind::kInfo, "the order from 'ic-chief' no longer holds"));
  EXPECT_NE(out.search_plan->digs.digs[0].victim_id, deep) << "the plan's own again: the deep one is not first";
}

}  // namespace
}  // namespace sarloc::incident
