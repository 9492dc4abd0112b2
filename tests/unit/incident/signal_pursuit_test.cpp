// One rescuer per victim (signal_pursuit.hpp): of the rescuers who hear a victim, the nearest is
// sent and the others' signals of it are handed over; the pursuer stays while it searches and
// hears it; a lost pursuer's victim goes to the next; one not found in time is given back to
// all; found, conflicting or ambiguous victims, and victims heard by one, hand nothing over.
#include "sarloc/core/incident/signal_pursuit.hpp"

#include <gtest/gtest.h>

namespace sarloc::incident {
namespace {

constexpr TimestampNs kSecond = 1'000'000'000;

FusedVictim victim(std::uint32_t id, const Vec2& at, std::vector<std::pair<std::string, std::uint32_t>> sources) {
  FusedVictim v;
  v.victim_id = id;
  v.position.position = Vec3(at.x(), at.y(), -1.0);
  v.position.covariance = Mat3::Identity();
  for (const auto& [rescuer, signal] : sources) v.sources.push_back({rescuer, signal});
  return v;
}

TEST(SignalPursuits, TheNearestIsSentAndTheOthersSignalsAreHandedOver) {
  SignalPursuits pursuits(240.0);
  const std::vector<FusedVictim> victims{victim(1, {0, 0}, {{"r1", 2}, {"r2", 4}, {"r3", 1}})};
  std::map<std::string, Vec2> searching{{"r1", {30, 0}}, {"r2", {10, 5}}, {"r3", {-40, 0}}};
  auto handed = pursuits.update(victims, searching, 0);
  EXPECT_EQ(pursuits.pursuer_of(1), "r2");
  ASSERT_EQ(handed.size(), 2u);
  EXPECT_EQ(signals_left_to_others(handed, "r1"), std::set<std::uint32_t>{2});
  EXPECT_EQ(signals_left_to_others(handed, "r3"), std::set<std::uint32_t>{1});
  EXPECT_TRUE(signals_left_to_others(handed, "r2").empty()) << "the pursuer keeps its signal";
  for (const auto& h : handed) EXPECT_EQ(h.pursued_by, "r2");
  ASSERT_EQ(pursuits.events().size(), 1u);
  EXPECT_FALSE(pursuits.events()[0].warning);

  // r1 walks nearer than r2: r2 stays the pursuer (no flapping), and nothing new is said.
  searching["r1"] = {1, 0};
  handed = pursuits.update(victims, searching, 10 * kSecond);
  EXPECT_EQ(pursuits.pursuer_of(1), "r2");
  EXPECT_TRUE(pursuits.events().empty());

  // r2's link is lost (no longer searching): the nearest of the others takes over.
  searching.erase("r2");
  handed = pursuits.update(victims, searching, 20 * kSecond);
  EXPECT_EQ(pursuits.pursuer_of(1), "r1");
  EXPECT_EQ(signals_left_to_others(handed, "r3"), std::set<std::uint32_t>{1});
  EXPECT_EQ(signals_left_to_others(handed, "r2"), std::set<std::uint32_t>{4}) << "r2, if it comes back, leaves it";
}

// Victims close together go one to each rescuer: r1 stands nearest to both, but once it pursues
// victim 1, victim 2 goes to r2.
TEST(SignalPursuits, ARescuerPursuingOneVictimIsNotSentToAnother) {
  SignalPursuits pursuits(240.0);
  const std::map<std::string, Vec2> searching{{"r1", {0, 0}}, {"r2", {10, 0}}};
  const std::vector<FusedVictim> victims{victim(1, {1, 0}, {{"r1", 1}, {"r2", 1}}),
                                         victim(2, {2, 0}, {{"r1", 2}, {"r2", 2}})};
  const auto handed = pursuits.update(victims, searching, 0);
  EXPECT_EQ(pursuits.pursuer_of(1), "r1");
  EXPECT_EQ(pursuits.pursuer_of(2), "r2");
  EXPECT_EQ(signals_left_to_others(handed, "r1"), std::set<std::uint32_t>{2});
  EXPECT_EQ(signals_left_to_others(handed, "r2"), std::set<std::uint32_t>{1});
  // A third victim with both busy: the nearest after all.
  auto three = victims;
  three.push_back(victim(3, {9, 0}, {{"r1", 3}, {"r2", 3}}));
  pursuits.update(three, searching, kSecond);
  EXPECT_EQ(pursuits.pursuer_of(3), "r2");
  EXPECT_EQ(pursuits.pursuer_of(1), "r1") << "pursuits under way stay";
}

TEST(SignalPursuits, APursuerWhoDoesNotFindItInTimeGivesItBackToAll) {
  SignalPursuits pursuits(60.0);
  const std::vector<FusedVictim> victims{victim(5, {0, 0}, {{"r1", 1}, {"r2", 1}})};
  const std::map<std::string, Vec2> searching{{"r1", {5, 0}}, {"r2", {20, 0}}};
  EXPECT_EQ(pursuits.update(victims, searching, 0).size(), 1u);
  EXPECT_EQ(pursuits.update(victims, searching, 60 * kSecond).size(), 1u) << "not yet";
  EXPECT_TRUE(pursuits.update(victims, searching, 61 * kSecond).empty());
  ASSERT_EQ(pursuits.events().size(), 1u);
  EXPECT_TRUE(pursuits.events()[0].warning);
  EXPECT_TRUE(pursuits.update(victims, searching, 200 * kSecond).empty()) << "given up for good";
  EXPECT_FALSE(pursuits.pursuer_of(5).has_value());
}

TEST(SignalPursuits, FoundConflictingAmbiguousOrSingleHeardVictimsHandNothingOver) {
  SignalPursuits pursuits(240.0);
  const std::map<std::string, Vec2> searching{{"r1", {5, 0}}, {"r2", {20, 0}}};
  auto found = victim(1, {0, 0}, {{"r1", 1}, {"r2", 1}});
  found.state = VictimState::kFound;
  auto conflict = victim(2, {50, 0}, {{"r1", 2}, {"r2", 2}});
  conflict.evidence_conflict = true;
  auto maybe = victim(3, {0, 50}, {{"r1", 3}, {"r2", 3}});
  const auto named = victim(4, {0, 55}, {{"r1", 4}, {"r2", 4}});  // victim 3 is possibly this one
  maybe.possibly_same_as = 4;
  const auto alone = victim(5, {90, 0}, {{"r1", 5}, {"r3", 1}});  // r3 is not searching
  auto nan = victim(6, {0, 0}, {{"r1", 6}, {"r2", 6}});
  nan.position.position.x() = std::nan("");
  EXPECT_TRUE(pursuits.update({found, conflict, maybe, named, alone, nan}, searching, 0).empty());
}

}  // namespace
}  // namespace sarloc::incident
