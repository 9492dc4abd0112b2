// The operator's buttons, clicked in headless Chromium (tests/js/dashboard_actions.mjs): "dig
// first" in the dig order, "dug out" in the victims table and a deposit drawn on the map reach
// the server with the session the page opened from the token, and the server publishes them as
// the operator's; the drawn corners are where they were clicked, in the incident frame. The server's
// own checks of these requests are dashboard_server_test.cpp's; here, that the page sends them.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <mutex>
#include <nlohmann/json.hpp>

#include "dashboard_server.hpp"
#include "support/required_program.hpp"
#include "support/sample_messages.hpp"

namespace sarloc::dashboard {
namespace {

TEST(DashboardActions, TheOperatorsDigFirstDugOutDrawnAndEditedDepositWorkInABrowser) {
  ASSERT_TRUE(test::has_node());
  ASSERT_TRUE(test::has_chromium());
  TimestampNs mission = 1763731300000000000LL;
  PictureState state{PictureStateConfig{}, [&] { return mission; }, 0};
  DashboardServerConfig config;
  config.port = 0;
  config.token = "correct-horse-battery";
  config.view_token = "look-but-do-not-touch";
  config.push_period_s = 0.05;
  DashboardServer server(config, state, [](std::uint32_t, const std::string&) { return true; });
  std::mutex mutex;  // the server's threads call these
  std::vector<std::pair<std::uint32_t, std::string>> dug_out;
  std::vector<std::pair<std::vector<std::uint32_t>, std::string>> dig_orders;
  server.set_dug_out_action([&](std::uint32_t id, const std::string& op) {
    std::lock_guard<std::mutex> lock(mutex);
    dug_out.push_back({id, op});
    return true;
  });
  std::vector<std::vector<Eigen::Vector2d>> deposits;
  server.set_deposit_action([&](const std::vector<Eigen::Vector2d>& outline, const std::string&) {
    std::lock_guard<std::mutex> lock(mutex);
    deposits.push_back(outline);
    return true;
  });
  server.set_dig_order_action([&](const std::vector<std::uint32_t>& ids, const std::string& op) {
    std::lock_guard<std::mutex> lock(mutex);
    dig_orders.push_back({ids, op});
    return true;
  });
  // Victims 7 and 9 FOUND; the plan digs 7, then 9.
  for (const std::uint32_t id : {7u, 9u}) {
    auto victim = test::sample_fused_victim();
    victim.victim_id = id;
    victim.evidence_conflict = false;
    victim.possibly_same_as = 0;
    if (id == 9) victim.position.position.x() += 40.0;  // apart on the map
    state.on_victim(victim);
  }
  state.on_search_plan(test::sample_search_plan());
  server.start();
  const std::string url = "http://127.0.0.1:" + std::to_string(server.port()) + "/#token=" + config.token;
  const std::string out = ::testing::TempDir() + "/dashboard_actions.json";
  const int status = std::system(
      ("node " SARLOC_SOURCE_DIR "/tests/js/dashboard_actions.mjs '" + url + "' 9 7 > " + out + " 2>&1").c_str());
  std::ifstream in(out);
  const std::string said((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(WEXITSTATUS(status), 0) << said;
  const auto report = nlohmann::json::parse(said.substr(said.rfind("{\"errors\"")));
  EXPECT_TRUE(report["errors"].empty()) << said;
  EXPECT_EQ(report["statuses"]["/api/victims/9/dig-first"], 202) << said;
  EXPECT_EQ(report["statuses"]["/api/victims/7/dug-out"], 202) << said;
  EXPECT_EQ(report["sentTo"], "sent: r1") << said;
  EXPECT_EQ(report["unplacedPursuits"], "Signals not yet placed: r3 pursues one also heard by r1") << said;
  std::lock_guard<std::mutex> lock(mutex);
  ASSERT_EQ(dig_orders.size(), 1u);
  EXPECT_EQ(dig_orders[0].first, (std::vector<std::uint32_t>{9, 7})) << "victim 9 first, then the rest as shown";
  EXPECT_EQ(dig_orders[0].second, "dashboard");
  ASSERT_EQ(dug_out.size(), 1u);
  EXPECT_EQ(dug_out[0], std::make_pair(7u, std::string("dashboard")));

  // Four corners clicked 60 px around victim 7, top left first, clockwise on screen; the drags
  // between them added none.
  EXPECT_EQ(report["drawnCorners"], 4) << said;
  // Nothing moved the map under the clicks (seen: the no-data banner appearing pushed it 38 px
  // down mid-drawing on a loaded machine, and the last two corners landed 2.5 m off).
  EXPECT_EQ(report["mapTopBefore"], report["mapTopAfter"]) << said;
  EXPECT_EQ(report["mapTopWithBanner"][0], report["mapTopWithBanner"][1]) << "the banner moves the map; " << said;
  EXPECT_EQ(report["statuses"]["/api/deposit"], 202) << said;
  ASSERT_EQ(deposits.size(), 2u) << "drawn, then edited; " << said;
  const auto& corners = deposits[0];
  ASSERT_EQ(corners.size(), 4u);
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (const auto& c : corners) centre += c / 4.0;
  const Eigen::Vector2d victim = test::sample_fused_victim().position.position.head<2>();
  EXPECT_LT((centre - victim).norm(), 1.0)
      << "centre " << centre.transpose() << ", victim " << victim.transpose() << "; " << said;
  EXPECT_LT(corners[0].x(), corners[1].x()) << "left to right is east";
  EXPECT_GT(corners[1].y(), corners[2].y()) << "down the screen is south";
  EXPECT_NEAR(corners[0].y(), corners[1].y(), 0.2) << "a square on screen is one in the incident frame";
  EXPECT_NEAR(corners[1].x(), corners[2].x(), 0.2);
  EXPECT_NEAR(corners[1].x() - corners[0].x(), corners[1].y() - corners[2].y(), 0.2);

  // Edited: the plan's deposit (sample_search_plan) with its first corner dragged 40 px east; the
  // other corners where they were (to the 0.1 m sent), none added, the map not panned.
  EXPECT_EQ(report["editCorners"], 4) << said;
  EXPECT_EQ(report["editedCorners"], 4) << said;
  EXPECT_EQ(report["viewBoxBeforeEdit"], report["viewBoxAfterEdit"]) << said;
  const auto& edited = deposits[1];
  ASSERT_EQ(edited.size(), 4u);
  EXPECT_GT(edited[0].x(), 2.0) << "moved east; " << said;
  EXPECT_NEAR(edited[0].y(), 0.0, 0.5) << "a horizontal drag";
  EXPECT_LT((edited[1] - Eigen::Vector2d(80, 0)).norm(), 0.11);
  EXPECT_LT((edited[2] - Eigen::Vector2d(80, 100)).norm(), 0.11);
  EXPECT_LT((edited[3] - Eigen::Vector2d(0, 100)).norm(), 0.11);
}

}  // namespace
}  // namespace sarloc::dashboard
