// IncidentCommand: its config, which estimates are fused and with which fix, links, alarms and
// acknowledgements. Hot standby: incident_command_standby_test.cpp.
#include <gtest/gtest.h>

#include <cmath>

#include "incident_commands.hpp"
#include "sarloc/core/common/errors.hpp"
#include "support/config_messages.hpp"

namespace sarloc::incident {
namespace {

using responder::AlarmKind;
using responder::EstimatorStatus;
using test::at;
using test::command_config;
using test::estimate_of;
using test::gnss_fix;
using test::has_event;
using Kind = IncidentEvent::Kind;

const IncidentAlarm* alarm_of(const CommandCycle& out, const std::string& responder, AlarmKind kind) {
  for (const auto& a : out.alarms) {
    if (a.alarm.responder_id == responder && a.alarm.kind == kind) return &a;
  }
  return nullptr;
}

const MemberStatus* member_of(const CommandCycle& out, const std::string& responder) {
  for (const auto& t : out.teams) {
    for (const auto& m : t.members) {
      if (m.responder_id == responder) return &m;
    }
  }
  return nullptr;
}

TEST(IncidentCommand, ConfigMessagesNameTheKey) {
  EXPECT_NO_THROW(IncidentCommandConfig{}.validate());
  auto c = command_config();
  c.fix_wait_s = 0.0;
  EXPECT_EQ(sarloc::test::validation_error(c), "command.fix_wait_s = 0: must be in (0, 600]");
  c = command_config();
  c.antenna_height_m = 7.5;
  EXPECT_EQ(sarloc::test::validation_error(c), "command.antenna_height_m = 7.5: must be in [0, 5]");
  c = command_config();
  c.origin.latitude_deg = 91.0;
  EXPECT_EQ(sarloc::test::validation_error(c), "incident.latitude_deg = 91: must be in [-90, 90]");
  c = command_config();
  c.incident_id = "";
  EXPECT_EQ(sarloc::test::validation_error(c), "incident.id = '': must be 1-64 characters");
  c = command_config();
  c.fusion.gate_probability = 1.5;  // the parts' own checks too
  EXPECT_EQ(sarloc::test::validation_error(c), "fusion.gate_probability = 1.5: must be in (0, 1)");
  EXPECT_THROW(IncidentCommand(c, at(0)), ConfigError);
}

TEST(IncidentCommand, ASingleInstanceIsActiveAtItsFirstCycleAndStampsTheFrame) {
  IncidentCommand command(command_config(), at(0));
  const auto out = command.cycle(at(2), at(2));
  ASSERT_TRUE(out.role_change);
  EXPECT_EQ(out.role_change->role, CommandRole::kActive);
  EXPECT_TRUE(out.active);
  EXPECT_EQ(out.frame.incident_id, "unit-incident");
  EXPECT_EQ(out.frame.name, "Unit test");
  EXPECT_EQ(out.frame.established, at(2));
  EXPECT_EQ(out.stamp, at(2));
  EXPECT_TRUE(has_event(out, Kind::kInfo, "active ("));
  const auto next = command.cycle(at(3), at(3));
  EXPECT_FALSE(next.role_change);
  EXPECT_EQ(next.frame.established, at(2)) << "established once";
}

// A multimodal filter's mean lies between its modes: it places nobody.
TEST(IncidentCommand, OnlyConvergedEstimatesAreFused) {
  IncidentCommand command(command_config(), at(0));
  command.on_position(gnss_fix("r1", at(1), Vec3(10, 20, 1500)), "w-r1", at(1));
  command.on_estimate(estimate_of("r1", 1, at(1), EstimatorStatus::kMultimodal), "w-r1", true, at(1));
  command.on_estimate(estimate_of("r1", 2, at(1), EstimatorStatus::kInitialising), "w-r1", true, at(1));
  auto out = command.cycle(at(1.5), at(1.5));
  EXPECT_EQ(out.estimates_fused, 0U);
  EXPECT_TRUE(out.victims.empty());
  EXPECT_EQ(command.estimates_waiting(), 0U) << "not kept for later either";

  command.on_estimate(estimate_of("r1", 1, at(1), EstimatorStatus::kConverged), "w-r1", true, at(1.6));
  out = command.cycle(at(2), at(2));
  EXPECT_EQ(out.estimates_fused, 1U);
  ASSERT_EQ(out.victims.size(), 1U);
  // The rescuer's fix plus the relative estimate; the height is the antenna's above the snow
  // (1 m by default) plus the relative -2 m, not GNSS altitude.
  EXPECT_NEAR(out.victims[0].position.position.x(), 13.0, 1e-9);
  EXPECT_NEAR(out.victims[0].position.position.y(), 24.0, 1e-9);
  EXPECT_NEAR(out.victims[0].position.position.z(), -1.0, 1e-9);
  EXPECT_EQ(out.counts.victims_total, 1U);
  EXPECT_EQ(out.counts.responders_total, 1U);
}

// The fix may still be on its way: the estimate waits fix_wait_s (1 s here) from its arrival.
TEST(IncidentCommand, AnEstimateWaitsForItsFixThenIsDropped) {
  IncidentCommand command(command_config(), at(0));
  command.on_estimate(estimate_of("r1", 1, at(10)), "w-r1", true, at(10));
  auto out = command.cycle(at(10.2), at(10.2));
  EXPECT_TRUE(out.victims.empty());
  EXPECT_EQ(command.estimates_waiting(), 1U);
  EXPECT_TRUE(has_event(out, Kind::kDebug, "no fix of 'r1'"));
  command.on_position(gnss_fix("r1", at(10), Vec3(10, 20, 0)), "w-r1", at(10.5));
  out = command.cycle(at(10.9), at(10.9));
  EXPECT_EQ(out.estimates_fused, 1U) << "placed once its fix came, within the wait";
  EXPECT_EQ(out.victims.size(), 1U);

  command.on_estimate(estimate_of("r2", 1, at(20)), "w-r2", true, at(20));
  command.cycle(at(20.5), at(20.5));
  EXPECT_EQ(command.estimates_waiting(), 1U);
  out = command.cycle(at(21), at(21));  // waited its second: dropped
  EXPECT_EQ(command.estimates_waiting(), 0U);
  command.on_position(gnss_fix("r2", at(20), Vec3(50, 0, 0)), "w-r2", at(21.2));
  out = command.cycle(at(21.5), at(21.5));
  EXPECT_EQ(out.victims.size(), 1U) << "a dropped estimate is not placed by a late fix";
}

// A fix further than position_max_age_s from the stamp misplaces the victim by the rescuer's
// walk since: it is not used; a device's estimate carrying its epoch's fix needs no other.
TEST(IncidentCommand, AnEstimateIsPlacedWithTheFixOfItsEpoch) {
  IncidentCommand command(command_config(), at(0));
  command.on_position(gnss_fix("r1", at(5), Vec3(0, 0, 0)), "w-r1", at(5));
  command.on_estimate(estimate_of("r1", 1, at(8)), "w-r1", true, at(8));  // 3 s later: too old, no later fix
  auto out = command.cycle(at(8.1), at(8.1));
  EXPECT_TRUE(out.victims.empty());

  auto carrying = estimate_of("r2", 1, at(8));
  carrying.reporter = gnss_fix("r2", at(8), Vec3(100, 0, 1500));
  command.on_estimate(carrying, "w-r2", true, at(8.2));
  out = command.cycle(at(8.3), at(8.3));
  ASSERT_EQ(out.victims.size(), 1U);
  EXPECT_NEAR(out.victims[0].position.position.x(), 103.0, 1e-9);

  // Fixes just before and after the stamp (at most 2.5 s apart) are interpolated.
  command.on_position(gnss_fix("r3", at(30), Vec3(0, -100, 0)), "w-r3", at(30));
  command.on_position(gnss_fix("r3", at(32), Vec3(2, -100, 0)), "w-r3", at(32));
  command.on_estimate(estimate_of("r3", 1, at(31)), "w-r3", true, at(32));
  out = command.cycle(at(32.1), at(32.1));
  ASSERT_EQ(out.estimates_fused, 1U);
  bool placed = false;
  for (const auto& v : out.victims) {
    if (std::abs(v.position.position.y() - (-96.0)) < 1e-6) {
      placed = true;
      EXPECT_NEAR(v.position.position.x(), 4.0, 1e-6);
    }
  }
  EXPECT_TRUE(placed);
}

TEST(IncidentCommand, ANonFinitePositionIsRefusedAndChangesNothing) {
  IncidentCommand command(command_config(), at(0));
  command.on_position(gnss_fix("r1", at(1), Vec3(std::nan(""), 0, 0)), "w-r1", at(1));
  const auto out = command.cycle(at(1.5), at(1.5));
  ASSERT_EQ(out.events.size(), 2U);  // the input's refusal first, then "active"
  const auto& refusal = out.events[0];
  EXPECT_EQ(refusal.kind, Kind::kRejected);
  EXPECT_EQ(refusal.reason, "invalid_value");
  EXPECT_EQ(refusal.subject, "r1");
  EXPECT_EQ(refusal.text, "responder_position.position: non-finite value");
  EXPECT_EQ(out.counts.responders_total, 0U);
}

// A device's own position writer stands for its link; the core daemon's map-aided writer
// serves many responders and stands for none.
TEST(IncidentCommand, ALostDeviceWriterRaisesLinkLostUntilAcknowledgedAndBack) {
  IncidentCommand command(command_config(), at(0));
  command.on_position(gnss_fix("r1", at(1), Vec3(5, 5, 0)), "w-r1", at(1));
  auto mapped = gnss_fix("r2", at(1), Vec3(9, 9, 0));
  mapped.source = responder::PositionSource::kMapAided;
  command.on_position(mapped, "w-core", at(1));
  command.cycle(at(1), at(1));
  command.on_writer_liveliness("w-core", false, at(2));
  command.on_writer_liveliness("w-r1", false, at(2));
  auto out = command.cycle(at(2.5), at(2.5));
  EXPECT_TRUE(has_event(out, Kind::kWarning, "link to responder 'r1' lost"));
  EXPECT_FALSE(has_event(out, Kind::kWarning, "'r2'"));
  const IncidentAlarm* lost = alarm_of(out, "r1", AlarmKind::kLinkLost);
  ASSERT_NE(lost, nullptr);
  EXPECT_EQ(lost->alarm.cleared_at, 0);
  EXPECT_NEAR(lost->alarm.last_position.position.x(), 5.0, 1e-9) << "where it was last known";
  EXPECT_EQ(alarm_of(out, "r2", AlarmKind::kLinkLost), nullptr);
  EXPECT_EQ(out.counts.responders_link_lost, 1U);
  const auto id = lost->alarm_id;

  command.on_writer_liveliness("w-r1", true, at(3));
  command.on_position(gnss_fix("r1", at(3), Vec3(5, 6, 0)), "w-r1", at(3));
  out = command.cycle(at(3.5), at(3.5));
  ASSERT_NE(alarm_of(out, "r1", AlarmKind::kLinkLost), nullptr) << "cleared, but stays until acknowledged";
  EXPECT_NE(alarm_of(out, "r1", AlarmKind::kLinkLost)->alarm.cleared_at, 0);
  command.on_acknowledgement(id, "ic-1", at(4), at(4));
  out = command.cycle(at(4.5), at(4.5));
  EXPECT_EQ(alarm_of(out, "r1", AlarmKind::kLinkLost), nullptr);
  EXPECT_EQ(out.disposed_alarms, std::vector<std::uint32_t>{id});
  EXPECT_TRUE(has_event(out, Kind::kInfo, "alarm " + std::to_string(id) + " acknowledged by 'ic-1'"));
}

// With a deposit, incident command plans the primary search from the avalanche rescuers' fixes:
// one strip each (two rescuers on 150 m: four strips of 37.5 m, two taken), entered from their
// side, every cycle in its output; a rescuer whose link is lost gives its strip back, said.
// Without a deposit, no plan; a deposit with too many vertices is refused by its key.
// An operator's drawn outline: a mission without a deposit gets a plan over it; a new outline
// replaces it (strips cut afresh); the same one again changes nothing; a crossing outline, one
// too big for 64 strips, a bad operator id or another incident's changes nothing, refused by name.
TEST(IncidentCommand, AnOperatorsDrawnDepositIsPlannedOverAndABadOneRefused) {
  const auto config = command_config();
  IncidentCommand command(config, at(0));
  command.on_position(gnss_fix("r1", at(1), Vec3(40, 205, 0)), "w-r1", at(1));
  command.on_position(gnss_fix("r2", at(1), Vec3(110, 205, 0)), "w-r2", at(1));
  EXPECT_FALSE(command.cycle(at(1.5), at(1.5)).search_plan) << "no deposit: no plan";
  const std::vector<Vec2> drawn{{0, 0}, {150, 0}, {150, 200}, {0, 200}};
  command.on_deposit_drawing("other-incident", drawn, "dashboard");
  EXPECT_FALSE(command.cycle(at(2), at(2)).search_plan) << "another incident's outline";
  command.on_deposit_drawing(config.incident_id, drawn, "dashboard");
  auto out = command.cycle(at(2.5), at(2.5));
  ASSERT_TRUE(out.search_plan);
  EXPECT_EQ(out.search_plan->plan.strips.size(), 4u);
  EXPECT_TRUE(has_event(out, Kind::kInfo, "deposit drawn by 'dashboard': 4 vertices, 30000 m2"));
  const std::uint32_t revision = out.search_plan->plan.revision;
  command.on_deposit_drawing(config.incident_id, drawn, "dashboard");
  out = command.cycle(at(3), at(3));
  EXPECT_FALSE(has_event(out, Kind::kInfo, "deposit drawn")) << "the same outline again";
  EXPECT_EQ(out.search_plan->plan.revision, revision);
  // Half as wide: two strips, cut afresh.
  command.on_deposit_drawing(config.incident_id, {{0, 0}, {75, 0}, {75, 200}, {0, 200}}, "dashboard");
  out = command.cycle(at(3.5), at(3.5));
  ASSERT_TRUE(out.search_plan);
  EXPECT_EQ(out.search_plan->plan.strips.size(), 2u);
  EXPECT_TRUE(has_event(out, Kind::kWarning, "in place of the last one"));
  const auto refused = [&](const std::vector<Vec2>& outline, const std::string& op, const std::string& part) {
    command.on_deposit_drawing(config.incident_id, outline, op);
    const auto cycle = command.cycle(at(4), at(4));
    EXPECT_TRUE(has_event(cycle, Kind::kRejected, part)) << part;
    ASSERT_TRUE(cycle.search_plan);
    EXPECT_EQ(cycle.search_plan->plan.strips.size(), 2u) << "a refused outline changes nothing";
  };
  refused({{0, 0}, {100, 100}, {100, 0}, {0, 100}}, "dashboard", "deposit_drawing.outline");  // crossing edges
  refused({{0, 0}, {100, 0}}, "dashboard", "deposit_drawing.outline");
  refused({{0, 0}, {3000, 0}, {3000, 3000}, {0, 3000}}, "dashboard", "strips at search.strip_width_m");
  refused(drawn, "not an id!", "operator_id is not an identifier");
}

TEST(IncidentCommand, WithADepositItPlansTheSearchAndALostRescuersStripOpens) {
  EXPECT_FALSE(IncidentCommand(command_config(), at(0)).cycle(at(1), at(1)).search_plan);
  auto config = command_config();
  config.deposit.emplace(std::vector<Vec2>{{0, 0}, {150, 0}, {150, 200}, {0, 200}}, "incident.deposit");
  IncidentCommand command(config, at(0));
  command.on_position(gnss_fix("r1", at(1), Vec3(40, 205, 0)), "w-r1", at(1));
  command.on_position(gnss_fix("r2", at(1), Vec3(110, 205, 0)), "w-r2", at(1));
  auto out = command.cycle(at(1.5), at(1.5));
  ASSERT_TRUE(out.search_plan);
  const SearchPlanPicture& plan = *out.search_plan;
  EXPECT_EQ(plan.incident_id, config.incident_id);
  EXPECT_EQ(plan.deposit.size(), 4u);
  ASSERT_EQ(plan.plan.strips.size(), 4u);
  ASSERT_EQ(plan.next_points.size(), 4u);
  std::size_t taken = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    const auto& s = plan.plan.strips[i];
    EXPECT_NEAR(s.strip.top.y(), 200.0, 1e-6) << "entered from the rescuers' (north) side";
    if (s.rescuer_id.empty()) continue;
    ++taken;
    ASSERT_TRUE(plan.next_points[i]) << "where " << s.rescuer_id << " walks next";
  }
  EXPECT_EQ(taken, 2u);
  EXPECT_TRUE(has_event(out, Kind::kInfo, "search plan revision"));
  const auto r1_strip = command.search_planner()->strip_of("r1");
  ASSERT_TRUE(r1_strip);
  // A firefighter's map-aided fix indoors searches nothing of the deposit.
  auto indoors = gnss_fix("ff1", at(2), Vec3(75, 100, 0));
  indoors.source = responder::PositionSource::kMapAided;
  command.on_position(indoors, "w-core", at(2));
  command.on_writer_liveliness("w-r1", false, at(2));
  out = command.cycle(at(2.5), at(2.5));
  ASSERT_TRUE(out.search_plan);
  EXPECT_TRUE(out.search_plan->plan.strips[*r1_strip].rescuer_id.empty()) << "r1's strip open again";
  EXPECT_TRUE(has_event(out, Kind::kWarning, "strip " + std::to_string(*r1_strip) + " open again (r1"));
  EXPECT_FALSE(command.search_planner()->strip_of("ff1"));

  auto too_many = command_config();
  std::vector<Vec2> circle;
  for (int k = 0; k < 300; ++k) circle.emplace_back(100.0 * std::cos(k * 0.02094), 100.0 * std::sin(k * 0.02094));
  too_many.deposit.emplace(circle, "incident.deposit");
  EXPECT_THROW(
      {
        try {
          IncidentCommand(too_many, at(0));
        } catch (const ConfigError& e) {
          EXPECT_NE(std::string(e.what()).find("incident.deposit"), std::string::npos) << e.what();
          throw;
        }
      },
      ConfigError);
  // 3 km across at 40 m: 75 strips, beyond the SearchPlan topic's 64.
  auto too_wide = command_config();
  too_wide.deposit.emplace(std::vector<Vec2>{{0, 0}, {3000, 0}, {3000, 3000}, {0, 3000}}, "incident.deposit");
  try {
    IncidentCommand(too_wide, at(0));
    ADD_FAILURE() << "75 strips accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("incident.deposit = 75: strips at search.strip_width_m"), std::string::npos)
        << e.what();
  }
}

// Two rescuers hear one transmitter (its signature alike on both receivers) before either has
// placed it: the first to take it pursues it, the other's signal is handed over (victim id 0).
// Signals without a signature (the ideal receiver) are handed nothing.
TEST(IncidentCommand, ATransmitterTwoRescuersHearBeforeEitherPlacesItGoesToTheFirst) {
  auto config = command_config();
  config.deposit.emplace(std::vector<Vec2>{{0, 0}, {150, 0}, {150, 200}, {0, 200}}, "incident.deposit");
  IncidentCommand command(config, at(0));
  command.on_position(gnss_fix("r1", at(1), Vec3(40, 205, 0)), "w-r1", at(1));
  command.on_position(gnss_fix("r2", at(1), Vec3(110, 205, 0)), "w-r2", at(1));
  auto r1 = estimate_of("r1", 3, at(1.2), EstimatorStatus::kMultimodal);
  auto r2 = estimate_of("r2", 1, at(1), EstimatorStatus::kMultimodal);
  command.on_estimate(r1, "w-core", false, at(1.3));
  command.on_estimate(r2, "w-core", false, at(1.3));
  auto out = command.cycle(at(1.5), at(1.5));
  ASSERT_TRUE(out.search_plan);
  EXPECT_TRUE(out.search_plan->handed_over.empty()) << "no signature: nobody can tell it is one transmitter";

  r1.transmitter = {12.0, 0.3, 0.850, 0.002};
  r2.transmitter = {12.2, 0.3, 0.851, 0.002};
  command.on_estimate(r1, "w-core", false, at(2));
  command.on_estimate(r2, "w-core", false, at(2));
  out = command.cycle(at(2.5), at(2.5));
  ASSERT_TRUE(out.search_plan);
  ASSERT_EQ(out.search_plan->handed_over.size(), 1u);
  const auto& h = out.search_plan->handed_over[0];
  EXPECT_EQ(h.rescuer_id, "r1");
  EXPECT_EQ(h.signal_id, 3u);
  EXPECT_EQ(h.victim_id, 0u);
  EXPECT_EQ(h.pursued_by, "r2") << "r2 heard it first (stamp 1 s against 1.2 s)";
  EXPECT_TRUE(
      has_event(out, Kind::kInfo, "signal r2/1 (carrier +12.2 Hz, period 0.851 s; not yet placed): pursued by r2"));
  {
    // With their distance readings (their mixtures' components: r1's 20-30 m off, r2's 50 m),
    // the nearer by reading is sent, although r2 heard it first.
    IncidentCommand by_reading(config, at(0));
    by_reading.on_position(gnss_fix("r1", at(1), Vec3(40, 205, 0)), "w-r1", at(1));
    by_reading.on_position(gnss_fix("r2", at(1), Vec3(110, 205, 0)), "w-r2", at(1));
    auto near = r1, far = r2;
    near.top_components = {{0.6, Vec3(20, 0, -1), Mat3::Identity()}, {0.4, Vec3(0, -30, -1), Mat3::Identity()}};
    far.top_components = {{1.0, Vec3(-30, -40, -1), Mat3::Identity()}};
    by_reading.on_estimate(near, "w-core", false, at(2));
    by_reading.on_estimate(far, "w-core", false, at(2));
    const auto read = by_reading.cycle(at(2.5), at(2.5));
    ASSERT_TRUE(read.search_plan);
    ASSERT_EQ(read.search_plan->handed_over.size(), 1u);
    EXPECT_EQ(read.search_plan->handed_over[0].pursued_by, "r1");
    EXPECT_TRUE(
        has_event(read, Kind::kInfo, "pursued by r1 (of 2 who hear it, the nearest by his distance reading (24 m)"));
  }
  // Nothing heard of their signals for longer than the fusion's source timeout (the rescuers
  // still searching): nothing handed over.
  const double later = 2.5 + config.fusion.source_timeout_s + 1;
  command.on_position(gnss_fix("r1", at(later - 0.5), Vec3(40, 200, 0)), "w-r1", at(later - 0.5));
  command.on_position(gnss_fix("r2", at(later - 0.5), Vec3(110, 200, 0)), "w-r2", at(later - 0.5));
  out = command.cycle(at(later), at(later));
  ASSERT_TRUE(out.search_plan);
  EXPECT_TRUE(out.search_plan->handed_over.empty());
}

TEST(IncidentCommand, ADeviceThatDisposesItsPositionSignedOffAndRaisesNothing) {
  IncidentCommand command(command_config(), at(0));
  command.on_position(gnss_fix("r1", at(1), Vec3(5, 5, 0)), "w-r1", at(1));
  command.on_writer_disposed("w-unknown", at(2));  // a writer that stands for nobody
  command.on_writer_disposed("w-r1", at(2));
  command.on_writer_liveliness("w-r1", false, at(2.1));  // its writer then goes
  const auto out = command.cycle(at(60), at(60));
  EXPECT_TRUE(has_event(out, Kind::kInfo, "responder 'r1' signed off"));
  const MemberStatus* r1 = member_of(out, "r1");
  ASSERT_NE(r1, nullptr);
  EXPECT_EQ(r1->link, LinkState::kSignedOff);
  EXPECT_EQ(alarm_of(out, "r1", AlarmKind::kLinkLost), nullptr);
}

TEST(IncidentCommand, AMapErrorSuspectedIndoorsIsAnAlarm) {
  IncidentCommand command(command_config(), at(0));
  auto fix = gnss_fix("ff1", at(1), Vec3(4, 2, 3));
  fix.source = responder::PositionSource::kMapAided;
  fix.floor = 1;
  fix.map_error_suspected = true;
  command.on_position(fix, "w-core", at(1));
  auto out = command.cycle(at(1.5), at(1.5));
  const IncidentAlarm* error = alarm_of(out, "ff1", AlarmKind::kMapError);
  ASSERT_NE(error, nullptr);
  EXPECT_EQ(error->alarm.floor, 1);
  EXPECT_NEAR(error->alarm.last_position.position.z(), 3.0, 1e-9) << "indoors the height is kept";

  fix.stamp = at(2);
  fix.map_error_suspected = false;
  command.on_position(fix, "w-core", at(2));
  out = command.cycle(at(2.5), at(2.5));
  ASSERT_NE(alarm_of(out, "ff1", AlarmKind::kMapError), nullptr);
  EXPECT_NE(alarm_of(out, "ff1", AlarmKind::kMapError)->alarm.cleared_at, 0);
}

TEST(IncidentCommand, DeviceAlarmsAndAcknowledgementsAreCheckedAndSaid) {
  IncidentCommand command(command_config(), at(0));
  command.cycle(at(0.5), at(0.5));
  auto mayday = test::mayday_of("ff2", at(1));
  mayday.team_id = "engine-1";
  command.on_device_alarm(mayday, at(1));
  responder::ResponderAlarm backwards = mayday;
  backwards.active = false;
  backwards.cleared_at = at(0.5);  // cleared before it was raised
  command.on_device_alarm(backwards, at(1));
  command.on_acknowledgement(99, "ic-1", at(1), at(1));
  command.on_acknowledgement(1, "bad id!", at(1), at(1));
  auto out = command.cycle(at(1.5), at(1.5));
  EXPECT_TRUE(has_event(out, Kind::kWarning, "mayday alarm from 'ff2' (team 'engine-1')"));
  ASSERT_NE(alarm_of(out, "ff2", AlarmKind::kMayday), nullptr);
  std::vector<std::string> reasons;
  for (const auto& e : out.events) {
    if (e.kind == Kind::kRejected) reasons.push_back(e.reason + " " + e.subject);
  }
  EXPECT_EQ(reasons, (std::vector<std::string>{"invalid_value ff2", "unknown_alarm ic-1", "invalid_value 'bad id!'"}));

  mayday.active = false;
  mayday.cleared_at = at(2);
  command.on_device_alarm(mayday, at(2));
  out = command.cycle(at(2.5), at(2.5));
  EXPECT_TRUE(has_event(out, Kind::kInfo, "mayday alarm of 'ff2' cleared"));
}

}  // namespace
}  // namespace sarloc::incident
