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

}  // namespace
}  // namespace sarloc::avalanche
