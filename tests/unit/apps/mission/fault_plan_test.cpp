// sarloc-mission's fault plan: parsing, when each fault is due, what it waits to see, on a
// fake steady clock.
#include <gtest/gtest.h>

#include "fault_plan.hpp"
#include "sarloc/core/common/errors.hpp"

namespace sarloc::app {
namespace {

using namespace std::chrono_literals;
using incident::LinkState;
const Fault::TimePoint kT0{std::chrono::seconds(1000)};  // the fake clock

std::string message_of(const std::string& text, bool restart) {
  try {
    parse_fault(text, restart);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(FaultPlan, ParsingNamesTheOptionAndTheProblem) {
  const Fault f = parse_fault("r2@12.5", false);
  EXPECT_EQ(f.target, "r2");
  EXPECT_DOUBLE_EQ(f.at_s, 12.5);
  EXPECT_TRUE(f.is_device_kill());
  EXPECT_EQ(message_of("core", false), "--kill = 'core': expected TARGET@SECONDS");
  EXPECT_EQ(message_of("@3", false), "--kill = '@3': expected TARGET@SECONDS");
  EXPECT_EQ(message_of("core@soon", false), "--kill = 'core@soon': 'soon' is not a number of seconds");
  EXPECT_EQ(message_of("core@-1", false), "--kill = 'core@-1': time must be >= 0");
  EXPECT_EQ(message_of("r1@5", true), "--restart = 'r1@5': only core or command can be restarted");
  EXPECT_FALSE(parse_fault("command@5", true).is_command_kill());
  EXPECT_TRUE(parse_fault("command@5", false).is_command_kill());
}

TEST(FaultPlan, FaultsComeDueOnceInTheOrderGiven) {
  auto plan = FaultPlan::parse({"core@40", "r2@10"}, {"core@55"});
  EXPECT_TRUE(plan.due(9.9, kT0).empty());
  auto due = plan.due(10.0, kT0);
  ASSERT_EQ(due.size(), 1U);
  EXPECT_EQ(due[0]->target, "r2");
  EXPECT_TRUE(plan.due(10.5, kT0 + 1s).empty()) << "done once";
  due = plan.due(60.0, kT0 + 50s);  // a slow loop: both late ones at once, in order
  ASSERT_EQ(due.size(), 2U);
  EXPECT_EQ(due[0]->target, "core");
  EXPECT_FALSE(due[0]->restart);
  EXPECT_TRUE(due[1]->restart);
  EXPECT_EQ(due[1]->when, kT0 + 50s);
  EXPECT_TRUE(plan.killed("r2"));
  EXPECT_FALSE(plan.killed("core"));
}

// A command restart starts again the instance the latest command kill stopped.
TEST(FaultPlan, ACommandRestartNamesTheInstanceKilledLast) {
  auto plan = FaultPlan::parse({"command@10", "command@20"}, {"command@30"});
  plan.due(10, kT0)[0]->instance = 1;  // the mission killed the active one: instance 1
  plan.due(20, kT0 + 10s)[0]->instance = 2;
  const auto restart = plan.due(30, kT0 + 20s);
  ASSERT_EQ(restart.size(), 1U);
  EXPECT_EQ(restart[0]->instance, 2U);

  auto nothing_killed = FaultPlan::parse({}, {"command@5"});
  EXPECT_EQ(nothing_killed.due(5, kT0)[0]->instance, 0U);
}

// A killed device waits (at most 30 s) for incident command to report its link lost.
TEST(FaultPlan, AKilledDeviceIsTimedUntilItsLinkIsReportedLost) {
  auto plan = FaultPlan::parse({"r2@10"}, {});
  EXPECT_FALSE(plan.awaiting_observation(kT0, 2)) << "nothing done yet";
  plan.due(10, kT0);
  EXPECT_TRUE(plan.awaiting_observation(kT0 + 1s, 2));
  plan.observe_links({{"r2", LinkState::kStale}, {"r1", LinkState::kLost}}, kT0 + 2s);
  EXPECT_LT(plan.faults()[0].link_lost_after_s, 0.0) << "stale is not lost; r1 was not killed";
  plan.observe_links({{"r2", LinkState::kLost}}, kT0 + 3500ms);
  EXPECT_DOUBLE_EQ(plan.faults()[0].link_lost_after_s, 3.5);
  plan.observe_links({{"r2", LinkState::kLost}}, kT0 + 9s);
  EXPECT_DOUBLE_EQ(plan.faults()[0].link_lost_after_s, 3.5) << "timed once";
  EXPECT_FALSE(plan.awaiting_observation(kT0 + 4s, 2));

  auto never = FaultPlan::parse({"r3@0"}, {});
  never.due(0, kT0);
  EXPECT_TRUE(never.awaiting_observation(kT0 + 29s, 1));
  EXPECT_FALSE(never.awaiting_observation(kT0 + 30s, 1)) << "the mission does not wait forever";
}

// A killed incident command is handed over once another participant publishes after the kill.
TEST(FaultPlan, ACommandKillIsHandedOverToAnotherPublisher) {
  auto plan = FaultPlan::parse({"command@10"}, {});
  Fault* kill = plan.due(10, kT0)[0];
  kill->killed_participant = "aaaa";
  EXPECT_TRUE(plan.awaiting_observation(kT0 + 1s, 2));
  EXPECT_FALSE(plan.awaiting_observation(kT0 + 1s, 1)) << "alone, nobody takes over";
  plan.observe_publisher("aaaa", kT0 - 5s, "sarloc-command-1");  // still the killed one's last samples
  plan.observe_publisher("bbbb", kT0 - 1s, "sarloc-command-2");  // publishing since before the kill
  EXPECT_LT(plan.faults()[0].handover_after_s, 0.0);
  plan.observe_publisher("bbbb", kT0 + 4200ms, "sarloc-command-2");
  EXPECT_DOUBLE_EQ(plan.faults()[0].handover_after_s, 4.2);
  EXPECT_EQ(plan.faults()[0].taken_over_by, "sarloc-command-2");
  EXPECT_FALSE(plan.awaiting_observation(kT0 + 5s, 2));

  const auto outcomes = plan.outcomes(mission::MissionScenario{}, 0);
  ASSERT_EQ(outcomes.size(), 1U);
  EXPECT_EQ(outcomes[0].action, "kill");
  EXPECT_EQ(outcomes[0].target, "command");
  EXPECT_TRUE(outcomes[0].done);
  ASSERT_TRUE(outcomes[0].handover_after_s);
  EXPECT_DOUBLE_EQ(*outcomes[0].handover_after_s, 4.2);
  EXPECT_FALSE(outcomes[0].link_lost_after_s);
}

}  // namespace
}  // namespace sarloc::app
