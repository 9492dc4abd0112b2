// IncidentCommand under hot standby: a standby adopts the active instance's picture, fuses on
// top of it without publishing, takes over with the same ids, and disposes retired ids again.
// The two instances here talk through deliver_picture (what their DDS readers would receive).
#include <gtest/gtest.h>

#include <algorithm>

#include "incident_commands.hpp"

namespace sarloc::incident {
namespace {

using test::at;
using test::command_config;
using test::deliver_picture;
using test::estimate_of;
using test::gnss_fix;
using test::has_event;
using Kind = IncidentEvent::Kind;

std::vector<std::uint32_t> ids_of(const std::vector<FusedVictim>& victims) {
  std::vector<std::uint32_t> ids;
  for (const auto& v : victims) ids.push_back(v.victim_id);
  return ids;
}

bool contains(const std::vector<std::uint32_t>& ids, std::uint32_t id) {
  return std::find(ids.begin(), ids.end(), id) != ids.end();
}

// Both instances read the same inputs.
void position_both(IncidentCommand& a, IncidentCommand& b, const std::string& r, double t, const Vec3& p) {
  a.on_position(gnss_fix(r, at(t), p), "w-" + r, at(t));
  b.on_position(gnss_fix(r, at(t), p), "w-" + r, at(t));
}
void estimate_both(IncidentCommand& a, IncidentCommand& b, const std::string& r, std::uint32_t signal, double t) {
  a.on_estimate(estimate_of(r, signal, at(t)), "w-" + r, true, at(t));
  b.on_estimate(estimate_of(r, signal, at(t)), "w-" + r, true, at(t));
}

// Instance 1 claims after claim_wait_s (4 s); instance 2 would claim a second later, but hears
// instance 1's summary first.
TEST(IncidentCommandStandby, TheStandbyAdoptsThePictureAndPublishesNothing) {
  IncidentCommand one(command_config(1, 2), at(0));
  IncidentCommand two(command_config(2, 2), at(0));
  position_both(one, two, "r1", 1, Vec3(10, 20, 0));
  estimate_both(one, two, "r1", 1, 1);
  EXPECT_FALSE(one.cycle(at(1), at(1)).active);
  EXPECT_FALSE(two.cycle(at(1), at(1)).active);
  const auto first = one.cycle(at(4), at(4));
  ASSERT_TRUE(first.active);
  ASSERT_EQ(first.victims.size(), 1U);
  deliver_picture(first, two, "summary-1", at(4));
  const auto second = two.cycle(at(5), at(5));
  EXPECT_FALSE(second.active);
  EXPECT_FALSE(second.role_change) << "it heard the active one: it stays standby";
  EXPECT_EQ(ids_of(second.victims), ids_of(first.victims)) << "same ids as the active one";
  EXPECT_EQ(two.role(), CommandRole::kStandby);
}

// The active one dies: its summary writer's liveliness is lost. The standby takes over at once,
// with the ids, the frame and the alarms of the last picture, plus what it heard since.
TEST(IncidentCommandStandby, TheStandbyTakesOverWithTheSameIdsFrameAndAlarms) {
  IncidentCommand one(command_config(1, 2), at(0));
  IncidentCommand two(command_config(2, 2), at(0));
  position_both(one, two, "r1", 3, Vec3(10, 20, 0));
  estimate_both(one, two, "r1", 1, 3);
  position_both(one, two, "r2", 3, Vec3(60, 0, 0));
  estimate_both(one, two, "r2", 1, 3);
  const auto mayday = test::mayday_of("r2", at(3));
  one.on_device_alarm(mayday, at(3));
  two.on_device_alarm(mayday, at(3));
  const auto last = one.cycle(at(4), at(4));
  ASSERT_TRUE(last.active);
  ASSERT_EQ(last.victims.size(), 2U);
  ASSERT_EQ(last.alarms.size(), 1U);
  deliver_picture(last, two, "summary-1", at(4));
  two.cycle(at(4.5), at(4.5));

  // Heard only by the standby, after the active one's last picture.
  two.on_position(gnss_fix("r3", at(5), Vec3(-40, 0, 0)), "w-r3", at(5));
  two.on_estimate(estimate_of("r3", 1, at(5)), "w-r3", true, at(5));
  two.on_peer_lost("summary-1", at(5.2));
  const auto taken = two.cycle(at(5.3), at(5.3));
  ASSERT_TRUE(taken.role_change);
  EXPECT_EQ(taken.role_change->role, CommandRole::kActive);
  EXPECT_TRUE(taken.active);
  EXPECT_TRUE(has_event(taken, Kind::kWarning, "taking over as the active incident command"));
  EXPECT_TRUE(has_event(taken, Kind::kWarning, "2 victim(s) adopted"));
  ASSERT_EQ(taken.victims.size(), 3U);
  for (const auto& v : last.victims) {
    const auto it = std::find_if(taken.victims.begin(), taken.victims.end(),
                                 [&](const FusedVictim& t) { return t.victim_id == v.victim_id; });
    ASSERT_NE(it, taken.victims.end()) << "victim " << v.victim_id << " kept its id";
    EXPECT_LT((it->position.position - v.position.position).norm(), 1e-6);
  }
  EXPECT_EQ(taken.victims.back().victim_id, 3U) << "the new one after the adopted ids";
  EXPECT_EQ(taken.frame.established, last.frame.established) << "one incident, one start";
  ASSERT_EQ(taken.alarms.size(), 1U);
  EXPECT_EQ(taken.alarms[0].alarm_id, last.alarms[0].alarm_id);
  // Acknowledgements go to the active instance only: now this one.
  two.on_acknowledgement(taken.alarms[0].alarm_id, "ic-1", at(6), at(6));
  const auto acked = two.cycle(at(6.5), at(6.5));
  ASSERT_EQ(acked.alarms.size(), 1U);
  EXPECT_TRUE(acked.alarms[0].acknowledged);
}

// The standby takes the active one's strip assignments (here swapped by hand: two instances can
// tie-break rescuers 2 m apart differently), so taking over sends no rescuer elsewhere; a plan of
// strips cut differently is not adopted, with one warning; one started late takes the active
// one's incident start (the dig order's minutes buried).
TEST(IncidentCommandStandby, TheStandbyTakesTheActiveOnesStripAssignments) {
  auto config_of = [](int instance) {
    auto c = command_config(instance, 2);
    c.deposit.emplace(std::vector<Vec2>{{0, 0}, {150, 0}, {150, 200}, {0, 200}}, "incident.deposit");
    return c;
  };
  IncidentCommand one(config_of(1), at(0));
  IncidentCommand two(config_of(2), at(0));
  position_both(one, two, "r1", 1, Vec3(40, 205, 0));
  position_both(one, two, "r2", 1, Vec3(110, 205, 0));
  one.cycle(at(1), at(1));
  two.cycle(at(1), at(1));
  auto last = one.cycle(at(4), at(4));
  ASSERT_TRUE(last.active);
  ASSERT_TRUE(last.search_plan);
  auto& strips = last.search_plan->plan.strips;
  const auto r1 = one.search_planner()->strip_of("r1"), r2 = one.search_planner()->strip_of("r2");
  ASSERT_TRUE(r1 && r2);
  std::swap(strips[*r1].rescuer_id, strips[*r2].rescuer_id);
  deliver_picture(last, two, "summary-1", at(4));
  two.cycle(at(4.5), at(4.5));
  EXPECT_EQ(two.search_planner()->strip_of("r1"), r2) << "the active one's assignment";
  EXPECT_EQ(two.search_planner()->strip_of("r2"), r1);
  two.on_peer_lost("summary-1", at(5));
  const auto taken = two.cycle(at(5.5), at(5.5));
  ASSERT_TRUE(taken.active);
  ASSERT_TRUE(taken.search_plan);
  EXPECT_EQ(taken.search_plan->plan.strips[*r2].rescuer_id, "r1") << "kept after taking over";

  IncidentCommand three(config_of(2), at(6));  // started late: it has not claimed yet
  position_both(one, three, "r1", 6, Vec3(40, 205, 0));
  three.on_position(gnss_fix("r2", at(6), Vec3(110, 205, 0)), "w-r2", at(6));
  three.cycle(at(6), at(6));
  auto cut_otherwise = one.cycle(at(6.5), at(6.5));
  ASSERT_TRUE(cut_otherwise.search_plan);
  cut_otherwise.search_plan->plan.strips.pop_back();
  deliver_picture(cut_otherwise, three, "summary-1", at(6.5));
  const auto refused = three.cycle(at(7), at(7));
  EXPECT_TRUE(has_event(refused, Kind::kWarning, "strips are cut differently"));
  // Started late, it counts the victims as buried from the active one's first cycle, not its own.
  ASSERT_TRUE(refused.search_plan);
  EXPECT_EQ(refused.search_plan->incident_start, at(1));
  deliver_picture(cut_otherwise, three, "summary-1", at(7.5));
  EXPECT_FALSE(has_event(three.cycle(at(8), at(8)), Kind::kWarning, "strips are cut differently")) << "said once";
}

TEST(IncidentCommandStandby, AStandbyIgnoresAcknowledgementsItsPictureWillCarry) {
  IncidentCommand one(command_config(1, 2), at(0));
  IncidentCommand two(command_config(2, 2), at(0));
  const auto mayday = test::mayday_of("r2", at(1));
  one.on_device_alarm(mayday, at(1));
  two.on_device_alarm(mayday, at(1));
  const auto out = one.cycle(at(4), at(4));
  deliver_picture(out, two, "summary-1", at(4));
  two.cycle(at(4.5), at(4.5));
  two.on_acknowledgement(out.alarms.at(0).alarm_id, "ic-1", at(5), at(5));
  two.on_acknowledgement(999, "ic-1", at(5), at(5));  // not even refused: not its business
  const auto standby = two.cycle(at(5.5), at(5.5));
  EXPECT_TRUE(standby.events.empty());
  EXPECT_FALSE(two.alarms().at(0).acknowledged);
}

// A reader may have missed the predecessor's disposal of a merged-away victim during a fade:
// the new active instance disposes every retired id again for kRedisposeWindowNs, then stops.
TEST(IncidentCommandStandby, RetiredIdsAreDisposedAgainForAWindowAfterTakingOver) {
  IncidentCommand two(command_config(2, 2), at(0));
  // The active one's picture: victims 1 and 3 (built by an active instance); 2 was merged away.
  IncidentCommand one(command_config(), at(0));
  for (const auto& [r, x] : {std::pair<std::string, double>{"r1", 0.0}, {"r2", 50.0}, {"r3", 100.0}}) {
    one.on_position(gnss_fix(r, at(1), Vec3(x, 0, 0)), "w-" + r, at(1));
    one.on_estimate(estimate_of(r, 1, at(1)), "w-" + r, true, at(1));
  }
  auto picture = one.cycle(at(1), at(1));
  ASSERT_EQ(ids_of(picture.victims), (std::vector<std::uint32_t>{1, 2, 3}));
  picture.victims.erase(picture.victims.begin() + 1);
  picture.disposed_victims = {2};
  deliver_picture(picture, two, "summary-1", at(1));
  EXPECT_FALSE(two.cycle(at(1.5), at(1.5)).active);

  two.on_peer_lost("summary-1", at(2));
  const auto taken = two.cycle(at(2), at(2));
  ASSERT_TRUE(taken.active);
  EXPECT_EQ(ids_of(taken.victims), (std::vector<std::uint32_t>{1, 3}));
  EXPECT_EQ(taken.disposed_victims, std::vector<std::uint32_t>{2});
  EXPECT_TRUE(has_event(taken, Kind::kInfo, "disposing again, for 10 s, the victim id(s) 2"));
  const double window_s = static_cast<double>(IncidentCommand::kRedisposeWindowNs) / 1e9;
  const auto during = two.cycle(at(2 + window_s - 0.5), at(2 + window_s - 0.5));
  EXPECT_EQ(during.disposed_victims, std::vector<std::uint32_t>{2});
  EXPECT_FALSE(has_event(during, Kind::kInfo, "disposing again")) << "said once";
  const auto after = two.cycle(at(2 + window_s + 0.5), at(2 + window_s + 0.5));
  EXPECT_TRUE(after.disposed_victims.empty());
  // A new victim takes the next id after every one seen, never a retired one.
  two.on_position(gnss_fix("r9", at(20), Vec3(-80, 0, 0)), "w-r9", at(20));
  two.on_estimate(estimate_of("r9", 1, at(20)), "w-r9", true, at(20));
  const auto next = two.cycle(at(20.5), at(20.5));
  EXPECT_TRUE(contains(ids_of(next.victims), 4U));
}

TEST(IncidentCommandStandby, AnotherIncidentsFrameIsNotAdopted) {
  IncidentCommand two(command_config(2, 2), at(0));
  IncidentFrame other;
  other.incident_id = "another-incident";
  other.established = at(0.5);
  two.on_peer_frame(other);
  two.on_peer_summary("summary-1", at(1));
  two.cycle(at(1), at(1));
  two.on_peer_lost("summary-1", at(2));
  const auto taken = two.cycle(at(2), at(2));
  ASSERT_TRUE(taken.active);
  EXPECT_EQ(taken.frame.incident_id, "unit-incident");
  EXPECT_EQ(taken.frame.established, at(2)) << "it establishes its own";
}

}  // namespace
}  // namespace sarloc::incident
