// The dashboard's picture: what changed since a version, events on transitions, removals,
// PAR timers and the no-data banner, on fake clocks.
#include <gtest/gtest.h>

#include "picture_state.hpp"
#include "support/sample_messages.hpp"
#include "support/config_messages.hpp"

namespace sarloc::dashboard {
namespace {

struct Clocks {
  TimestampNs mission = 1'000'000'000'000LL;
  double wall = 1000.0;
};

PictureState make(Clocks& c, PictureStateConfig config = {}) {
  return PictureState(config, [&c] { return c.mission; }, 0, [&c] { return c.wall; });
}

bool has_event(const nlohmann::json& message, const std::string& text) {
  for (const auto& e : message["events"]) {
    if (e["text"].get<std::string>().find(text) != std::string::npos) return true;
  }
  return false;
}

// With the incident's WGS-84 origin, every victim carries its latitude and longitude (without
// one, none: the page shows ENU only); a mission's deposit is in every snapshot.
TEST(PictureState, VictimsCarryTheirLatitudeAndLongitudeAndTheDepositIsDrawnOnceKnown) {
  Clocks c;
  auto state = make(c);
  auto v = test::sample_fused_victim();
  v.victim_id = 4;
  v.position.position = Vec3(100.0, -50.0, -1.5);
  state.on_victim(v);
  EXPECT_FALSE(state.snapshot()["victims"][0].contains("wgs84"));
  const GeodeticOrigin origin{46.5567, 7.9262, 2100.0};
  state.set_geodetic_origin(origin);
  const std::string expected = incident::format_wgs84(incident::GeodeticFrame(origin).to_wgs84(v.position.position));
  EXPECT_EQ(state.snapshot()["victims"][0]["wgs84"], expected);
  EXPECT_EQ(expected.rfind("46.5562", 0), 0u) << expected << ": 50 m south of 46.5567 N";
  // The deposit's outline goes with every snapshot, as the building does.
  EXPECT_TRUE(state.snapshot()["deposit"].empty());
  state.set_deposit({{-45.0, 10.0}, {60.0, 0.0}, {70.0, 70.0}});
  EXPECT_EQ(state.snapshot()["deposit"], nlohmann::json::parse("[[-45.0, 10.0], [60.0, 0.0], [70.0, 70.0]]"));
}

// Incident command's search plan: in every snapshot, in a delta only when it changed (a new
// revision or more searched), and its strips in the GeoJSON.
TEST(PictureState, TheSearchPlanIsInSnapshotsAndInDeltasWhenItChanged) {
  Clocks c;
  auto state = make(c);
  EXPECT_FALSE(state.snapshot().contains("plan"));
  auto plan = test::sample_search_plan();
  state.on_search_plan(plan);
  const auto snapshot = state.snapshot();
  ASSERT_TRUE(snapshot.contains("plan"));
  EXPECT_EQ(snapshot["plan"]["strips"][0]["rescuer"], "r1");
  EXPECT_EQ(snapshot["plan"]["strips"][0]["next"], nlohmann::json::parse("[20.0, 80.0]"));
  EXPECT_EQ(snapshot["plan"]["pursuers"]["7"], "r1") << "victim 7 is r1's; r2's signal of it handed over";
  EXPECT_FALSE(snapshot["plan"]["pursuers"].contains("0")) << "victim id 0 is no victim";
  EXPECT_EQ(snapshot["plan"]["unplaced_pursuits"], nlohmann::json::parse(R"([{"pursuer": "r3", "others": ["r1"]}])"))
      << "a transmitter not yet placed: r3 pursues it, r1's signal of it handed over";
  ASSERT_EQ(snapshot["plan"]["digs"].size(), 2u);
  EXPECT_EQ(snapshot["plan"]["digs"][0]["victim"], 7) << "dig order: victim 7 first";
  EXPECT_EQ(snapshot["plan"]["digs"][0]["digger"], "r3");
  EXPECT_EQ(snapshot["plan"]["digs"][1]["digger"], "") << "no free rescuer for victim 9 yet";
  EXPECT_DOUBLE_EQ(snapshot["plan"]["expected_survivors"].get<double>(), 1.35);
  const auto version = state.version();
  state.on_search_plan(plan);
  EXPECT_FALSE(state.delta(version).contains("plan")) << "the same plan again: nothing to send";
  plan.plan.searched = 0.3;
  plan.plan.strips[0].searched = 0.6;
  state.on_search_plan(plan);
  const auto delta = state.delta(version);
  ASSERT_TRUE(delta.contains("plan"));
  EXPECT_DOUBLE_EQ(delta["plan"]["strips"][0]["searched"].get<double>(), 0.6);
  EXPECT_TRUE(delta["plan"]["strips"][1]["next"].is_null()) << "strip 1 is done";
  const auto before_dig = state.version();
  plan.digs.digs[1].digger_id = "r2";  // a rescuer free for victim 9 now
  state.on_search_plan(plan);
  EXPECT_EQ(state.delta(before_dig)["plan"]["digs"][1]["digger"], "r2") << "a new digger is sent";
  const auto before_placed = state.version();
  plan.handed_over.pop_back();  // r3 placed that transmitter (or it was given back to all)
  state.on_search_plan(plan);
  const auto placed = state.delta(before_placed);
  ASSERT_TRUE(placed.contains("plan")) << "a pursuit before placement ended: the plan is sent";
  EXPECT_EQ(placed["plan"]["unplaced_pursuits"], nlohmann::json::array()) << "the page drops the line";
  // An operator drew another deposit: the plan over it replaces the mission's on the map.
  EXPECT_EQ(state.snapshot()["deposit"],
            nlohmann::json::parse("[[0.0, 0.0], [80.0, 0.0], [80.0, 100.0], [0.0, 100.0]]"));
  const auto before_drawing = state.version();
  plan.deposit = {{0, 0}, {50, 0}, {50, 60}};
  state.on_search_plan(plan);
  const auto drawn = nlohmann::json::parse("[[0.0, 0.0], [50.0, 0.0], [50.0, 60.0]]");
  EXPECT_EQ(state.delta(before_drawing)["plan"]["deposit"], drawn) << "the page redraws the deposit from the plan";
  EXPECT_EQ(state.snapshot()["deposit"], drawn);
  state.set_geodetic_origin({46.5563, 7.9263, 2320.0});
  const auto geo = state.geojson();
  ASSERT_TRUE(geo);
  bool strip_seen = false;
  for (const auto& f : (*geo)["features"]) strip_seen = strip_seen || f["properties"]["kind"] == "strip";
  EXPECT_TRUE(strip_seen) << geo->dump();
}

TEST(PictureState, DeltasCarryOnlyWhatChangedAndEventsMarkTransitions) {
  Clocks c;
  auto state = make(c);
  auto v = test::sample_fused_victim();
  v.victim_id = 3;
  v.state = incident::VictimState::kLocated;
  v.evidence_conflict = false;
  state.on_victim(v);
  const auto after_first = state.version();
  auto snapshot = state.snapshot();
  ASSERT_EQ(snapshot["victims"].size(), 1u);
  EXPECT_EQ(snapshot["victims"][0]["state"], "LOCATED");
  EXPECT_TRUE(has_event(snapshot, "victim 3 in the picture"));

  auto p = test::sample_responder_position();
  p.responder_id = "r1";
  state.on_position(p);
  auto delta = state.delta(after_first);
  EXPECT_EQ(delta["victims"].size(), 0u) << "the victim did not change";
  ASSERT_EQ(delta["responders"].size(), 1u);
  EXPECT_EQ(delta["responders"][0]["id"], "r1");

  const auto before_found = state.version();
  v.state = incident::VictimState::kFound;
  state.on_victim(v);
  delta = state.delta(before_found);
  ASSERT_EQ(delta["victims"].size(), 1u);
  EXPECT_EQ(delta["victims"][0]["state"], "FOUND");
  EXPECT_TRUE(has_event(delta, "victim 3 FOUND"));
  EXPECT_EQ(delta["version"], state.version());

  const auto before_gone = state.version();
  state.on_victim_gone(3);
  delta = state.delta(before_gone);
  ASSERT_EQ(delta["removed"].size(), 1u);
  EXPECT_EQ(delta["removed"][0]["kind"], "victim");
  EXPECT_EQ(state.victim_count(), 0u);
  state.on_victim_gone(3);  // twice: nothing more
  EXPECT_EQ(state.delta(state.version())["removed"].size(), 0u);
}

TEST(PictureState, LinksAlarmsAndPar) {
  Clocks c;
  PictureStateConfig config;
  config.par_interval_s = 600;
  auto state = make(c, config);
  auto t = test::sample_team_status();
  t.team_id = "alpha";
  t.members.resize(1);
  t.members[0].responder_id = "ff1";
  t.members[0].link = incident::LinkState::kAlive;
  state.on_team(t);
  auto snapshot = state.snapshot();
  EXPECT_EQ(snapshot["teams"][0]["par_due_wall_ms"], static_cast<std::int64_t>((1000.0 + 600.0) * 1e3));
  t.members[0].link = incident::LinkState::kLost;
  state.on_team(t);
  EXPECT_TRUE(has_event(state.snapshot(), "ff1 (alpha): link LOST"));

  c.wall += 700;  // overdue; reported now
  EXPECT_TRUE(state.par_reported("alpha", "ic"));
  EXPECT_FALSE(state.par_reported("nosuch", "ic"));
  EXPECT_EQ(state.snapshot()["teams"][0]["par_due_wall_ms"], static_cast<std::int64_t>((1700.0 + 600.0) * 1e3));

  auto a = test::sample_incident_alarm();
  a.alarm_id = 9;
  a.acknowledged = false;
  a.alarm.active = true;
  state.on_alarm(a);
  a.acknowledged = true;
  a.acknowledged_by = "ic";
  state.on_alarm(a);
  a.alarm.active = false;
  state.on_alarm(a);
  snapshot = state.snapshot();
  EXPECT_TRUE(has_event(snapshot, "alarm 9 for ff-7 RAISED"));
  EXPECT_TRUE(has_event(snapshot, "acknowledged by ic"));
  EXPECT_TRUE(has_event(snapshot, "cleared"));
  state.on_alarm_gone(9);
  EXPECT_EQ(state.snapshot()["alarms"].size(), 0u);
}

// Incident command republishes every alarm each cycle: an unchanged one is not sent to the pages
// again (a page re-read every alarm four times a second before), a reopened one is.
TEST(PictureState, AnAlarmRepublishedUnchangedIsNotSentAgain) {
  Clocks c;
  auto state = make(c);
  auto a = test::sample_incident_alarm();
  a.alarm_id = 4;
  a.alarm.active = false;
  state.on_alarm(a);
  const auto seen = state.version();
  for (int cycle = 0; cycle < 5; ++cycle) state.on_alarm(a);
  EXPECT_EQ(state.version(), seen);
  EXPECT_EQ(state.delta(seen)["alarms"].size(), 0u);
  a.alarm.active = true;
  a.alarm.raised_at += 1'000'000'000;
  a.alarm.cleared_at = 0;
  state.on_alarm(a);
  const auto delta = state.delta(seen);
  ASSERT_EQ(delta["alarms"].size(), 1u);
  EXPECT_TRUE(has_event(delta, "alarm 4 for ff-7 RAISED again"));
}

// Removals are kept for pages that have not seen them, up to a bound: a page further behind gets
// a snapshot, which holds no removed victim.
TEST(PictureState, APageBehindTheRemovalsKeptGetsASnapshot) {
  Clocks c;
  auto state = make(c);
  auto v = test::sample_fused_victim();
  v.victim_id = 1;
  state.on_victim(v);
  const auto behind = state.version();
  state.on_victim_gone(1);
  const auto caught_up = state.version();
  EXPECT_EQ(state.delta(behind)["type"], "delta");
  EXPECT_FALSE(state.needs_snapshot(behind));
  for (std::uint32_t id = 2; id < 6000; ++id) {
    v.victim_id = id;
    state.on_victim(v);
    state.on_victim_gone(id);
  }
  EXPECT_TRUE(state.needs_snapshot(behind));
  EXPECT_TRUE(state.needs_snapshot(caught_up));
  const auto delta = state.delta(behind);
  EXPECT_EQ(delta["type"], "snapshot");
  EXPECT_EQ(delta["victims"].size(), 0u);
  const auto recent = state.version() - 10;
  EXPECT_FALSE(state.needs_snapshot(recent));
  EXPECT_EQ(state.delta(recent)["type"], "delta");
}

TEST(PictureState, TheBannerComesWhenNoDataArrivesForStaleAfter) {
  Clocks c;
  PictureStateConfig config;
  config.stale_after_s = 5;
  auto state = make(c, config);
  EXPECT_TRUE(state.heartbeat()["stale"]) << "nothing ever heard";
  state.on_position(test::sample_responder_position());
  c.wall += 4;
  EXPECT_FALSE(state.heartbeat()["stale"]);
  c.wall += 2;
  EXPECT_TRUE(state.heartbeat()["stale"]);
  EXPECT_NEAR(state.heartbeat()["data_age_s"].get<double>(), 6.0, 1e-9);
}

responder::ResponderPosition map_aided_fix_of_ff1_at_10_s() {
  auto p = test::sample_responder_position();
  p.responder_id = "ff1";
  p.source = responder::PositionSource::kMapAided;
  p.stamp = 10'000'000'000LL;
  return p;
}

TEST(PictureState, AnOlderPositionOrADeadReckoningOverAFreshMapAidedFixIsNotShown) {
  Clocks c;
  auto state = make(c);
  auto p = map_aided_fix_of_ff1_at_10_s();
  p.position.position = Vec3(1, 2, 0);
  state.on_position(p);
  auto older = p;
  older.stamp = 9'000'000'000LL;
  older.position.position = Vec3(50, 50, 0);
  state.on_position(older);
  auto reckoned = p;
  reckoned.source = responder::PositionSource::kDeadReckoning;
  reckoned.stamp = 11'000'000'000LL;
  reckoned.position.position = Vec3(60, 60, 0);
  state.on_position(reckoned);
  const auto r = state.snapshot()["responders"][0];
  EXPECT_DOUBLE_EQ(r["x"].get<double>(), 1.0);
  EXPECT_EQ(r["source"], "map-aided");
}

// The core daemon writes a silent firefighter's last position again (estimator::PositionRefresh):
// the map shows one point, and no browser is told of a change.
TEST(PictureState, TheDaemonsCopyOfALastPositionChangesNothing) {
  Clocks c;
  auto state = make(c);
  auto p = map_aided_fix_of_ff1_at_10_s();
  state.on_position(p);
  const auto version = state.version();
  state.on_position(p);
  state.on_position(p);
  EXPECT_EQ(state.version(), version);
  EXPECT_EQ(state.snapshot()["responders"][0]["track"].size(), 1U);
  p.stamp += 500'000'000LL;  // a new one at the same place is news
  state.on_position(p);
  EXPECT_GT(state.version(), version);
  EXPECT_EQ(state.snapshot()["responders"][0]["track"].size(), 2U);
}

// Issue 65: an ambiguous firefighter is drawn at each place he may be in, with its weight, not
// at the mean between them; the places of another time, or of a position no longer ambiguous,
// are not drawn.
TEST(PictureState, AnAmbiguousPositionCarriesItsPlacesOnlyWhileItIsAmbiguous) {
  Clocks c;
  auto state = make(c);
  auto places = test::sample_responder_candidates();
  places.responder_id = "ff1";
  places.stamp = 10'000'000'000LL;
  state.on_candidates(places);
  responder::Guidance g;
  g.rescuer_id = "ff1";
  state.on_guidance(g);
  EXPECT_TRUE(state.snapshot()["responders"].empty()) << "no position yet: nothing to draw, nowhere";
  auto p = map_aided_fix_of_ff1_at_10_s();
  p.converged = false;
  p.ambiguous = true;
  state.on_position(p);
  auto r = state.snapshot()["responders"][0];
  EXPECT_TRUE(r["ambiguous"].get<bool>());
  ASSERT_EQ(r["candidates"].size(), 2U);
  EXPECT_DOUBLE_EQ(r["candidates"][0]["weight"].get<double>(), 0.625);
  EXPECT_EQ(r["candidates"][0]["floor"], 3);
  EXPECT_DOUBLE_EQ(r["candidates"][1]["x"].get<double>(),
                   std::round(100.0 * places.candidates[1].position.position.x()) / 100.0);

  auto older = places;  // late, out of order: the newest places stay
  older.stamp = 9'000'000'000LL;
  older.candidates.resize(1);
  state.on_candidates(older);
  EXPECT_EQ(state.snapshot()["responders"][0]["candidates"].size(), 2U);

  p.stamp = 16'000'000'000LL;  // still ambiguous, but these places are 6 s old
  state.on_position(p);
  EXPECT_TRUE(state.snapshot()["responders"][0]["candidates"].empty());

  places.stamp = p.stamp;
  state.on_candidates(places);
  EXPECT_EQ(state.snapshot()["responders"][0]["candidates"].size(), 2U);
  const auto version = state.version();
  p.stamp += 500'000'000LL;  // converged: one place, the mean
  p.ambiguous = false;
  p.converged = true;
  state.on_position(p);
  EXPECT_GT(state.version(), version);
  r = state.snapshot()["responders"][0];
  EXPECT_FALSE(r["ambiguous"].get<bool>());
  EXPECT_TRUE(r["candidates"].empty());
}

// The picture's limits are checked where the state is made, whoever fills them.
TEST(PictureState, ItsConfigIsCheckedNamingTheKey) {
  EXPECT_EQ(sarloc::test::validation_error(PictureStateConfig{}), "");
  PictureStateConfig no_track;
  no_track.track_length = 0;
  EXPECT_EQ(sarloc::test::validation_error(no_track), "dashboard.track_length = 0: must be 1-10000");
  PictureStateConfig jittery;
  jittery.stale_after_s = 0.1;
  EXPECT_EQ(sarloc::test::validation_error(jittery), "dashboard.stale_after_s = 0.1: must be in [0.5, 3600]");
  PictureStateConfig no_log;
  no_log.event_log_length = 0;
  EXPECT_THROW(PictureState(no_log, [] { return TimestampNs{0}; }, 0), ConfigError);
}

}  // namespace
}  // namespace sarloc::dashboard
