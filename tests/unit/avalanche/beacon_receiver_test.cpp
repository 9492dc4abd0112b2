// The simulated receiver device (BeaconReceiver): what it hears of a transmitter as it walks.
#include "sarloc/core/avalanche/beacon_receiver.hpp"

#include <gtest/gtest.h>

#include <map>
#include <vector>

namespace sarloc::avalanche {
namespace {

// A transmitter whose period is within a fraction of a millisecond of the device's 1 s window
// (issue 58, seed 20 trial 36): with windows cut apart its pulses start too near a window's start
// to begin a track and then straddle the windows' edge for minutes, never heard 4 m away; a device
// that listens without gaps hears it from the first pulses.
TEST(BeaconReceiverTest, APeriodEqualToTheWindowIsHeardWhenListeningWithoutGaps) {
  std::vector<Beacon> beacons(1);
  beacons[0].position = Vec3(4.0, 1.0, -0.8);
  beacons[0].moment = Vec3(-0.0099, 0.0020, 0.0102);
  beacons[0].timing.period_s = 0.9997;
  beacons[0].timing.on_time_s = 0.1088;
  beacons[0].timing.first_start_s = 0.0086;
  beacons[0].timing.carrier_offset_hz = 30.8;
  std::map<bool, std::size_t> samples;
  for (const bool continuous : {false, true}) {
    SimulationConfig config;
    config.receiver.continuous_listening = continuous;
    BeaconReceiver receiver(config, 21);
    for (int k = 0; k < 48; ++k) {
      ReceiverPose pose;  // walking towards the victim from 50 m, a metre a second
      pose.position = beacons[0].position + Vec3(50.0 - k, 0.0, 1.8);
      samples[continuous] += receiver.listen(pose, beacons, k, 1.0).samples.size();
    }
  }
  EXPECT_LE(samples[false], 2U) << "cut windows: the victim all but unheard (what this test keeps in view)";
  EXPECT_GE(samples[true], 35U) << "continuous: a sample nearly every second";
}

// The evaluation's truth of a sample's transmitter (HeardSample::transmitter, and so the majority
// that scores a FOUND and the wrong attributions) is what the detector's joint fit put into it. A
// weak pulse whose last 70 ms a 2.5 times stronger pulse 6 Hz away overlaps is resolved by the
// detector at its own carrier; labelled by overlap energy, as before, its samples were the strong
// transmitter's, with a truth NIS in the hundreds (4 victims, seed 11, trial 0).
TEST(BeaconReceiverTest, ASampleIsTheTransmitterWhosePulseTheDetectorFitted) {
  std::vector<Beacon> beacons(2);
  beacons[0].position = Vec3(0.0, 0.0, -1.2);  // weak, first
  beacons[0].moment = Vec3(0.006, 0.0, 0.005);
  beacons[0].timing.carrier_offset_hz = 29.1;
  beacons[0].timing.first_start_s = 0.30;
  beacons[1].position = Vec3(1.3, 0.4, -1.8);  // strong, 0.1 s later
  beacons[1].moment = Vec3(0.0, 0.014, 0.012);
  beacons[1].timing.carrier_offset_hz = 22.9;
  beacons[1].timing.first_start_s = 0.40;
  for (Beacon& b : beacons) {
    b.timing.period_s = 1.0;
    b.timing.on_time_s = 0.17;
  }
  BeaconReceiver receiver(SimulationConfig{}, 5);
  std::map<std::size_t, std::size_t> samples_of;
  std::size_t mixed = 0;
  for (int k = 0; k < 30; ++k) {
    ReceiverPose pose;
    pose.position = Vec3(6.0, 3.0, 1.0);
    for (const HeardSample& h : receiver.listen(pose, beacons, k, 1.0).samples) {
      ASSERT_TRUE(h.transmitter.has_value());
      ASSERT_TRUE(h.truth_nis.has_value());
      ++samples_of[*h.transmitter];
      const int axes = __builtin_popcount(h.sample.valid_axes);
      EXPECT_LT(*h.truth_nis / axes, 9.0)
          << "window " << k << ": a sample labelled transmitter " << *h.transmitter << " that does not hold its field";
      if (h.mixed_with && h.mixed_energy_ratio >= 0.1) ++mixed;
    }
  }
  EXPECT_GE(samples_of[0], 15U) << "the weak transmitter, resolved, is heard in most windows";
  EXPECT_GE(samples_of[1], 15U);
  EXPECT_EQ(mixed, 0U) << "each pulse was fitted on its own: nothing of the other is summed into it";
}

}  // namespace
}  // namespace sarloc::avalanche
