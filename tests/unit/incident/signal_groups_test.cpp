// Which rescuers hear one transmitter before anyone has placed it (signal_groups.hpp): signals of
// different rescuers alike by signature are one group; a signature that could be two
// transmitters' groups nothing; a signal not yet placed joins the victim whose every source it
// matches, and no victim when it matches two.
#include "sarloc/core/incident/signal_groups.hpp"

#include <gtest/gtest.h>

namespace sarloc::incident {
namespace {

constexpr double kGate = 0.999;

/// A signature as the realistic receiver states it after a few pulses (sigmas include the
/// receivers' oscillator tolerance).
responder::TransmitterSignature signature(double carrier_hz, double period_s) {
  return {carrier_hz, 0.3, period_s, 0.002};
}

HeardSignal heard(const std::string& rescuer, std::uint32_t signal, responder::TransmitterSignature t,
                  double first_heard_s = 0.0, bool placed = false) {
  return {rescuer, signal, t, placed, static_cast<TimestampNs>(first_heard_s * 1e9)};
}

FusedVictim victim(std::uint32_t id, std::vector<std::pair<std::string, std::uint32_t>> sources) {
  FusedVictim v;
  v.victim_id = id;
  v.position.position = Vec3(0, 0, -1);
  v.position.covariance = Mat3::Identity();
  for (const auto& [rescuer, signal] : sources) v.sources.push_back({rescuer, signal});
  return v;
}

std::vector<std::string> rescuers_of(const std::vector<HeardSignal>& group) {
  std::vector<std::string> out;
  for (const auto& s : group) out.push_back(s.rescuer_id);
  return out;
}

TEST(SignalGroups, RescuersHearingOneTransmitterBeforeAnyonePlacesItAreOneGroupFirstHeardFirst) {
  const auto groups =
      group_heard_signals({heard("r1", 1, signature(12.0, 0.850), 9.0), heard("r2", 3, signature(12.4, 0.851), 5.0),
                           heard("r3", 2, signature(12.2, 0.849), 7.0), heard("r3", 1, signature(-40.0, 1.100), 2.0)},
                          {}, kGate);
  ASSERT_EQ(groups.unplaced.size(), 1u) << "r3's other transmitter is heard by r3 alone";
  EXPECT_EQ(rescuers_of(groups.unplaced[0]), (std::vector<std::string>{"r2", "r3", "r1"}));
  EXPECT_EQ(groups.unplaced[0][1].signal_id, 2u);
  EXPECT_TRUE(groups.joined.empty());
}

TEST(SignalGroups, ASignatureNotKnownOrThatCouldBeTwoTransmittersGroupsNothing) {
  responder::TransmitterSignature carrier_only = signature(12.0, 0.850);
  carrier_only.period_sigma_s = 0.0;
  EXPECT_TRUE(group_heard_signals({heard("r1", 1, carrier_only), heard("r2", 1, signature(12.0, 0.850))}, {}, kGate)
                  .unplaced.empty())
      << "the carrier alone is not enough";
  EXPECT_TRUE(
      group_heard_signals({heard("r1", 1, signature(12.0, 0.850)), heard("r2", 1, signature(12.0, 0.950))}, {}, kGate)
          .unplaced.empty())
      << "the same carrier, another period: two transmitters";
  // r2 hears two transmitters alike with each other and with r1's: which one r1 hears, nobody knows.
  EXPECT_TRUE(group_heard_signals({heard("r1", 1, signature(12.0, 0.850)), heard("r2", 1, signature(12.1, 0.850)),
                                   heard("r2", 2, signature(12.2, 0.851))},
                                  {}, kGate)
                  .unplaced.empty());
  // A third rescuer's signal whose carrier alone is known and agrees: it may be the same
  // transmitter or another alike, so nothing is grouped.
  EXPECT_TRUE(group_heard_signals({heard("r1", 1, signature(12.0, 0.850)), heard("r2", 1, signature(12.0, 0.850)),
                                   heard("r3", 1, carrier_only)},
                                  {}, kGate)
                  .unplaced.empty());
  // a ~ b and b ~ c, but a and c differ: not one transmitter.
  EXPECT_TRUE(group_heard_signals({heard("r1", 1, signature(11.0, 0.850)), heard("r2", 1, signature(12.0, 0.850)),
                                   heard("r3", 1, signature(13.0, 0.850))},
                                  {}, kGate)
                  .unplaced.empty());
  // Alike with a placed signal that is no victim's source yet (its fix on the way): not grouped.
  EXPECT_TRUE(group_heard_signals({heard("r1", 1, signature(12.0, 0.850)), heard("r2", 1, signature(12.0, 0.850)),
                                   heard("r3", 1, signature(12.0, 0.850), 0.0, true)},
                                  {}, kGate)
                  .unplaced.empty());
}

TEST(SignalGroups, ASignalNotYetPlacedJoinsTheVictimWhoseEverySourceItMatches) {
  const std::vector<FusedVictim> victims{victim(7, {{"r1", 1}, {"r2", 2}}), victim(8, {{"r4", 1}})};
  const std::vector<HeardSignal> signals{
      heard("r1", 1, signature(12.0, 0.850), 0.0, true),
      heard("r2", 2, signature(12.3, 0.850), 0.0, true),
      heard("r4", 1, signature(-30.0, 1.200), 0.0, true),
      heard("r3", 4, signature(12.1, 0.850)),   // victim 7's
      heard("r5", 1, signature(12.0, 0.850)),   // victim 7's too
      heard("r6", 1, signature(-30.0, 0.700)),  // neither
  };
  const auto groups = group_heard_signals(signals, victims, kGate);
  ASSERT_EQ(groups.joined.count(7), 1u);
  EXPECT_EQ(rescuers_of(groups.joined.at(7)), (std::vector<std::string>{"r3", "r5"}));
  EXPECT_EQ(groups.joined.count(8), 0u);
  EXPECT_TRUE(groups.unplaced.empty()) << "joined signals form no group of their own";

  // Alike with one source of victim 7 and not the other: not victim 7's for sure.
  auto split = signals;
  split[1].transmitter = signature(12.0, 0.900);
  EXPECT_EQ(group_heard_signals(split, victims, kGate).joined.count(7), 0u);
  // Alike with sources of two victims: neither's.
  auto twins = signals;
  twins[2].transmitter = signature(12.2, 0.850);
  const auto ambiguous = group_heard_signals(twins, victims, kGate);
  EXPECT_TRUE(ambiguous.joined.empty());
  EXPECT_TRUE(ambiguous.unplaced.empty());
}

TEST(SignalGroups, HundredsOfSignalsAreGroupedOnlyWithTheirOwnTransmitter) {
  // 200 rescuers, each hearing one of 100 transmitters spread over the band (2 rescuers each).
  std::vector<HeardSignal> signals;
  for (int r = 0; r < 200; ++r) {
    const int t = r % 100;
    signals.push_back(heard("r" + std::to_string(r), 1, signature(-79.0 + 1.6 * t, 0.7 + 0.006 * t), r * 0.1));
  }
  const auto groups = group_heard_signals(signals, {}, kGate);
  ASSERT_EQ(groups.unplaced.size(), 100u);
  for (const auto& g : groups.unplaced) {
    ASSERT_EQ(g.size(), 2u);
    EXPECT_EQ(std::stoi(g[0].rescuer_id.substr(1)) % 100, std::stoi(g[1].rescuer_id.substr(1)) % 100);
    EXPECT_LE(g[0].first_heard, g[1].first_heard) << "first heard first";
  }
}

}  // namespace
}  // namespace sarloc::incident
