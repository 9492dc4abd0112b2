// An operator's deposit over DDS: the dashboard node publishes the outline drawn on its map and
// incident command, which had no deposit, plans the search over it. A crossing outline and
// another incident's outline are refused or ignored (no plan); a second outline replaces the first.
#include <gtest/gtest.h>

#include <algorithm>
#include <mutex>
#include <optional>
#include <thread>

#include "sarloc/dds/command_node.hpp"
#include "sarloc/dds/dashboard_node.hpp"
#include "support/dds_test_domains.hpp"
#include "support/dds_test_helpers.hpp"

namespace sarloc::dds {
namespace {

using namespace std::chrono_literals;
using test::eventually;

// The same polygon, whatever its first vertex and orientation (the plan's is counter-clockwise).
bool same_polygon(std::vector<Eigen::Vector2d> a, std::vector<Eigen::Vector2d> b) {
  if (a.size() != b.size() || a.empty()) return false;
  for (int pass = 0; pass < 2; ++pass, std::reverse(b.begin(), b.end()))
    for (std::size_t shift = 0; shift < a.size(); ++shift) {
      bool all = true;
      for (std::size_t i = 0; i < a.size() && all; ++i) all = (a[i] - b[(i + shift) % b.size()]).norm() < 1e-9;
      if (all) return true;
    }
  return false;
}

TEST(CommandDeposit, AnOperatorsDrawnDepositIsPlannedOverAndACrossingOneIsNot) {
  const MissionClock clock;
  CommandNodeConfig config;
  config.node_id = "command-deposit";
  config.incident.incident_id = "deposit-test";
  config.cycle_s = 0.1;
  auto p = test::make_participant(test::kDomainCommandDeposit, "command");
  CommandNode command(p, config, clock);

  std::mutex mutex;
  std::optional<incident::SearchPlanPicture> plan;
  bool heard = false;
  DashboardSink sink;
  sink.on_search_plan = [&](const incident::SearchPlanPicture& picture) {
    std::lock_guard<std::mutex> lock(mutex);
    plan = picture;
  };
  sink.on_picture_writer = [&](const std::string&) {
    std::lock_guard<std::mutex> lock(mutex);
    heard = true;
  };
  DashboardNode dashboard(test::make_participant(test::kDomainCommandDeposit, "dashboard"), std::move(sink));
  ASSERT_TRUE(eventually(
      [&] {
        std::lock_guard<std::mutex> lock(mutex);
        return heard;
      },
      10s));
  std::this_thread::sleep_for(500ms);  // the command's readers matched the dashboard's writers
  auto current = [&] {
    std::lock_guard<std::mutex> lock(mutex);
    return plan;
  };

  const std::vector<Eigen::Vector2d> bow_tie{{0, 0}, {60, 50}, {60, 0}, {0, 50}};
  ASSERT_TRUE(dashboard.draw_deposit("deposit-test", bow_tie, "ic-chief", clock.now()));
  const std::vector<Eigen::Vector2d> square{{0, 0}, {60, 0}, {60, 50}, {0, 50}};
  ASSERT_TRUE(dashboard.draw_deposit("another-incident", square, "ic-chief", clock.now()));
  std::this_thread::sleep_for(1500ms);
  EXPECT_FALSE(current()) << "a crossing outline, and another incident's, plan nothing";

  ASSERT_TRUE(dashboard.draw_deposit("deposit-test", square, "ic-chief", clock.now()));
  ASSERT_TRUE(eventually(
      [&] {
        const auto got = current();
        return got && same_polygon(got->deposit, square);
      },
      5s));
  EXPECT_EQ(current()->incident_id, "deposit-test");

  const std::vector<Eigen::Vector2d> larger{{0, 0}, {120, 0}, {120, 50}, {0, 50}};
  ASSERT_TRUE(dashboard.draw_deposit("deposit-test", larger, "ic-chief", clock.now()));
  ASSERT_TRUE(eventually(
      [&] {
        const auto got = current();
        return got && same_polygon(got->deposit, larger);
      },
      5s))
      << "a second outline replaces the first";
  EXPECT_FALSE(dashboard.draw_deposit("deposit-test", std::vector<Eigen::Vector2d>(300, Eigen::Vector2d::Zero()),
                                      "ic-chief", clock.now()))
      << "more points than the topic holds are not sent";
  std::this_thread::sleep_for(300ms);
  EXPECT_TRUE(same_polygon(current()->deposit, larger));
}

}  // namespace
}  // namespace sarloc::dds
