// BusyGate: no new responder while the workers lag; those served are served on.
#include "sarloc/core/estimator/busy_gate.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/estimator/responder_roster.hpp"

namespace sarloc::estimator {
namespace {

using Clock = BusyGate::Clock;
using namespace std::chrono_literals;

BusyGateConfig gate_config(double max_wait_s, double hold_s, double max_utilisation = 0.0) {
  BusyGateConfig c;
  c.max_wait_s = max_wait_s;
  c.hold_s = hold_s;
  c.max_utilisation = max_utilisation;
  return c;
}

TEST(BusyGate, AWaitBeyondTheBoundClosesTheGateForTheHoldThenItOpens) {
  BusyGate gate(gate_config(0.2, 5.0));
  const auto t = Clock::now();
  EXPECT_FALSE(gate.busy(t));
  EXPECT_FALSE(gate.note_wait(200ms, t)) << "at the bound is not beyond it";
  EXPECT_FALSE(gate.busy(t));
  EXPECT_TRUE(gate.note_wait(201ms, t)) << "the wait that closes an open gate says so";
  EXPECT_TRUE(gate.busy(t));
  EXPECT_TRUE(gate.busy(t + 4900ms));
  EXPECT_FALSE(gate.note_wait(300ms, t + 1s)) << "closed already: not a second closing";
  EXPECT_TRUE(gate.busy(t + 5900ms)) << "each late wait holds it closed from then";
  EXPECT_FALSE(gate.busy(t + 6001ms));
  EXPECT_EQ(gate.closings(), 1U);
  EXPECT_TRUE(gate.note_wait(1s, t + 7s));
  EXPECT_EQ(gate.closings(), 2U);
}

TEST(BusyGate, AnEarlierNoteNeverShortensTheHold) {
  BusyGate gate(gate_config(0.2, 5.0));
  const auto t = Clock::now();
  gate.note_wait(1s, t + 3s);  // a worker that dequeued later
  gate.note_wait(1s, t);       // one that noted an older dequeue afterwards
  EXPECT_TRUE(gate.busy(t + 7s));
}

TEST(BusyGate, ZeroMaxWaitNeverCloses) {
  BusyGate gate(gate_config(0.0, 5.0));
  const auto t = Clock::now();
  EXPECT_FALSE(gate.note_wait(10s, t));
  EXPECT_FALSE(gate.busy(t));
}

TEST(BusyGate, WorkersNotingAtOnceCloseItOnce) {
  BusyGate gate(gate_config(0.2, 60.0));
  const auto t = Clock::now();
  std::vector<std::thread> workers;
  for (int w = 0; w < 4; ++w) {
    workers.emplace_back([&gate, t, w] {
      for (int k = 0; k < 1000; ++k) gate.note_wait(1s, t + std::chrono::milliseconds(w + k));
    });
  }
  for (auto& w : workers) w.join();
  EXPECT_EQ(gate.closings(), 1U);
  EXPECT_TRUE(gate.busy(t + 60s));
}

TEST(BusyGate, AWorkerBusierThanTheBoundClosesItBeforeAnySampleWaits) {
  BusyGate gate(gate_config(0.2, 5.0, 0.85));
  const auto t = Clock::now();
  EXPECT_FALSE(gate.note_utilisation(0.85, t));
  EXPECT_FALSE(gate.busy(t));
  EXPECT_TRUE(gate.note_utilisation(0.9, t));
  EXPECT_TRUE(gate.busy(t + 4s));
  EXPECT_FALSE(gate.busy(t + 5001ms));
  BusyGate off(gate_config(0.2, 5.0, 0.0));
  EXPECT_FALSE(off.note_utilisation(1.0, t));
}

TEST(BusyGate, ConfigErrorsNameTheKey) {
  try {
    BusyGate gate(gate_config(-1.0, 5.0));
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("core.busy_wait_s = -1"), std::string::npos) << e.what();
  }
  try {
    BusyGate gate(gate_config(0.2, 1e9));
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("core.busy_hold_s"), std::string::npos) << e.what();
  }
  EXPECT_THROW(BusyGate(gate_config(0.2, 5.0, 1.5)), ConfigError);
}

TEST(ResponderRoster, ABusyDaemonRefusesNewIdsAndServesTheAdmitted) {
  ResponderRoster roster({true, {}, 256, 60.0});
  const auto t = Clock::now();
  EXPECT_EQ(roster.admit("r1", t), ResponderRoster::Admission::kNew);
  EXPECT_EQ(roster.admit("r1", t + 1s, true), ResponderRoster::Admission::kServed);
  EXPECT_EQ(roster.admit("r2", t + 1s, true), ResponderRoster::Admission::kBusy);
  EXPECT_STREQ(reason_of(ResponderRoster::Admission::kBusy), "daemon_busy");
  EXPECT_EQ(roster.served(), 1U) << "a refused id leaves nothing behind";
  EXPECT_EQ(roster.admit("r2", t + 2s), ResponderRoster::Admission::kNew) << "admitted once the gate is open";
  // An unknown id is refused as unknown, not as busy: the reason an operator sees is the real one.
  ResponderRoster listed({false, {"r1"}, 256, 60.0});
  EXPECT_EQ(listed.admit("r9", t, true), ResponderRoster::Admission::kNotListed);
}

TEST(ResponderRoster, ACrowdSwitchingOnAtOnceIsAdmittedAtTheDeclaredPace) {
  ResponderRosterConfig config{true, {}, 256, 60.0};
  config.new_per_s = 10.0;
  ResponderRoster roster(config);
  const auto t = Clock::now();
  int admitted = 0;
  for (int k = 0; k < 50; ++k) admitted += roster.admit("r" + std::to_string(k), t) == ResponderRoster::Admission::kNew;
  EXPECT_EQ(admitted, 10) << "a burst of new_per_s";
  EXPECT_EQ(roster.admit("r10", t), ResponderRoster::Admission::kPaced);
  EXPECT_STREQ(reason_of(ResponderRoster::Admission::kPaced), "admission_paced");
  EXPECT_EQ(roster.admit("r0", t), ResponderRoster::Admission::kServed) << "the admitted are not paced";
  // Half a second later: five more.
  for (int k = 10; k < 50; ++k)
    admitted += roster.admit("r" + std::to_string(k), t + 500ms) == ResponderRoster::Admission::kNew;
  EXPECT_EQ(admitted, 15);
  // Unpaced: all at once.
  config.new_per_s = 0.0;
  ResponderRoster unpaced(config);
  for (int k = 0; k < 50; ++k) ASSERT_EQ(unpaced.admit("r" + std::to_string(k), t), ResponderRoster::Admission::kNew);
  config.new_per_s = -1.0;
  EXPECT_THROW(ResponderRoster{config}, ConfigError);
}

TEST(BusyGate, AWaitBeyondTheShedBoundReleasesOneResponderASecondAtMost) {
  BusyGateConfig config = gate_config(0.2, 5.0);
  config.shed_wait_s = 2.0;
  BusyGate gate(config);
  const auto t = Clock::now();
  EXPECT_FALSE(gate.note_shed(2s, t)) << "at the bound is not beyond it";
  EXPECT_FALSE(gate.note_shed(1s, t)) << "a wait that closes the gate to newcomers releases no one";
  EXPECT_TRUE(gate.note_shed(2001ms, t));
  EXPECT_FALSE(gate.note_shed(8s, t + 999ms)) << "a second release within the second";
  EXPECT_TRUE(gate.note_shed(8s, t + 1s));
  EXPECT_TRUE(gate.note_shed(3s, t + 2500ms));
  config.shed_wait_s = 0.0;
  BusyGate never(config);
  EXPECT_FALSE(never.note_shed(60s, t)) << "0: never";
  config.shed_wait_s = -1.0;
  try {
    BusyGate bad(config);
    FAIL() << "a negative shed bound was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("core.busy_shed_wait_s = -1"), std::string::npos) << e.what();
  }
}

TEST(BusyGate, WorkersAskingAtOnceReleaseOne) {
  BusyGateConfig config = gate_config(0.2, 5.0);
  config.shed_wait_s = 1.0;
  BusyGate gate(config);
  const auto t = Clock::now();
  std::atomic<int> releases{0};
  std::vector<std::thread> workers;
  for (int k = 0; k < 8; ++k) workers.emplace_back([&] { releases += gate.note_shed(5s, t) ? 1 : 0; });
  for (auto& w : workers) w.join();
  EXPECT_EQ(releases.load(), 1);
}

// Those served are too many (BusyGate::note_shed): the one admitted last goes, and is a new id
// again, refused while the daemon is busy and admitted afresh once it is not; the first stay.
TEST(ResponderRoster, ReleasingTakesTheResponderAdmittedLastAndItIsNewAgain) {
  ResponderRosterConfig config{true, {}, 256, 60.0};
  config.new_per_s = 0.0;
  ResponderRoster roster(config);
  const auto t = Clock::now();
  EXPECT_FALSE(roster.release_newest()) << "no one served: no one to release";
  for (const char* id : {"r1", "r2", "r3"}) ASSERT_EQ(roster.admit(id, t), ResponderRoster::Admission::kNew);
  EXPECT_EQ(roster.admit("r3", t + 5s), ResponderRoster::Admission::kServed);
  EXPECT_EQ(roster.admit("r1", t + 6s), ResponderRoster::Admission::kServed) << "heard last is not admitted last";
  // The lagging worker's own: of those it accepts, the one admitted last.
  EXPECT_EQ(roster.release_newest([](const std::string& id) { return id != "r3"; }), std::optional<std::string>("r2"));
  EXPECT_FALSE(roster.release_newest([](const std::string& id) { return id == "r9"; }));
  EXPECT_EQ(roster.release_newest(), std::optional<std::string>("r3"));
  EXPECT_EQ(roster.served(), 1U);
  EXPECT_EQ(roster.admit("r3", t + 7s, true), ResponderRoster::Admission::kBusy) << "released: new again";
  EXPECT_EQ(roster.admit("r1", t + 7s, true), ResponderRoster::Admission::kServed) << "the first is served on";
  EXPECT_EQ(roster.admit("r3", t + 20s), ResponderRoster::Admission::kNew) << "admitted afresh once not busy";
  EXPECT_EQ(roster.release_newest(), std::optional<std::string>("r3"));
  EXPECT_TRUE(roster.evict_idle(t + 100s) == std::vector<std::string>{"r1"}) << "idle eviction still sees the rest";
}

TEST(ResponderRoster, AFirefightersFirstStepFromAReportedEntryIsAdmittedHoweverBusy) {
  ResponderRosterConfig config{true, {}, 3, 60.0};
  config.new_per_s = 1.0;
  config.door_starts = {"ff1", "ff2", "ff3", "ff4"};
  ResponderRoster roster(config);
  const auto t = Clock::now();
  EXPECT_EQ(roster.admit("r1", t), ResponderRoster::Admission::kNew) << "the pace's one token";
  EXPECT_EQ(roster.admit("ff1", t, true), ResponderRoster::Admission::kBusy) << "not its first step: no door start";
  EXPECT_EQ(roster.admit("r2", t, false, true), ResponderRoster::Admission::kPaced) << "no entry reported: paced";
  EXPECT_EQ(roster.admit("ff1", t, true, true), ResponderRoster::Admission::kNew) << "busy, but at the door";
  EXPECT_EQ(roster.admit("ff2", t, false, true), ResponderRoster::Admission::kNew) << "beyond the pace, at the door";
  EXPECT_EQ(roster.admit("ff3", t, true, true), ResponderRoster::Admission::kFull) << "max_responders still holds";
  EXPECT_EQ(roster.release_newest(), std::optional<std::string>("r1")) << "door starts are released last";
  EXPECT_EQ(roster.release_newest(), std::optional<std::string>("ff1")) << "then the door starts";
  EXPECT_EQ(roster.admit("ff1", t + 1s, true), ResponderRoster::Admission::kBusy) << "released mid-search: new again";
  EXPECT_EQ(roster.admit("ff1", t + 1s, true, true), ResponderRoster::Admission::kBusy)
      << "a second first step (a device restarted mid-search, or forged) is no door start";
  EXPECT_EQ(roster.admit("ff2", t + 1s, true), ResponderRoster::Admission::kServed);

  ResponderRosterConfig listed{false, {"ff1"}, 256, 60.0};
  listed.door_starts = {"ff1", "ff9"};
  ResponderRoster sector(listed);
  EXPECT_EQ(sector.admit("ff9", t, true, true), ResponderRoster::Admission::kNotListed) << "another sector's";
  EXPECT_EQ(sector.admit("ff1", t, true, true), ResponderRoster::Admission::kNew);
}

}  // namespace
}  // namespace sarloc::estimator
