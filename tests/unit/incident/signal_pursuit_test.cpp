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

// Before anyone has placed it (signal_groups.hpp): the first of those who hear a transmitter to
// take it pursues it, the others' signals of it are handed over (victim id 0); once placed, the
// victim stays with him if he is among those who placed it; a pursuer busy with another goes to the next; not placed in
// time, it is given back to all; a standby adopts it.
responder::TransmitterSignature signature(double carrier_hz, double period_s) {
  return {carrier_hz, 0.3, period_s, 0.002};
}

HeardSignal heard(const std::string& rescuer, std::uint32_t signal, double first_heard_s, bool placed = false) {
  return {rescuer, signal, signature(12.0, 0.850), placed, static_cast<TimestampNs>(first_heard_s * 1e9)};
}

TEST(SignalPursuits, BeforeAnyonePlacesItTheFirstToTakeASignalPursuesItAndKeepsItsVictim) {
  SignalPursuits pursuits(240.0);
  std::map<std::string, Vec2> searching{{"r1", {0, 0}}, {"r2", {10, 0}}, {"r3", {20, 0}}};
  std::vector<HeardSignal> signals{heard("r1", 2, 9.0), heard("r2", 5, 4.0), heard("r3", 1, 6.0)};
  auto handed = pursuits.update({}, searching, 10 * kSecond, group_heard_signals(signals, {}, 0.999));
  ASSERT_EQ(handed.size(), 2u);
  EXPECT_EQ(signals_left_to_others(handed, "r1"), std::set<std::uint32_t>{2});
  EXPECT_EQ(signals_left_to_others(handed, "r3"), std::set<std::uint32_t>{1});
  for (const auto& h : handed) {
    EXPECT_EQ(h.pursued_by, "r2") << "the first to take it";
    EXPECT_EQ(h.victim_id, 0u) << "not yet placed";
  }
  EXPECT_EQ(pursuits.pursuer_of_signal({"r3", 1}), "r2");
  ASSERT_EQ(pursuits.events().size(), 1u);
  EXPECT_NE(pursuits.events()[0].text.find("signal r2/5 (carrier +12.0 Hz, period 0.850 s; not yet placed): pursued "
                                           "by r2 (of 3 who hear it"),
            std::string::npos)
      << pursuits.events()[0].text;

  // The same next cycle: nothing new said.
  handed = pursuits.update({}, searching, 11 * kSecond, group_heard_signals(signals, {}, 0.999));
  EXPECT_EQ(handed.size(), 2u);
  EXPECT_TRUE(pursuits.events().empty());

  // r2 places it first: the victim stays with r2; r1's and r3's signals, not converged yet,
  // join it and stay handed over.
  signals[1].placed = true;
  std::vector<FusedVictim> victims{victim(4, {10, 1}, {{"r2", 5}})};
  handed = pursuits.update(victims, searching, 12 * kSecond, group_heard_signals(signals, victims, 0.999));
  EXPECT_EQ(pursuits.pursuer_of(4), "r2");
  EXPECT_EQ(signals_left_to_others(handed, "r1"), std::set<std::uint32_t>{2});
  EXPECT_EQ(signals_left_to_others(handed, "r3"), std::set<std::uint32_t>{1});
  for (const auto& h : handed) EXPECT_EQ(h.victim_id, 4u);
  EXPECT_FALSE(pursuits.pursuer_of_signal({"r3", 1}));
  signals[1].placed = false;

  // A standby that adopts a cycle before the victim keeps r2 on it.
  SignalPursuits standby(240.0);
  standby.adopt(pursuits.update({}, searching, 13 * kSecond, group_heard_signals(signals, {}, 0.999)), 13 * kSecond);
  EXPECT_EQ(standby.pursuer_of_signal({"r1", 2}), "r2");
  EXPECT_FALSE(standby.pursuer_of(0)) << "no victim 0";
}

// With every free hearer's distance reading (a transceiver's display), the nearest by it is
// sent, not the first to take it; one without a reading leaves it to the first.
TEST(SignalPursuits, BeforeAnyonePlacesItTheNearestByHisDistanceReadingIsSent) {
  SignalPursuits pursuits(240.0);
  const std::map<std::string, Vec2> searching{{"r1", {0, 0}}, {"r2", {10, 0}}, {"r3", {20, 0}}};
  std::vector<HeardSignal> signals{heard("r1", 2, 9.0), heard("r2", 5, 4.0), heard("r3", 1, 6.0)};
  signals[0].range_m = 48.0;
  signals[1].range_m = 55.0;
  signals[2].range_m = 31.0;
  pursuits.update({}, searching, 10 * kSecond, group_heard_signals(signals, {}, 0.999));
  EXPECT_EQ(pursuits.pursuer_of_signal({"r1", 2}), "r3") << "r3 reads 31 m";
  ASSERT_EQ(pursuits.events().size(), 1u);
  EXPECT_NE(pursuits.events()[0].text.find("pursued by r3 (of 3 who hear it, the nearest by his distance reading"),
            std::string::npos)
      << pursuits.events()[0].text;
  SignalPursuits unread(240.0);
  signals[0].range_m = std::nan("");
  unread.update({}, searching, 10 * kSecond, group_heard_signals(signals, {}, 0.999));
  EXPECT_EQ(unread.pursuer_of_signal({"r1", 2}), "r2") << "r1 reads none: the first to take it";
}

TEST(SignalPursuits, BeforeAnyonePlacesItOnlyAFreeRescuerIsSentAndOneWhoHearsItAloneHandsNothingOver) {
  SignalPursuits pursuits(240.0);
  std::map<std::string, Vec2> searching{{"r1", {0, 0}}, {"r2", {10, 0}}};
  const std::vector<FusedVictim> victims{victim(1, {1, 0}, {{"r1", 1}, {"r2", 1}})};  // r1 is nearest
  std::vector<HeardSignal> signals{heard("r1", 1, 0.0, true), heard("r2", 1, 0.0, true), heard("r1", 2, 3.0),
                                   heard("r2", 2, 5.0)};
  signals[0].transmitter = signals[1].transmitter = signature(-50.0, 1.2);
  auto handed = pursuits.update(victims, searching, kSecond, group_heard_signals(signals, victims, 0.999));
  EXPECT_EQ(pursuits.pursuer_of(1), "r1");
  EXPECT_EQ(pursuits.pursuer_of_signal({"r1", 2}), "r2") << "r1 took it first but pursues victim 1";
  EXPECT_EQ(signals_left_to_others(handed, "r1"), std::set<std::uint32_t>{2});
  // A third transmitter both hear: both pursue another, so nobody is sent away from it.
  signals.push_back(heard("r1", 3, 6.0));
  signals.push_back(heard("r2", 3, 7.0));
  signals[4].transmitter = signals[5].transmitter = signature(40.0, 0.75);
  handed = pursuits.update(victims, searching, 2 * kSecond, group_heard_signals(signals, victims, 0.999));
  EXPECT_FALSE(pursuits.pursuer_of_signal({"r1", 3}));
  EXPECT_TRUE(signals_left_to_others(handed, "r1").count(3) == 0 && signals_left_to_others(handed, "r2").count(3) == 0);
  // Nor is a rescuer pursuing a transmitter not yet placed sent to a new victim: r2 pursues the
  // second, so victim 9, nearest to r2, goes to r3.
  searching["r3"] = {30, 0};
  auto more = victims;
  more.push_back(victim(9, {10, 0}, {{"r2", 9}, {"r3", 9}}));
  pursuits.update(more, searching, 3 * kSecond, group_heard_signals(signals, more, 0.999));
  EXPECT_EQ(pursuits.pursuer_of(9), "r3");
  EXPECT_EQ(pursuits.pursuer_of_signal({"r1", 2}), "r2");
  // r2 and r3 sign off: a group heard by one searching rescuer hands nothing over.
  searching.erase("r2");
  searching.erase("r3");
  handed = pursuits.update(more, searching, 4 * kSecond, group_heard_signals(signals, more, 0.999));
  EXPECT_TRUE(handed.empty());
}

// r1 and r2, 10 m apart, both hear one transmitter that neither has placed (r1 first).
struct OneTransmitterTwoHearers {
  std::map<std::string, Vec2> searching{{"r1", {0, 0}}, {"r2", {10, 0}}};
  std::vector<HeardSignal> signals{heard("r1", 1, 0.0), heard("r2", 1, 1.0)};
  SignalGroups groups = group_heard_signals(signals, {}, 0.999);
};

TEST(SignalPursuits, ATransmitterNotPlacedInTimeIsGivenBackToAll) {
  SignalPursuits pursuits(60.0);
  const OneTransmitterTwoHearers heard_by_two;
  const auto& [searching, signals, groups] = heard_by_two;
  EXPECT_EQ(pursuits.update({}, searching, 0, groups).size(), 1u);
  EXPECT_EQ(pursuits.update({}, searching, 60 * kSecond, groups).size(), 1u) << "not yet";
  EXPECT_TRUE(pursuits.update({}, searching, 61 * kSecond, groups).empty());
  ASSERT_EQ(pursuits.events().size(), 1u);
  EXPECT_TRUE(pursuits.events()[0].warning);
  EXPECT_TRUE(pursuits.update({}, searching, 100 * kSecond, groups).empty()) << "given up for good";
  // Placed since: still given back to everyone.
  const std::vector<FusedVictim> victims{victim(3, {5, 0}, {{"r1", 1}})};
  auto placed = signals;
  placed[0].placed = true;
  EXPECT_TRUE(pursuits.update(victims, searching, 110 * kSecond, group_heard_signals(placed, victims, 0.999)).empty());

  // With the shipped 240 s pursuit timeout, placing it has kUnplacedPursuitPlaceNs (90 s).
  SignalPursuits shipped(240.0);
  EXPECT_EQ(shipped.update({}, searching, 0, groups).size(), 1u);
  EXPECT_EQ(shipped.update({}, searching, 90 * kSecond, groups).size(), 1u) << "not yet";
  EXPECT_TRUE(shipped.update({}, searching, 91 * kSecond, groups).empty());
  ASSERT_EQ(shipped.events().size(), 1u);
  EXPECT_NE(shipped.events()[0].text.find("not placed by r1 within 90 s"), std::string::npos)
      << shipped.events()[0].text;
}

// Incident command runs for hours: what was given back to everyone is remembered while it is in
// the picture, and forgotten a pursuit timeout after it left it (pursued afresh if it returns).
TEST(SignalPursuits, WhatWasGivenUpIsForgottenAPursuitTimeoutAfterItLeftThePicture) {
  SignalPursuits pursuits(60.0);
  const OneTransmitterTwoHearers heard_by_two;
  const auto& [searching, signals, groups] = heard_by_two;
  const std::vector<FusedVictim> victims{victim(7, {0, 0}, {{"r1", 2}, {"r2", 2}})};
  EXPECT_EQ(pursuits.update(victims, searching, 0, groups).size(), 2u);
  EXPECT_TRUE(pursuits.update(victims, searching, 61 * kSecond, groups).empty());
  EXPECT_EQ(pursuits.given_up_count(), 3u) << "victim 7 and both signals of the transmitter";
  // Both leave the picture for less than a timeout and come back: still given up.
  EXPECT_TRUE(pursuits.update({}, searching, 100 * kSecond).empty());
  EXPECT_TRUE(pursuits.update(victims, searching, 110 * kSecond, groups).empty());
  EXPECT_EQ(pursuits.given_up_count(), 3u);
  // Gone for longer: forgotten, and pursued afresh when heard again.
  EXPECT_TRUE(pursuits.update({}, searching, 150 * kSecond).empty());
  EXPECT_EQ(pursuits.given_up_count(), 3u) << "40 s unseen";
  EXPECT_TRUE(pursuits.update({}, searching, 171 * kSecond).empty());
  EXPECT_EQ(pursuits.given_up_count(), 0u) << "61 s unseen";
  EXPECT_EQ(pursuits.update(victims, searching, 180 * kSecond, groups).size(), 2u);
  EXPECT_EQ(pursuits.pursuer_of(7), "r1");
  EXPECT_EQ(pursuits.pursuer_of_signal({"r1", 1}), "r2") << "r1 pursues the victim";
}

// A given-up signal that only its own rescuer hears for a while (in no group) is still in the
// picture: when a second rescuer hears it again, it is not pursued afresh.
TEST(SignalPursuits, AGivenUpSignalHeardByItsRescuerAloneStaysGivenUp) {
  SignalPursuits pursuits(60.0);
  const OneTransmitterTwoHearers heard_by_two;
  const auto& [searching, signals, groups] = heard_by_two;
  EXPECT_EQ(pursuits.update({}, searching, 0, groups).size(), 1u);
  EXPECT_TRUE(pursuits.update({}, searching, 61 * kSecond, groups).empty());
  const auto alone = group_heard_signals({signals[0]}, {}, 0.999);
  ASSERT_TRUE(alone.unplaced.empty());
  for (int s = 70; s <= 200; s += 10) EXPECT_TRUE(pursuits.update({}, searching, s * kSecond, alone).empty());
  EXPECT_EQ(pursuits.given_up_count(), 1u) << "r1/1 still heard; r2/1 unheard for 139 s";
  EXPECT_TRUE(pursuits.update({}, searching, 205 * kSecond, groups).empty()) << "r1/1 was never out of the picture";
  EXPECT_EQ(pursuits.given_up_count(), 1u);
}

// The timeout counts from the start of the pursuit, before it was placed, and across a group
// broken for a cycle (a fix on its way); placed by others first, the nearest who placed it is sent;
// a pursuer whose signal only matches the victim's signature keeps it for kMatchedPursuerGraceNs.
TEST(SignalPursuits, APursuitKeepsItsStartThroughABreakAndGoesToOneWhoPlacedIt) {
  SignalPursuits pursuits(60.0);
  const std::map<std::string, Vec2> searching{{"r1", {0, 0}}, {"r2", {10, 0}}, {"r3", {50, 0}}};
  std::vector<HeardSignal> signals{heard("r1", 1, 1.0), heard("r2", 1, 0.0), heard("r3", 1, 2.0)};
  EXPECT_EQ(pursuits.update({}, searching, 0, group_heard_signals(signals, {}, 0.999)).size(), 2u);
  EXPECT_TRUE(pursuits.update({}, searching, 5 * kSecond, {}).empty()) << "broken: nothing handed over";
  EXPECT_EQ(pursuits.pursuer_of_signal({"r1", 1}), "r2") << "but the pursuit waits";
  EXPECT_EQ(pursuits.update({}, searching, 10 * kSecond, group_heard_signals(signals, {}, 0.999)).size(), 2u);
  EXPECT_TRUE(pursuits.events().empty()) << "the same pursuit again, nothing new said";

  // r3 places it first (r3 is the nearest to it): having placed it is better evidence of being
  // near than having heard it first, so r2's pursuit ends and r3 is sent, with a new timeout.
  signals[2].placed = true;
  const std::vector<FusedVictim> victims{victim(6, {45, 0}, {{"r3", 1}})};
  auto handed = pursuits.update(victims, searching, 20 * kSecond, group_heard_signals(signals, victims, 0.999));
  EXPECT_EQ(pursuits.pursuer_of(6), "r3");
  EXPECT_FALSE(pursuits.pursuer_of_signal({"r1", 1})) << "the pursuit before placing ends";
  EXPECT_EQ(signals_left_to_others(handed, "r2"), std::set<std::uint32_t>{1});
  EXPECT_TRUE(signals_left_to_others(handed, "r3").empty());
  ASSERT_EQ(pursuits.events().size(), 2u);
  EXPECT_NE(pursuits.events()[0].text.find("placed; r2, who pursued its signal before it was placed, did not place it "
                                           "(or no longer searches): his pursuit ends"),
            std::string::npos)
      << pursuits.events()[0].text;
  EXPECT_FALSE(pursuits.update(victims, searching, 79 * kSecond, group_heard_signals(signals, victims, 0.999)).empty())
      << "r3's 60 s count from 20 s";
  EXPECT_EQ(pursuits.pursuer_of(6), "r3");
  // Whether a placer is free does not depend on the order of the victims: r3 placed V1 alone
  // and pursued T2's signal, which r4 placed alone. r3's pursuit of T2 ends, so he is free for
  // V1, which r1, who pursued its signal before it was placed, did not place.
  SignalPursuits ordered(240.0);
  const std::map<std::string, Vec2> four{{"r1", {0, 0}}, {"r3", {50, 0}}, {"r4", {100, 0}}};
  std::vector<HeardSignal> t1_t2{heard("r1", 1, 0.0), heard("r3", 1, 1.0), heard("r3", 2, 0.0), heard("r4", 2, 1.0)};
  t1_t2[2].transmitter = t1_t2[3].transmitter = signature(-50.0, 1.2);
  ordered.update({}, four, 0, group_heard_signals(t1_t2, {}, 0.999));
  ASSERT_EQ(ordered.pursuer_of_signal({"r3", 1}), "r1");
  ASSERT_EQ(ordered.pursuer_of_signal({"r4", 2}), "r3");
  t1_t2[1].placed = t1_t2[3].placed = true;
  const std::vector<FusedVictim> v1_v2{victim(1, {48, 0}, {{"r3", 1}}), victim(2, {98, 0}, {{"r4", 2}})};
  handed = ordered.update(v1_v2, four, kSecond, group_heard_signals(t1_t2, v1_v2, 0.999));
  EXPECT_EQ(ordered.pursuer_of(1), "r3") << "r3 is free: his pursuit of T2 ended";
  EXPECT_EQ(ordered.pursuer_of(2), "r4");
  EXPECT_EQ(signals_left_to_others(handed, "r1"), std::set<std::uint32_t>{1});
  EXPECT_EQ(signals_left_to_others(handed, "r3"), std::set<std::uint32_t>{2});

  // Nor does the exception below (all who placed it pursue another) keep a victim with one who
  // has just been sent to another: r1, freed from T1 (placed by r3 alone, busy with T2), is the
  // only one who placed V0 and is sent there; V1 goes to r3, who placed it, although busy.
  SignalPursuits one_each(240.0);
  std::vector<HeardSignal> three{heard("r1", 1, 0.0), heard("r3", 1, 1.0), heard("r3", 2, 0.0), heard("r4", 2, 1.0)};
  three[2].transmitter = three[3].transmitter = signature(-50.0, 1.2);
  one_each.update({}, four, 0, group_heard_signals(three, {}, 0.999));
  ASSERT_EQ(one_each.pursuer_of_signal({"r3", 1}), "r1");
  ASSERT_EQ(one_each.pursuer_of_signal({"r4", 2}), "r3");
  three[1].placed = true;
  three.push_back(heard("r1", 5, 2.0, true));
  three.push_back(heard("r4", 5, 3.0));
  three[4].transmitter = three[5].transmitter = signature(40.0, 0.75);
  const std::vector<FusedVictim> v0_v1{victim(7, {2, 0}, {{"r1", 5}}), victim(1, {48, 0}, {{"r3", 1}})};
  one_each.update(v0_v1, four, kSecond, group_heard_signals(three, v0_v1, 0.999));
  EXPECT_EQ(one_each.pursuer_of(7), "r1");
  EXPECT_EQ(one_each.pursuer_of(1), "r3") << "not r1 as well";

  // Placed by others who all pursue another victim: the one who pursued its signal before it was placed keeps it,
  // for kMatchedPursuerGraceNs if he does not place it himself.
  SignalPursuits busy_placer(240.0);
  std::vector<HeardSignal> two_transmitters{heard("r2", 2, 0.0, true), heard("r3", 2, 0.0, true), heard("r1", 1, 1.0),
                                            heard("r3", 1, 2.0)};
  two_transmitters[0].transmitter = two_transmitters[1].transmitter = signature(-50.0, 1.2);
  std::vector<FusedVictim> near_r3{victim(5, {48, 0}, {{"r3", 2}, {"r2", 2}})};
  busy_placer.update(near_r3, searching, 0, group_heard_signals(two_transmitters, near_r3, 0.999));
  EXPECT_EQ(busy_placer.pursuer_of(5), "r3");
  EXPECT_EQ(busy_placer.pursuer_of_signal({"r3", 1}), "r1") << "r1 heard it first (and r3 is busy)";
  two_transmitters[3].placed = true;
  near_r3.push_back(victim(6, {45, 0}, {{"r3", 1}}));
  handed = busy_placer.update(near_r3, searching, 5 * kSecond, group_heard_signals(two_transmitters, near_r3, 0.999));
  EXPECT_EQ(busy_placer.pursuer_of(6), "r1");
  EXPECT_EQ(signals_left_to_others(handed, "r3"), (std::set<std::uint32_t>{1}));
  ASSERT_FALSE(busy_placer.events().empty());
  EXPECT_NE(busy_placer.events()[0].text.find(
                "still pursued by r1, who pursued its signal before it was placed (those who placed it "
                "pursue another)"),
            std::string::npos)
      << busy_placer.events()[0].text;
  busy_placer.update(near_r3, searching, 35 * kSecond, group_heard_signals(two_transmitters, near_r3, 0.999));
  EXPECT_EQ(busy_placer.pursuer_of(6), "r1");
  busy_placer.update(near_r3, searching, 36 * kSecond, group_heard_signals(two_transmitters, near_r3, 0.999));
  EXPECT_EQ(busy_placer.pursuer_of(6), "r3") << "r1 did not place it in 30 s: the one who did, busy or not";

  // A pursuer who placed it, then lost his source of it (his filter fell back below CONVERGED)
  // while his signal still matches its signature: he keeps it for kMatchedPursuerGraceNs, then the
  // nearest of those who placed it is sent (a warning says why).
  SignalPursuits matched(240.0);
  const std::vector<FusedVictim> by_two{victim(6, {45, 0}, {{"r3", 1}, {"r2", 1}})};
  std::vector<HeardSignal> placed_by_two{heard("r2", 1, 0.0, true), heard("r3", 1, 2.0, true)};
  matched.update(by_two, searching, 0, group_heard_signals(placed_by_two, by_two, 0.999));
  EXPECT_EQ(matched.pursuer_of(6), "r3") << "the nearest who placed it";
  const std::vector<FusedVictim> by_r2{victim(6, {45, 0}, {{"r2", 1}, {"r1", 1}})};
  std::vector<HeardSignal> r3_lost{heard("r1", 1, 0.0, true), heard("r2", 1, 0.0, true), heard("r3", 1, 2.0)};
  handed = matched.update(by_r2, searching, kSecond, group_heard_signals(r3_lost, by_r2, 0.999));
  EXPECT_EQ(matched.pursuer_of(6), "r3") << "r3's signal only matches now: he keeps it a while";
  EXPECT_EQ(signals_left_to_others(handed, "r2"), std::set<std::uint32_t>{1});
  handed = matched.update(by_r2, searching, 31 * kSecond, group_heard_signals(r3_lost, by_r2, 0.999));
  EXPECT_EQ(matched.pursuer_of(6), "r3");
  handed = matched.update(by_r2, searching, 32 * kSecond, group_heard_signals(r3_lost, by_r2, 0.999));
  EXPECT_EQ(matched.pursuer_of(6), "r2") << "the nearest of r1 and r2, who placed it";
  ASSERT_FALSE(matched.events().empty());
  EXPECT_TRUE(matched.events()[0].warning);
  EXPECT_EQ(signals_left_to_others(handed, "r3"), std::set<std::uint32_t>{1});

  // Had r2 placed it, he would have kept it only until the pursuit's timeout, counted from 0 s.
  SignalPursuits kept(60.0);
  const std::vector<HeardSignal> unplaced{heard("r1", 1, 1.0), heard("r2", 1, 0.0), heard("r3", 1, 2.0)};
  kept.update({}, searching, 0, group_heard_signals(unplaced, {}, 0.999));
  auto both = unplaced;
  both[1].placed = both[2].placed = true;
  const std::vector<FusedVictim> by_both{victim(6, {45, 0}, {{"r3", 1}, {"r2", 1}})};
  kept.update(by_both, searching, 20 * kSecond, group_heard_signals(both, by_both, 0.999));
  EXPECT_EQ(kept.pursuer_of(6), "r2");
  EXPECT_FALSE(kept.update(by_both, searching, 60 * kSecond, group_heard_signals(both, by_both, 0.999)).empty());
  EXPECT_TRUE(kept.update(by_both, searching, 61 * kSecond, group_heard_signals(both, by_both, 0.999)).empty())
      << "60 s after the pursuit began, not after the victim was placed";
}

}  // namespace
}  // namespace sarloc::incident
