// The realistic receiver's signal separation (issue 12): overlapping pulses keep their ids, what
// cannot be attributed is not guessed, tracks are re-anchored on the right train, devices'
// signatures tell transmitters apart.
#include "sarloc/core/avalanche/signal_separator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include "sarloc/core/avalanche/beacon_receiver.hpp"
#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/avalanche/pulse_detector.hpp"
#include "sarloc/core/avalanche/receiver_model.hpp"

namespace sarloc::avalanche {
namespace {

// The tail of a pulse that began before the window: its start is the window's, whatever edge
// the detector finds a sample or two later. Taken for a whole pulse, one once started a second
// track on its transmitter's carrier, after which the transmitter's own pulses, claimed by
// both tracks, went unattributed (the rescuer lost a victim 25 m away).
TEST(SignalSeparator, APulseCutByTheWindowStartIsTruncated) {
  std::mt19937_64 rng(21);
  const Vec3 noise(2.1e-9, 6.3e-9, 6.3e-9);
  int tails = 0;
  for (int k = 0; k < 40; ++k) {
    SignalSeparator separator;
    IncomingPulse p;
    p.start_s = -0.13;
    p.end_s = 0.02 + 0.001 * (k % 30);  // 20-50 ms inside the window
    p.carrier_offset_hz = -43.5;
    p.amplitude = Vec3c(std::complex<double>(2.5e-8, 0.5e-8), std::complex<double>(-1e-8, 0.0), 0.0) *
                  std::polar(1.0, 0.3 * k);
    const SeparationReport r = separator.process(synthesize({p}, 0.0, 1.0, 500.0, noise, rng));
    for (const auto& d : r.pulses) {
      if (d.end_s > 0.1) continue;
      ++tails;
      EXPECT_TRUE(d.truncated_start) << "tail found at [" << d.start_s << ", " << d.end_s << "]";
    }
  }
  EXPECT_GE(tails, 30);
}

// Three transmitters 3 m apart whose pulses overlap, on distinct carriers: each keeps its id.
TEST(SignalSeparator, OverlappingPulsesOnDistinctCarriersKeepTheirIds) {
  SimulationConfig config;
  BeaconReceiver receiver(config, 11);
  std::vector<Beacon> beacons(3);
  const double carriers[3] = {-40.0, 5.0, 52.0};
  for (int i = 0; i < 3; ++i) {
    beacons[i].position = Vec3(20.0 + 3.0 * i, 2.0 * i, -1.0);
    beacons[i].moment = Vec3(0.01, 0.004 * i, 0.006);
    beacons[i].timing.period_s = 1.0 + 0.004 * i;  // overlapping for long stretches
    beacons[i].timing.on_time_s = 0.12;
    beacons[i].timing.first_start_s = 0.30 + 0.03 * i;
    beacons[i].timing.carrier_offset_hz = carriers[i];
  }
  ReceiverPose pose;
  pose.position = Vec3(0.0, 0.0, 1.0);
  std::uint32_t wrong = 0, samples = 0;
  for (int k = 0; k < 15; ++k) {
    const Listening heard = receiver.listen(pose, beacons, k, 1.0);
    wrong += heard.wrong_attributions;
    for (const auto& h : heard.samples) {
      ++samples;
      ASSERT_TRUE(h.transmitter.has_value());
      EXPECT_EQ(receiver.beacon_of_signal(h.sample.signal_id), h.transmitter);
      EXPECT_EQ(receiver.majority_beacon_of_signal(h.sample.signal_id), h.transmitter);
    }
  }
  EXPECT_EQ(wrong, 0U);
  // Most pulses of each of the three, of 45: 36-40 over devices 11-15 (which pulses the noise
  // hides or an overlap leaves unattributed varies with the device's oscillator and noise).
  EXPECT_GE(samples, 36U);
  EXPECT_EQ(receiver.separator().tracks(), 3U);
}

// Two transmitters on the same carrier, pulsing at the same time: the separation cannot tell
// them apart and says so (unattributed) rather than guessing.
TEST(SignalSeparator, SameCarrierSameTimeIsNotAttributed) {
  SimulationConfig config;
  // Windows cut apart, as this test was written for: with continuous listening each window's data
  // starts 0.25 s earlier, and at that phase (pulses of period 1 s at 0.35 and 0.85 in the window)
  // the separator never confirms a track, cut windows or not: a limitation found in issue 58
  // (docs/estimation/avalanche.md, "Left"), kept visible here rather than hidden by the phase.
  config.receiver.continuous_listening = false;
  BeaconReceiver receiver(config, 12);
  std::vector<Beacon> beacons(2);
  for (int i = 0; i < 2; ++i) {
    beacons[i].position = Vec3(15.0 + 4.0 * i, -3.0 * i, -1.0);
    beacons[i].moment = Vec3(0.01, 0.0, 0.01);
    beacons[i].timing.period_s = 1.0;
    beacons[i].timing.on_time_s = 0.1;
    beacons[i].timing.carrier_offset_hz = 10.0 + 0.2 * i;
  }
  beacons[0].timing.first_start_s = 0.2;
  beacons[1].timing.first_start_s = 0.25;  // overlap 50 ms on every pulse
  ReceiverPose pose;
  pose.position = Vec3(0.0, 0.0, 1.0);
  std::uint32_t wrong = 0, unattributed = 0;
  for (int k = 0; k < 10; ++k) {
    const Listening heard = receiver.listen(pose, beacons, k, 1.0);
    wrong += heard.wrong_attributions;
    unattributed += heard.report.unattributed;
  }
  EXPECT_GE(unattributed, 5U);  // at least half of the 10 overlapping pairs: never guessed
  EXPECT_LE(wrong, 1U);
}

Beacon same_carrier_beacon(const Vec3& position, const Vec3& moment, double first_start_s, double carrier_hz) {
  Beacon b;
  b.position = position;
  b.moment = moment;
  b.timing.period_s = 1.0;
  b.timing.on_time_s = 0.12;
  b.timing.carrier_offset_hz = carrier_hz;
  b.timing.first_start_s = first_start_s;
  return b;
}

// Two transmitters on one carrier (within one frequency cell), their pulses half a period
// apart: only timing tells them apart, and it does once the second train has proved itself
// interleaved with the first: two signals, each its own transmitter's.
TEST(SignalSeparator, SameCarrierDistinctTimingGivesTwoSignals) {
  SimulationConfig config;
  // Windows cut apart, as this test was written for: with continuous listening each window's data
  // starts 0.25 s earlier, and at that phase (pulses of period 1 s at 0.35 and 0.85 in the window)
  // the separator never confirms a track, cut windows or not: a limitation found in issue 58
  // (docs/estimation/avalanche.md, "Left"), kept visible here rather than hidden by the phase.
  config.receiver.continuous_listening = false;
  BeaconReceiver receiver(config, 14);
  const std::vector<Beacon> beacons{same_carrier_beacon(Vec3(12.0, 0.0, -1.0), Vec3(0.01, 0.0, 0.01), 0.1, -30.0),
                                    same_carrier_beacon(Vec3(14.0, -3.0, -1.5), Vec3(0.0, 0.012, 0.004), 0.6, -29.5)};
  ReceiverPose pose;
  pose.position = Vec3(0.0, 0.0, 1.0);
  std::uint32_t wrong = 0;
  std::map<std::uint32_t, std::set<std::size_t>> truth_of_signal;
  for (int k = 0; k < 15; ++k) {
    const Listening heard = receiver.listen(pose, beacons, k, 1.0);
    wrong += heard.wrong_attributions;
    for (const auto& h : heard.samples)
      if (h.transmitter) truth_of_signal[h.sample.signal_id].insert(*h.transmitter);
  }
  ASSERT_EQ(truth_of_signal.size(), 2U) << "one signal per transmitter";
  std::set<std::size_t> transmitters;
  for (const auto& [signal, truth] : truth_of_signal) {
    EXPECT_EQ(truth.size(), 1U) << "signal " << signal << " mixes transmitters";
    transmitters.insert(truth.begin(), truth.end());
  }
  EXPECT_EQ(transmitters.size(), 2U);
  EXPECT_LE(wrong, 1U);
}

// A second transmitter 2.2 Hz from a tracked one, on the same period, its pulses starting 50 ms
// earlier (and half as strong here): every pulse of it overlaps the first one's, so it is never clear of its timing, but
// the detector resolves both at once (distinct edges) and one transmitter cannot pulse twice at
// once: a second signal, each its own transmitter's; the strong one keeps its id throughout.
TEST(SignalSeparator, TwoTransmittersHeardAtOnceAreTwoSignals) {
  SimulationConfig config;
  BeaconReceiver receiver(config, 16);
  const Beacon strong = same_carrier_beacon(Vec3(4.0, 0.0, -1.0), Vec3(0.02, 0.0, 0.01), 0.40, 15.5);  // tracked first
  const Beacon weak = same_carrier_beacon(Vec3(2.0, 0.5, -1.0), Vec3(0.0, 0.008, 0.004), 0.35, 17.7);
  ReceiverPose pose;
  pose.position = Vec3(0.0, 0.0, 1.0);
  std::map<std::uint32_t, std::map<std::size_t, int>> truth_of_signal;
  std::optional<std::uint32_t> strong_id;
  for (int k = 0; k < 24; ++k) {
    const std::vector<Beacon> beacons = k < 4 ? std::vector<Beacon>{strong} : std::vector<Beacon>{strong, weak};
    const Listening heard = receiver.listen(pose, beacons, k, 1.0);
    for (const auto& h : heard.samples) {
      if (!h.transmitter) continue;
      ++truth_of_signal[h.sample.signal_id][*h.transmitter];
      if (k < 4) strong_id = h.sample.signal_id;
    }
  }
  ASSERT_TRUE(strong_id.has_value());
  ASSERT_EQ(truth_of_signal.size(), 2U) << "the weak transmitter was never tracked";
  for (const auto& [signal, truth] : truth_of_signal) {
    ASSERT_FALSE(truth.empty());
    const auto majority = std::max_element(truth.begin(), truth.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
    EXPECT_EQ(majority->first, signal == *strong_id ? 0U : 1U) << "signal " << signal;
    int others = 0;
    for (const auto& [t, n] : truth) others += t == majority->first ? 0 : n;
    EXPECT_LE(others, 1) << "signal " << signal << " mixes transmitters";
  }
}

// One transmitter whose pulses jump to another phase (its timing estimate went stale, or the
// receiver lost the train): the new train is not a second transmitter. It stays one signal, its
// id kept, reacquired; no sample is published from the new train before the hand-over.
TEST(SignalSeparator, OneTransmitterRetimedIsNeverSplit) {
  SimulationConfig config;
  BeaconReceiver receiver(config, 15);
  const Vec3 position(12.0, 0.0, -1.0), moment(0.01, 0.0, 0.01);
  const std::vector<Beacon> before{same_carrier_beacon(position, moment, 0.1, -30.0)};
  const std::vector<Beacon> after{same_carrier_beacon(position, moment, 0.6, -30.0)};
  ReceiverPose pose;
  pose.position = Vec3(0.0, 0.0, 1.0);
  std::set<std::uint32_t> signals;
  bool reacquired = false;
  for (int k = 0; k < 25; ++k) {
    const Listening heard = receiver.listen(pose, k < 8 ? before : after, k, 1.0);
    for (const auto& h : heard.samples) {
      signals.insert(h.sample.signal_id);
      reacquired = reacquired || h.sample.event == SignalEvent::kReacquired;
    }
  }
  EXPECT_EQ(signals.size(), 1U) << "one transmitter split into several signals";
  EXPECT_TRUE(reacquired);
  EXPECT_EQ(receiver.separator().tracks(), 1U);
}

// Two tracked transmitters on one carrier; the weaker one falls silent until its track is lost,
// then pulses again at another phase, clear of the other's timing: its track is re-anchored
// (reacquired, its id kept). With two tracks on the carrier its pulses went unattributed: a
// deep victim, heard 70 dB above the noise for 500 s, was never found (3 victims, seed 2,
// trial 5).
TEST(SignalSeparator, ALostTrackOnASharedCarrierIsReanchoredClearOfItsMate) {
  SimulationConfig config;
  // Windows cut apart, as this test was written for: with continuous listening each window's data
  // starts 0.25 s earlier, and at that phase (pulses of period 1 s at 0.35 and 0.85 in the window)
  // the separator never confirms a track, cut windows or not: a limitation found in issue 58
  // (docs/estimation/avalanche.md, "Left"), kept visible here rather than hidden by the phase.
  config.receiver.continuous_listening = false;
  BeaconReceiver receiver(config, 17);
  const Beacon a = same_carrier_beacon(Vec3(12.0, 0.0, -1.0), Vec3(0.01, 0.0, 0.01), 0.1, -30.0);
  const Beacon b_before = same_carrier_beacon(Vec3(14.0, -3.0, -1.5), Vec3(0.0, 0.012, 0.004), 0.6, -29.5);
  const Beacon b_after = same_carrier_beacon(Vec3(14.0, -3.0, -1.5), Vec3(0.0, 0.012, 0.004), 0.45, -29.5);
  ReceiverPose pose;
  pose.position = Vec3(0.0, 0.0, 1.0);
  std::optional<std::uint32_t> b_id;
  std::uint32_t wrong = 0, b_heard_after = 0, b_unattributed_after = 0;
  bool reacquired = false;
  for (int k = 0; k < 40; ++k) {
    std::vector<Beacon> beacons{a};
    if (k < 15) beacons.push_back(b_before);
    if (k >= 24) beacons.push_back(b_after);
    const Listening heard = receiver.listen(pose, beacons, k, 1.0);
    wrong += heard.wrong_attributions;
    for (const auto& h : heard.samples) {
      if (!h.transmitter || *h.transmitter != 1) continue;
      if (k < 15) b_id = h.sample.signal_id;
      if (k < 24) continue;
      ++b_heard_after;
      EXPECT_EQ(h.sample.signal_id, b_id) << "window " << k;
      reacquired = reacquired || h.sample.event == SignalEvent::kReacquired;
    }
    if (k >= 24) b_unattributed_after += heard.report.unattributed;
  }
  ASSERT_TRUE(b_id.has_value()) << "the second transmitter was never tracked";
  EXPECT_GE(b_heard_after, 12U) << "unattributed after its return: " << b_unattributed_after;
  EXPECT_TRUE(reacquired);
  EXPECT_LE(wrong, 1U);
}

// A found victim's track is lost while the rescuer walks on; another transmitter on its
// carrier, elsewhere, starts pulsing at another phase. Its field is not the one the lost track's
// filter predicts: it becomes a signal of its own, and the lost track keeps its id for its own
// transmitter, re-anchored when that one is heard again. Re-anchored on the stranger's pulses,
// the lost track fed them to a filter that takes no more samples, and the found transmitter's,
// unclaimed, started a new signal that was found a second time (4 victims, seed 2, trial 43).
TEST(SignalSeparator, ALostTrackIsNotReanchoredOnAPulseItsFilterCannotExplain) {
  SimulationConfig config;
  BeaconReceiver receiver(config, 19);
  const Beacon a_before = same_carrier_beacon(Vec3(12.0, 0.0, -1.0), Vec3(0.01, 0.0, 0.01), 0.1, -30.0);
  const Beacon a_after = same_carrier_beacon(Vec3(12.0, 0.0, -1.0), Vec3(0.01, 0.0, 0.01), 0.35, -30.0);
  const Beacon b = same_carrier_beacon(Vec3(-3.0, 11.0, -1.5), Vec3(0.0, 0.012, -0.004), 0.7, -29.6);
  ReceiverPose pose;
  pose.position = Vec3(0.0, 0.0, 1.0);
  // A's filter, as the rescuer's search would answer for it: it explains fields along A's own
  // (sign unknown) and nothing else. Every other signal has no filter yet.
  std::optional<std::uint32_t> a_id;
  Vec3 a_direction = Vec3::Zero();
  receiver.separator().set_consistency(
      [&](std::uint32_t signal, const Vec3& field, const Vec3&, std::uint8_t) -> std::optional<FieldFit> {
        if (!a_id || signal != *a_id) return std::nullopt;
        const double along = std::fabs(field.normalized().dot(a_direction));
        return FieldFit{0.0, along > std::cos(10.0 * kPi / 180.0) ? 1.0 : 1e4};
      });
  std::set<std::uint32_t> b_ids;
  std::uint32_t a_heard_after = 0, b_heard = 0;
  bool a_reacquired = false;
  for (int k = 0; k < 45; ++k) {
    std::vector<Beacon> beacons;
    if (k < 8) beacons.push_back(a_before);
    if (k >= 16) beacons.push_back(b);
    if (k >= 30) beacons.push_back(a_after);
    const Listening heard = receiver.listen(pose, beacons, k, 1.0);
    for (const auto& h : heard.samples) {
      ASSERT_TRUE(h.transmitter.has_value());
      const Beacon& truth = beacons[*h.transmitter];
      if (truth.position == a_before.position) {
        if (!a_id) {
          a_id = h.sample.signal_id;
          a_direction = h.sample.field.normalized();
        }
        EXPECT_EQ(h.sample.signal_id, *a_id) << "window " << k;
        if (k >= 30) {
          ++a_heard_after;
          a_reacquired = a_reacquired || h.sample.event == SignalEvent::kReacquired;
        }
      } else {
        ++b_heard;
        b_ids.insert(h.sample.signal_id);
      }
    }
  }
  ASSERT_TRUE(a_id.has_value());
  EXPECT_EQ(b_ids.count(*a_id), 0U) << "the stranger's pulses went to the lost track";
  EXPECT_EQ(b_ids.size(), 1U);
  EXPECT_GE(b_heard, 20U);
  EXPECT_GE(a_heard_after, 10U);
  EXPECT_TRUE(a_reacquired);
}

// One transmitter split into two signals (two trains on its carrier, here two beacons at one
// spot), both tracks then lost; it pulses again at another phase. Timing cannot say which track
// it is, and both filters explain its field. Once the rescuer's filters name one signal a
// repeat of the other (FieldFit::repeat_of), the pulses go to the other, reacquired; without
// that, to neither: the rescuer stood over such a victim with one sample every 20-50 s (4
// victims, seed 9, trial 15).
TEST(SignalSeparator, ATransmitterSplitInTwoIsReanchoredOnTheSignalItsRepeatNames) {
  auto run = [](bool repeat_named) {
    SimulationConfig config;
    BeaconReceiver receiver(config, 21);
    const Vec3 position(12.0, 0.0, -1.0), moment(0.01, 0.0, 0.01);
    const Beacon first = same_carrier_beacon(position, moment, 0.1, -30.0);
    const Beacon second = same_carrier_beacon(position, moment, 0.6, -30.0);
    const Beacon again = same_carrier_beacon(position, moment, 0.35, -30.0);
    std::optional<std::uint32_t> first_id, second_id;
    receiver.separator().set_consistency(
        [&](std::uint32_t signal, const Vec3&, const Vec3&, std::uint8_t) -> std::optional<FieldFit> {
          FieldFit fit{0.0, 1.0};  // both filters explain the field alike
          if (repeat_named && second_id && first_id && signal == *second_id) fit.repeat_of = *first_id;
          return fit;
        });
    ReceiverPose pose;
    pose.position = Vec3(0.0, 0.0, 1.0);
    std::map<std::uint32_t, int> heard_after;
    bool reacquired = false;
    for (int k = 0; k < 45; ++k) {
      std::vector<Beacon> beacons;
      if (k < 15) beacons = {first, second};
      if (k >= 25) beacons = {again};
      const Listening heard = receiver.listen(pose, beacons, k, 1.0);
      for (const auto& h : heard.samples) {
        if (k < 15 && h.transmitter) (*h.transmitter == 0 ? first_id : second_id) = h.sample.signal_id;
        if (k < 25) continue;
        ++heard_after[h.sample.signal_id];
        reacquired = reacquired || h.sample.event == SignalEvent::kReacquired;
      }
    }
    EXPECT_TRUE(first_id && second_id && *first_id != *second_id) << "the two trains were not two tracks";
    return std::make_tuple(first_id.value_or(0), heard_after, reacquired);
  };
  const auto [first_id, heard, reacquired] = run(true);
  ASSERT_EQ(heard.size(), 1U) << "the pulses went to more than one signal, or to none";
  EXPECT_EQ(heard.begin()->first, first_id);
  EXPECT_GE(heard.begin()->second, 15);
  EXPECT_TRUE(reacquired);
  const auto [unused_id, heard_unnamed, unused_reacquired] = run(false);
  EXPECT_TRUE(heard_unnamed.empty()) << "two lost tracks that nothing tells apart: given to one of them";
}

// Two transmitters 0.5 Hz apart, their pulses overlapping almost entirely: the detector cannot
// resolve them; the pulse is flagged blended or elliptical and never becomes a field sample.
TEST(SignalSeparator, UnresolvableBlendGivesNoSample) {
  SimulationConfig config;
  BeaconReceiver receiver(config, 13);
  std::vector<Beacon> beacons(2);
  beacons[0].position = Vec3(10.0, 0.0, -1.0);
  beacons[0].moment = Vec3(0.01, 0.0, 0.01);
  beacons[1].position = Vec3(8.0, -4.0, -1.0);
  beacons[1].moment = Vec3(0.0, 0.012, 0.004);
  for (auto& b : beacons) {
    b.timing.period_s = 1.0;
    b.timing.on_time_s = 0.15;
    b.timing.first_start_s = 0.3;
  }
  beacons[0].timing.carrier_offset_hz = 20.0;
  beacons[1].timing.carrier_offset_hz = 20.5;
  beacons[1].timing.first_start_s = 0.31;
  ReceiverPose pose;
  pose.position = Vec3(0.0, 0.0, 1.0);
  std::uint32_t samples = 0, unattributed = 0;
  for (int k = 0; k < 8; ++k) {
    const Listening heard = receiver.listen(pose, beacons, k, 1.0);
    samples += static_cast<std::uint32_t>(heard.samples.size());
    unattributed += heard.report.unattributed;
  }
  EXPECT_EQ(samples, 0U);
  EXPECT_GE(unattributed, 6U);
}

// Two devices, each with its own oscillator error, hear the same four transmitters: one pair on
// one period 37 Hz apart (victims A and B of config/missions/four-within-5m.yaml), the others on
// periods 5 ms off. Each device's signatures are off by its own oscillator, and say so: one
// transmitter's signatures agree across the devices within their sigmas, and any two of the four
// differ beyond them.
TEST(SignalSeparator, TwoDevicesSignaturesTellTheSameTransmitterFromAnother) {
  SimulationConfig config;
  config.receiver.kind = ReceiverKind::kRealistic;
  std::vector<Beacon> beacons(4);
  const double carriers[4] = {-12.0, 25.0, 3.0, -40.0};
  const double periods[4] = {1.000, 1.000, 1.005, 0.995};
  for (int i = 0; i < 4; ++i) {
    beacons[i].position = Vec3(18.0 + 1.5 * i, 2.0 * i - 3.0, -1.0 - 0.3 * i);
    beacons[i].moment = Vec3(0.01, 0.004 * i, 0.006);
    beacons[i].timing.period_s = periods[i];
    beacons[i].timing.on_time_s = 0.1;
    beacons[i].timing.first_start_s = 0.05 + 0.23 * i;
    beacons[i].timing.carrier_offset_hz = carriers[i];
  }
  BeaconReceiver first(config, 21), second(config, 22);
  ASSERT_GT(std::fabs(first.oscillator_offset_hz() - second.oscillator_offset_hz()), 1.0);
  ReceiverPose pose;
  pose.position = Vec3(0.0, 0.0, 1.0);
  // Per device and transmitter: the latest signature of the signal that follows it.
  std::map<std::size_t, responder::TransmitterSignature> of_first, of_second;
  for (int k = 0; k < 20; ++k) {
    for (auto* device : {&first, &second}) {
      const Listening heard = device->listen(pose, beacons, k, 1.0);
      for (const auto& m : to_measurements(heard, "r", static_cast<std::uint64_t>(k) + 1, k, std::nullopt)) {
        const auto beacon = device->majority_beacon_of_signal(m.signal_id);
        if (beacon && m.transmitter.known()) (device == &first ? of_first : of_second)[*beacon] = m.transmitter;
      }
    }
  }
  ASSERT_EQ(of_first.size(), 4U);
  ASSERT_EQ(of_second.size(), 4U);
  for (std::size_t i = 0; i < 4; ++i) {
    const auto& a = of_first[i];
    ASSERT_TRUE(a.carrier_known() && a.period_known());
    // Heard against the device's oscillator, and stated with its tolerance.
    EXPECT_NEAR(a.carrier_offset_hz, carriers[i] - first.oscillator_offset_hz(), 1.0);
    EXPECT_GE(a.carrier_sigma_hz, 1e-5 * 457000.0);
    EXPECT_NEAR(a.period_s, periods[i], 3.0 * a.period_sigma_s);
    EXPECT_EQ(responder::compare_signatures(a, of_second[i], 0.999, true), responder::SignatureMatch::kAlike) << i;
    for (std::size_t j = 0; j < 4; ++j) {
      if (j == i) continue;
      EXPECT_EQ(responder::compare_signatures(a, of_second[j], 0.9999), responder::SignatureMatch::kDistinct)
          << i << " vs " << j;
    }
  }
}

// A track lost and reanchored on another transmitter's pulses (its carrier, another period) has
// followed two timings: its signature states no period. Reanchored on its own transmitter's
// pulses, it states its period again.
TEST(SignalSeparator, ATrackReanchoredOnAnotherTimingStatesNoPeriod) {
  for (const bool other : {true, false}) {
    SimulationConfig config;
    config.receiver.kind = ReceiverKind::kRealistic;
    BeaconReceiver receiver(config, 31);
    Beacon first = same_carrier_beacon(Vec3(12.0, 0.0, -1.0), Vec3(0.01, 0.0, 0.01), 0.1, 10.0);
    Beacon second = same_carrier_beacon(Vec3(14.0, -3.0, -1.2), Vec3(0.0, 0.012, 0.004), 0.45, 10.1);
    second.timing.period_s = 1.006;
    const Beacon& later = other ? second : first;
    ReceiverPose pose;
    pose.position = Vec3(0.0, 0.0, 1.0);
    std::set<std::uint32_t> signals;
    for (int k = 0; k < 40; ++k) {
      // First heard alone for 10 s, then silence (lost after 5 s), then `later` alone.
      std::vector<Beacon> on;
      if (k < 10) on.push_back(first);
      if (k >= 18) on.push_back(later);
      for (const auto& h : receiver.listen(pose, on, k, 1.0).samples) signals.insert(h.sample.signal_id);
      if (k == 9) {
        ASSERT_EQ(signals.size(), 1U);
        const auto s = receiver.separator().signature_of(*signals.begin());
        ASSERT_TRUE(s && s->period_known());
        EXPECT_NEAR(s->period_s, 1.0, 3.0 * s->period_sigma_s);
      }
    }
    ASSERT_EQ(signals.size(), 1U) << "reanchored, not a new signal";
    const auto s = receiver.separator().signature_of(*signals.begin());
    ASSERT_TRUE(s.has_value());
    EXPECT_TRUE(s->carrier_known());
    if (other) {
      EXPECT_FALSE(s->period_known()) << "stated " << s->period_s << " +- " << s->period_sigma_s;
    } else {
      ASSERT_TRUE(s->period_known());
      EXPECT_NEAR(s->period_s, 1.0, 3.0 * s->period_sigma_s);
    }
  }
}

}  // namespace
}  // namespace sarloc::avalanche
