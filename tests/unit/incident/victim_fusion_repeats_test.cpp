// VictimFusion and one transmitter heard as two signals: suspected and confirmed repeats, splits,
// twins, and transmitter signatures.
#include <gtest/gtest.h>

#include "sarloc/core/incident/victim_fusion.hpp"
#include "source_estimates.hpp"

namespace sarloc::incident {
namespace {

using responder::EstimatorStatus;
using test::kSec;
using test::src;

SourceEstimate repeat_of(SourceEstimate s, responder::RepeatState state, std::uint32_t of) {
  s.repeat = state;
  s.repeat_of_signal = of;
  return s;
}

// a's signal 1 found, its signal 2 located 0.4 m away: two victims, as far as incident command knows.
void found_and_located_by_a(VictimFusion& f) {
  f.update(src("a", 1, kSec, Vec3(0.0, 0.0, -1.0), 0.1, EstimatorStatus::kFound));
  f.update(src("a", 2, kSec, Vec3(0.4, 0.0, -1.0), 0.15, EstimatorStatus::kLocated));
  f.step(kSec);
}

// One transmitter split into two signals by a's separation: a's device cannot yet tell signal 2
// from signal 1, found. Signal 2 still shows where a second victim may be, but confirms nothing:
// its victim, located before, goes back to unconfirmed and names the victim it may be.
TEST(VictimFusion, ASuspectedRepeatConfirmsNothingAndNamesTheVictimItMayBe) {
  VictimFusion f;
  found_and_located_by_a(f);
  ASSERT_EQ(f.victims().size(), 2u);
  EXPECT_EQ(f.victims()[1].state, VictimState::kLocated) << "before the device's word";
  EXPECT_EQ(f.victims()[1].possibly_same_as, 0u);
  f.update(repeat_of(src("a", 2, 2 * kSec, Vec3(0.4, 0.0, -1.0), 0.15, EstimatorStatus::kConverged),
                     responder::RepeatState::kSuspected, 1));
  f.update(src("a", 1, 2 * kSec, Vec3(0.0, 0.0, -1.0), 0.1, EstimatorStatus::kFound));
  f.step(2 * kSec);
  ASSERT_EQ(f.victims().size(), 2u) << "shown, as a possible second victim";
  EXPECT_EQ(f.victims()[0].state, VictimState::kFound);
  EXPECT_EQ(f.victims()[1].state, VictimState::kUnconfirmed);
  EXPECT_EQ(f.victims()[1].located_at, 0);
  EXPECT_EQ(f.victims()[1].possibly_same_as, f.victims()[0].victim_id);
  // Another rescuer locating it there stands by it: the repeat's doubt is a's alone.
  f.update(src("b", 1, 3 * kSec, Vec3(0.45, 0.0, -1.0), 0.15, EstimatorStatus::kLocated));
  f.update(repeat_of(src("a", 2, 3 * kSec, Vec3(0.4, 0.0, -1.0), 0.15, EstimatorStatus::kConverged),
                     responder::RepeatState::kSuspected, 1));
  f.update(src("a", 1, 3 * kSec, Vec3(0.0, 0.0, -1.0), 0.1, EstimatorStatus::kFound));
  f.step(3 * kSec);
  ASSERT_EQ(f.victims().size(), 2u);
  EXPECT_EQ(f.victims()[1].state, VictimState::kLocated);
}

// A repeat claim counts while its estimator is heard: the core daemon's copy suspected signal 2,
// then stopped (killed); the device, which sees every sample, says none, and confirms it again.
TEST(VictimFusion, AStoppedEstimatorsRepeatClaimLapses) {
  VictimFusion f;
  found_and_located_by_a(f);
  SourceEstimate daemon = repeat_of(src("a", 2, 2 * kSec, Vec3(0.4, 0.0, -1.0), 0.15, EstimatorStatus::kConverged),
                                    responder::RepeatState::kSuspected, 1);
  daemon.from_device = false;
  daemon.estimator = "core";
  f.update(daemon);
  f.step(2 * kSec);
  ASSERT_EQ(f.victims().size(), 2u);
  EXPECT_EQ(f.victims()[1].state, VictimState::kUnconfirmed) << "while the daemon suspects it";
  const TimestampNs later = 2 * kSec + static_cast<TimestampNs>(f.config().source_timeout_s * 1e9) + kSec;
  f.update(src("a", 1, later, Vec3(0.0, 0.0, -1.0), 0.1, EstimatorStatus::kFound));
  f.update(src("a", 2, later, Vec3(0.4, 0.0, -1.0), 0.15, EstimatorStatus::kLocated));
  f.step(later);
  ASSERT_EQ(f.victims().size(), 2u);
  EXPECT_EQ(f.victims()[1].state, VictimState::kLocated);
  EXPECT_EQ(f.victims()[1].possibly_same_as, 0u);
}

// Stood over, signal 2 is signal 1 again: the victim it had opened merges into signal 1's.
TEST(VictimFusion, AConfirmedRepeatMergesItsVictimIntoTheVictimOfTheSignalItRepeats) {
  VictimFusion f;
  found_and_located_by_a(f);
  ASSERT_EQ(f.victims().size(), 2u);
  ASSERT_EQ(f.victims()[1].state, VictimState::kLocated);
  f.update(repeat_of(src("a", 2, 2 * kSec, Vec3(0.05, 0.0, -1.0), 0.1, EstimatorStatus::kConverged),
                     responder::RepeatState::kConfirmed, 1));
  f.update(src("a", 1, 2 * kSec, Vec3(0.0, 0.0, -1.0), 0.1, EstimatorStatus::kFound));
  f.step(2 * kSec);
  ASSERT_EQ(f.victims().size(), 1u);
  EXPECT_EQ(f.victims()[0].victim_id, 1u);
  EXPECT_EQ(f.victims()[0].state, VictimState::kFound);
  EXPECT_EQ(f.take_removed(), (std::vector<std::uint32_t>{2}));
  // Its later estimates open nothing.
  f.update(repeat_of(src("a", 2, 3 * kSec, Vec3(0.05, 0.0, -1.0), 0.1, EstimatorStatus::kConverged),
                     responder::RepeatState::kConfirmed, 1));
  f.step(3 * kSec);
  EXPECT_EQ(f.victims().size(), 1u);
}

// Every rescuer's separation split one transmitter into two signals: one rescuer's signals
// never share a victim, so the picture holds two victims a few decimetres apart. It cannot tell
// them from one: neither is confirmed by the fused radius, each names the other, and only a
// device's own word confirms. Before, both were LOCATED (live, four within 5 m, clean seed 1:
// one victim confirmed twice, 0.56 m apart).
TEST(VictimFusion, ATransmitterEveryRescuerSplitIsNotConfirmedTwice) {
  VictimFusionConfig c;
  c.source_timeout_s = 5.0;
  VictimFusion f(c);
  const Vec3 a(-1.5, 39.0, -1.2);
  auto report = [&](TimestampNs t, EstimatorStatus r2_first, bool with_r2) {
    for (const char* r : {"r1", "r2", "r3"}) {
      if (!with_r2 && std::string(r) == "r2") continue;
      const bool first_of_r2 = std::string(r) == "r2";
      f.update(src(r, 1, t, a + Vec3(0.1, 0.0, 0.0), 0.15, first_of_r2 ? r2_first : EstimatorStatus::kConverged));
      f.update(src(r, 2, t, a + Vec3(-0.1, 0.1, 0.0), 0.15));
    }
    f.step(t);
  };
  report(0, EstimatorStatus::kConverged, true);
  ASSERT_EQ(f.victims().size(), 2u);
  for (const FusedVictim& v : f.victims()) {
    EXPECT_EQ(v.sources.size(), 3u);
    EXPECT_EQ(v.state, VictimState::kUnconfirmed) << "victim " << v.victim_id;
    EXPECT_NE(v.possibly_same_as, 0u);
    EXPECT_NE(v.possibly_same_as, v.victim_id);
  }
  // r2's device stands over its first signal: that victim is found, the other still names it.
  report(kSec, EstimatorStatus::kFound, true);
  ASSERT_EQ(f.victims().size(), 2u);
  const auto found = std::find_if(f.victims().begin(), f.victims().end(),
                                  [](const FusedVictim& v) { return v.state == VictimState::kFound; });
  ASSERT_NE(found, f.victims().end());
  const std::uint32_t found_id = found->victim_id;
  EXPECT_EQ(found->possibly_same_as, 0u);
  for (const FusedVictim& v : f.victims()) {
    if (v.victim_id == found_id) continue;
    EXPECT_EQ(v.state, VictimState::kUnconfirmed);
    EXPECT_EQ(v.possibly_same_as, found_id);
  }
  // r2 walks on (its sources time out): what its device found stays found.
  report(7 * kSec, EstimatorStatus::kConverged, false);
  const auto still = std::find_if(f.victims().begin(), f.victims().end(),
                                  [&](const FusedVictim& v) { return v.victim_id == found_id; });
  ASSERT_NE(still, f.victims().end());
  EXPECT_EQ(still->state, VictimState::kFound);
}

// r3's FOUND signal shares victim 1 with r2's estimate; r3's split of that transmitter appears
// next to r2's, outside the FOUND one's merge gate. Joint association would give the newcomer
// victim 1 (it fits r2's estimate better) and open a second victim for the FOUND signal: the
// device's FOUND keeps its victim. Before: victim 1 went on with the converged split, and C was
// FOUND twice (live, four within 5 m).
TEST(VictimFusion, ASignalItsDeviceLocatedKeepsItsVictimAgainstANewcomerOfTheSameRescuer) {
  VictimFusion f;
  const Vec3 c(0.0, 42.0, -1.0);
  auto report = [&](TimestampNs t, bool with_split) {
    f.update(src("r2", 3, t, c + Vec3(0.7, 0.9, 0.0), 0.4));
    f.update(src("r3", 3, t, c, 0.1, EstimatorStatus::kFound));
    if (with_split) f.update(src("r3", 5, t, c + Vec3(0.72, 0.96, 0.0), 0.3));
    f.step(t);
  };
  report(0, false);
  ASSERT_EQ(f.victims().size(), 1u);
  ASSERT_EQ(f.victims()[0].state, VictimState::kFound);
  report(kSec, true);
  report(2 * kSec, true);
  ASSERT_EQ(f.victims().size(), 2u);
  const FusedVictim& first = f.victims()[0];
  EXPECT_EQ(first.state, VictimState::kFound);
  ASSERT_EQ(first.sources.size(), 2u);
  EXPECT_TRUE(std::any_of(first.sources.begin(), first.sources.end(),
                          [](const VictimSource& s) { return s.rescuer_id == "r3" && s.signal_id == 3; }));
  EXPECT_EQ(f.victims()[1].state, VictimState::kUnconfirmed) << "the split confirms nothing";
}

// A victim located by the fused radius alone, then a twin: the same rescuers' second signals
// there. The confirmation rested on nothing a device said, and is withdrawn.
TEST(VictimFusion, AConfirmationByTheFusedRadiusAloneIsWithdrawnForATwin) {
  VictimFusion f;
  const Vec3 a(-1.5, 39.0, -1.2);
  f.update(src("r1", 1, 0, a, 0.15));
  f.update(src("r3", 1, 0, a + Vec3(0.05, 0.0, 0.0), 0.15));
  f.step(0);
  ASSERT_EQ(f.victims().size(), 1u);
  ASSERT_EQ(f.victims()[0].state, VictimState::kLocated) << "the fused radius";
  f.update(src("r1", 2, kSec, a + Vec3(0.2, 0.1, 0.0), 0.15));
  f.update(src("r3", 2, kSec, a + Vec3(0.25, 0.1, 0.0), 0.15));
  f.update(src("r1", 1, kSec, a, 0.15));
  f.update(src("r3", 1, kSec, a + Vec3(0.05, 0.0, 0.0), 0.15));
  f.step(kSec);
  ASSERT_EQ(f.victims().size(), 2u);
  for (const FusedVictim& v : f.victims()) {
    EXPECT_EQ(v.state, VictimState::kUnconfirmed) << "victim " << v.victim_id;
    EXPECT_EQ(v.located_at, 0);
    EXPECT_NE(v.possibly_same_as, 0u);
  }
}

SourceEstimate signed_by(SourceEstimate s, double carrier_hz, double period_s) {
  // As a device states it: its oscillator's 4.6 Hz in the carrier, the timing filter's period.
  s.transmitter = responder::TransmitterSignature{carrier_hz, 4.6, period_s, 0.0002};
  return s;
}

// The four-within-5m failure of the fresh-clone CI of a127f40: C FOUND by r1 and r2 in one
// victim, by r3 in a second one that r3's estimate had opened 1 m away; both then FOUND 0.56 m
// apart, and kept apart as two dig sites. Their signatures (one carrier within the devices'
// oscillators, one period) say one transmitter: one victim. Victims of distinct signatures, or
// of signatures not known, stay two (TwoFoundVictimsNeverMerge).
TEST(VictimFusion, TwoFoundVictimsOfOneTransmitterAreOne) {
  const Vec3 c(0.0, 42.0, -1.0), far = c + Vec3(3.0, 0.0, 0.0), near = c + Vec3(0.45, 0.3, 0.0);
  for (const double r3_carrier : {7.0, 45.0}) {  // r1's 3 Hz: the same transmitter, then another
    VictimFusion f;
    for (int k = 0; k < 6; ++k) {
      const TimestampNs t = k * kSec;
      f.update(signed_by(src("r1", 2, t, c, 0.35, EstimatorStatus::kFound), 3.0, 1.005));
      f.update(signed_by(src("r3", 4, t, k < 3 ? far : near, 0.35, EstimatorStatus::kFound), r3_carrier, 1.005));
      f.step(t);
      if (k == 2) {
        ASSERT_EQ(f.victims().size(), 2u) << "3 m apart: two victims";
      }
    }
    if (r3_carrier == 7.0) {
      ASSERT_EQ(f.victims().size(), 1u) << "one transmitter FOUND twice";
      EXPECT_EQ(f.victims()[0].state, VictimState::kFound);
      EXPECT_EQ(f.victims()[0].sources.size(), 2u);
      EXPECT_EQ(f.take_removed().size(), 1u);
    } else {
      ASSERT_EQ(f.victims().size(), 2u) << "two transmitters 0.54 m apart merged";
    }
  }
}

// The restart mission in a loaded CI (twice): r1's filter of C's signal, fed C's pulses from
// the detection floor, converged 48 m from C and stayed there. Here r1 and r3 place it there
// first (LOCATED by the fused radius: nothing says otherwise yet), then r2 FOUND C: the contact's
// signature is C's, so its confirmation is withdrawn and it names C, and it keeps saying so once
// r1 and r3 are gone. A contact of another transmitter there stays a victim more.
TEST(VictimFusion, AContactOfAConfirmedVictimsTransmitterElsewhereNamesIt) {
  const Vec3 c(18.0, 62.0, -1.2), ghost(-26.3, 42.5, -0.9);
  for (const double r1_carrier : {67.9, 20.0}) {  // C's carrier as r1 hears it, then another transmitter's
    VictimFusion f;
    auto contact_at = [&](TimestampNs t) {
      f.update(signed_by(src("r1", 4, t, ghost, 0.5), r1_carrier, 1.0585));
      f.update(signed_by(src("r3", 1, t, ghost + Vec3(0.1, 0.0, 0.0), 0.1), r1_carrier, 1.0585));
    };
    contact_at(0);
    f.step(0);
    ASSERT_EQ(f.victims().size(), 1u);
    const std::uint32_t contact_id = f.victims()[0].victim_id;
    ASSERT_EQ(f.victims()[0].state, VictimState::kLocated) << "two rescuers' devices agree, nothing alike yet";
    for (int k = 1; k < 3; ++k) {
      f.update(signed_by(src("r2", 3, k * kSec, c, 0.3, EstimatorStatus::kFound), 68.1, 1.0585));
      contact_at(k * kSec);
      f.step(k * kSec);
      ASSERT_EQ(f.victims().size(), 2u);
      const FusedVictim& contact = *f.victim(contact_id);
      const FusedVictim& found = f.victims()[f.victims()[0].victim_id == contact_id ? 1 : 0];
      ASSERT_EQ(found.state, VictimState::kFound);
      if (r1_carrier == 20.0) {
        EXPECT_EQ(contact.possibly_same_as, 0u) << "another transmitter";
        EXPECT_EQ(contact.state, VictimState::kLocated);
      } else {
        EXPECT_EQ(contact.state, VictimState::kUnconfirmed) << "step " << k << ": withdrawn in the step C is FOUND";
        EXPECT_EQ(contact.located_at, 0);
        EXPECT_EQ(contact.possibly_same_as, found.victim_id);
      }
    }
    if (r1_carrier == 20.0) continue;
    // r1 and r3 stop (signed off, out of range): the contact keeps what it may be.
    for (int k = 3; k < 20; ++k) {
      f.update(signed_by(src("r2", 3, k * kSec, c, 0.3, EstimatorStatus::kFound), 68.1, 1.0585));
      f.step(k * kSec);
    }
    ASSERT_EQ(f.victims().size(), 2u);
    const FusedVictim& left = *f.victim(contact_id);
    EXPECT_TRUE(left.sources.empty());
    EXPECT_EQ(left.state, VictimState::kUnconfirmed);
    ASSERT_NE(left.possibly_same_as, 0u);
    ASSERT_NE(f.victim(left.possibly_same_as), nullptr);
    EXPECT_EQ(f.victim(left.possibly_same_as)->state, VictimState::kFound);
  }
}

// One transmitter placed in two places 40 m apart, each by two rescuers' converged estimates and
// by no device's LOCATED or FOUND: which place is right nobody knows, so neither is confirmed by
// the fused radius, whichever is judged first; each names the other.
TEST(VictimFusion, TwoPlacesOfOneTransmitterNoDeviceStandsByConfirmNeither) {
  const Vec3 here(0.0, 40.0, -1.0), there(40.0, 40.0, -1.0);
  VictimFusion f;
  for (int k = 0; k < 3; ++k) {
    const TimestampNs t = k * kSec;
    f.update(signed_by(src("r1", 1, t, here, 0.1), 30.0, 1.1));
    f.update(signed_by(src("r2", 1, t, here + Vec3(0.1, 0.0, 0.0), 0.1), 30.0, 1.1));
    f.update(signed_by(src("r3", 1, t, there, 0.1), 31.0, 1.1));
    f.update(signed_by(src("r4", 1, t, there + Vec3(0.1, 0.0, 0.0), 0.1), 31.0, 1.1));
    f.step(t);
    ASSERT_EQ(f.victims().size(), 2u);
    for (const FusedVictim& v : f.victims()) {
      EXPECT_EQ(v.state, VictimState::kUnconfirmed) << "victim " << v.victim_id << ", step " << k;
      EXPECT_NE(v.possibly_same_as, 0u);
      EXPECT_NE(v.possibly_same_as, v.victim_id);
    }
  }
}

// Seen live (four-within-5m under load): r2's FOUND signal of A fell silent for 12 s (its pulses
// went to a new signal, a suspected repeat of it), the repeat took A's place beside r1's FOUND,
// and the FOUND signal, heard again, opened a second FOUND victim: A twice. A signal its device
// found comes back to the victim it was last bound to.
TEST(VictimFusion, AFoundSignalBackFromSilenceTakesItsVictimBackFromARepeat) {
  const Vec3 a(-1.5, 39.0, -1.2);
  VictimFusion f;
  TimestampNs t = 0;
  for (int k = 0; k < 3; ++k, t += kSec) {
    f.update(src("r1", 3, t, a, 0.35, EstimatorStatus::kFound));
    f.update(src("r2", 3, t, a + Vec3(0.4, 0.0, 0.0), 0.35, EstimatorStatus::kFound));
    f.step(t);
  }
  ASSERT_EQ(f.victims().size(), 1u);
  const TimestampNs silent_from = t;
  for (; t < silent_from + 12 * kSec; t += kSec) {  // r2/3 silent; r2/9 follows A, a suspected repeat
    f.update(src("r1", 3, t, a, 0.35, EstimatorStatus::kFound));
    f.update(repeat_of(src("r2", 9, t, a, 0.35, EstimatorStatus::kConverged), responder::RepeatState::kSuspected, 3));
    f.step(t);
  }
  ASSERT_EQ(f.victims().size(), 1u);
  ASSERT_EQ(f.victims()[0].sources.size(), 2u);
  EXPECT_EQ(f.victims()[0].sources[1].signal_id, 9u) << "the repeat in the silent signal's place";
  for (int k = 0; k < 3; ++k, t += kSec) {
    f.update(src("r1", 3, t, a, 0.35, EstimatorStatus::kFound));
    f.update(src("r2", 3, t, a + Vec3(0.4, 0.0, 0.0), 0.35, EstimatorStatus::kFound));
    f.update(repeat_of(src("r2", 9, t, a, 0.35, EstimatorStatus::kConverged), responder::RepeatState::kSuspected, 3));
    f.step(t);
  }
  std::size_t confirmed = 0;
  for (const FusedVictim& v : f.victims()) {
    if (v.state == VictimState::kUnconfirmed) continue;
    ++confirmed;
    ASSERT_EQ(v.sources.size(), 2u);
    EXPECT_EQ(v.sources[1].rescuer_id, "r2");
    EXPECT_EQ(v.sources[1].signal_id, 3u) << "the FOUND signal back in its victim";
  }
  EXPECT_EQ(confirmed, 1u) << "A twice";
}

}  // namespace
}  // namespace sarloc::incident
