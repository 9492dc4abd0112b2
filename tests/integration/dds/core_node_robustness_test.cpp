// A stream of malformed samples leaves sarloc-core's node running and the other rescuers'
// estimates exactly as they would have been without it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "sarloc/core/mission/simulated_rescuer.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/core_node.hpp"
#include "support/dds_test_domains.hpp"
#include "support/dds_test_helpers.hpp"

namespace sarloc::dds {
namespace {

using namespace std::chrono_literals;

mission::MissionScenario two_victim_scenario() {
  mission::MissionScenario s;
  s.victims = {{"A", Vec3(-10.0, 30.0, -1.0), Vec3(0.01, -0.005, 0.004), {}, {}},
               {"B", Vec3(12.0, 25.0, -1.5), Vec3(-0.004, 0.003, 0.015), {}, {}}};
  s.rescuers = {{"good", "t", Vec3(0.0, 0.0, 0.0), 90.0}};
  s.seed = 11;
  // A sample of every victim every epoch: the daemon's input handling is under test, not separation.
  s.sensors.receiver.kind = avalanche::ReceiverKind::kIdeal;
  return s;
}

avalanche::RescuerSearchConfig small_search() {
  avalanche::RescuerSearchConfig c;
  c.sog.initial_components = 300;  // the test is about robustness, not accuracy: keep it quick
  return c;
}

TEST(CoreNodeRobustness, MalformedStreamNeitherCrashesNorTouchesOtherRescuers) {
  auto daemon_participant = test::make_participant(test::kDomainMalformedInput, "core");
  CoreNodeConfig config;
  config.estimators.avalanche_rescuer = small_search();
  config.warning_interval_s = 60.0;
  auto node = std::make_unique<CoreNode>(daemon_participant, config);

  auto device = test::make_participant(test::kDomainMalformedInput, "devices");
  Writer<::sarloc::FieldMeasurement> measurements(device);
  Writer<::sarloc::Odometry> odometry(device);
  auto attacker_participant = test::make_participant(test::kDomainMalformedInput, "attacker");
  Writer<::sarloc::FieldMeasurement> bad_measurements(attacker_participant);
  Writer<::sarloc::Odometry> bad_odometry(attacker_participant);

  std::mutex mutex;
  std::condition_variable cv;
  std::map<std::pair<std::uint32_t, std::uint64_t>, ::sarloc::VictimEstimate> received;
  Reader<::sarloc::VictimEstimate> estimates(device, [&](const ::sarloc::VictimEstimate& e, const auto&) {
    if (e.rescuer_id().to_string() != "good") return;
    std::lock_guard<std::mutex> lock(mutex);
    received[{e.signal_id(), e.measurement_sequence()}] = e;
    cv.notify_all();
  });
  ASSERT_TRUE(measurements.wait_for_readers(1, 10s));
  ASSERT_TRUE(odometry.wait_for_readers(1, 10s));
  ASSERT_TRUE(bad_measurements.wait_for_readers(1, 10s));
  ASSERT_TRUE(bad_odometry.wait_for_readers(1, 10s));
  ASSERT_TRUE(estimates.wait_for_writers(1, 10s));

  const auto scenario = two_victim_scenario();
  mission::SimulatedRescuer sim(scenario, "good");
  avalanche::RescuerSearch expected("good", small_search());  // what the daemon must compute
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  std::size_t malformed_sent = 0;
  std::vector<avalanche::FieldMeasurement> previous;
  constexpr int kEpochs = 12;
  for (int k = 0; k < kEpochs; ++k) {
    const TimestampNs stamp = 1'000'000'000LL * (k + 1);
    if (k > 0) {
      auto o = sim.walk(0.0, 1.0, stamp - 1'000'000'000LL, stamp);
      ASSERT_FALSE(expected.add_odometry(o).has_value());
      ASSERT_TRUE(odometry.write(to_idl(o)));
    }
    const auto epoch = sim.measure(stamp);
    ASSERT_FALSE(epoch.empty());
    for (const auto& m : epoch) {
      ASSERT_TRUE(std::holds_alternative<avalanche::SearchUpdate>(expected.process(m)));
      ASSERT_TRUE(measurements.write(to_idl(m)));
    }
    {
      std::unique_lock<std::mutex> lock(mutex);
      ASSERT_TRUE(cv.wait_for(lock, 10s, [&] {
        for (const auto& m : epoch) {
          if (received.count({m.signal_id, m.sequence}) == 0) return false;
        }
        return true;
      })) << "no estimate for epoch " << k;
    }

    // The attacker: every kind of bad sample, for another rescuer and replayed for this one.
    auto bad = to_idl(epoch.front());
    bad.rescuer_id("bad");
    bad.sequence_number(100 + k);
    auto nan_field = bad;
    nan_field.field().x(nan);
    auto inf_noise = bad;
    inf_noise.sequence_number(200 + k);
    inf_noise.noise_stddev().y(inf);
    auto absurd = bad;
    absurd.sequence_number(300 + k);
    absurd.field().z(1e6);
    auto no_id = bad;
    no_id.rescuer_id("");
    std::vector<::sarloc::FieldMeasurement> bad_fields{nan_field, inf_noise, absurd, no_id};
    for (const auto& m : epoch) bad_fields.push_back(to_idl(m));          // duplicate sequence of 'good'
    for (const auto& m : previous) bad_fields.push_back(to_idl(m));       // stale sequence of 'good'
    for (const auto& m : bad_fields) ASSERT_TRUE(bad_measurements.write(m));
    malformed_sent += bad_fields.size();

    ::sarloc::Odometry bad_odo;  // 'good' itself, replaying its last odometry sequence or an older one
    bad_odo.rescuer_id("good");
    bad_odo.sequence_number(static_cast<std::uint64_t>(std::max(1, k - 1)));
    bad_odo.interval_start(stamp - 1'000'000'000LL);
    bad_odo.interval_end(stamp);
    auto huge_step = bad_odo;
    huge_step.rescuer_id("bad");
    huge_step.sequence_number(1000 + k);
    huge_step.translation().x(500.0);
    auto nan_cov = huge_step;
    nan_cov.sequence_number(2000 + k);
    nan_cov.translation().x(0.5);
    nan_cov.covariance()[7] = nan;
    auto bad_enum = huge_step;
    bad_enum.sequence_number(3000 + k);
    bad_enum.source(static_cast<::sarloc::OdometrySource>(99));
    std::vector<::sarloc::Odometry> bad_odos{huge_step, nan_cov, bad_enum};
    if (k > 0) bad_odos.push_back(bad_odo);  // before its first odometry, 'good' has nothing to replay
    for (const auto& o : bad_odos) ASSERT_TRUE(bad_odometry.write(o));
    malformed_sent += bad_odos.size();
    // Let the daemon take all of them before the next genuine epoch, so each is refused for
    // a known reason (a replay arriving after the next epoch would be "backwards" instead).
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    while (node->counters().rejected < malformed_sent && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(5ms);
    }
    ASSERT_EQ(node->counters().rejected, malformed_sent) << "epoch " << k;
    previous = epoch;
  }

  // Every estimate of 'good' is exactly what a search without the attacker computes.
  for (const auto& [key, e] : received) {
    const auto expected_estimate = expected.estimate(key.first);
    ASSERT_TRUE(expected_estimate.has_value());
    if (key.second != static_cast<std::uint64_t>(kEpochs)) continue;  // the last epoch's is what `expected` holds
    EXPECT_EQ(to_core(e).relative.position, expected_estimate->relative.position) << "signal " << key.first;
    EXPECT_EQ(to_core(e).relative.covariance, expected_estimate->relative.covariance);
    EXPECT_EQ(e.live_components(), expected_estimate->live_components);
  }

  // Still alive, and every bad sample was counted by reason.
  std::this_thread::sleep_for(300ms);
  const auto counters = node->counters();
  EXPECT_EQ(counters.rejected, malformed_sent);
  for (const char* reason : {"invalid_value", "duplicate_sequence", "sequence_backwards", "absurd_motion",
                             "unknown_rescuer"}) {
    EXPECT_GT(counters.by_reason.count(reason), 0U) << "no rejection counted as " << reason;
  }
  EXPECT_EQ(node->rescuers_served(), 2U) << "'good' and 'bad' (its valid-looking samples were refused)";
}

// A rescuer's device restarted mid-search numbers its steps and samples from 1 again, and its
// signals afresh. The daemon serves it afresh from its first step after the restart, instead of
// refusing all it sends as numbered backwards until the responder's state goes idle (300 s).
TEST(CoreNodeRobustness, ARestartedDeviceIsServedAfreshNotRefusedUntilIdle) {
  auto daemon_participant = test::make_participant(test::kDomainDeviceRestart, "core");
  CoreNodeConfig config;
  config.estimators.avalanche_rescuer = small_search();
  auto node = std::make_unique<CoreNode>(daemon_participant, config);
  auto device = test::make_participant(test::kDomainDeviceRestart, "good");
  Writer<::sarloc::FieldMeasurement> measurements(device);
  Writer<::sarloc::Odometry> odometry(device);
  std::mutex mutex;
  std::condition_variable cv;
  std::set<std::pair<TimestampNs, std::uint64_t>> answered;  // (stamp, sequence) of each estimate
  Reader<::sarloc::VictimEstimate> estimates(device, [&](const ::sarloc::VictimEstimate& e, const auto&) {
    if (e.rescuer_id().to_string() != "good") return;
    std::lock_guard<std::mutex> lock(mutex);
    answered.insert({e.stamp(), e.measurement_sequence()});
    cv.notify_all();
  });
  ASSERT_TRUE(measurements.wait_for_readers(1, 10s));
  ASSERT_TRUE(odometry.wait_for_readers(1, 10s));
  ASSERT_TRUE(estimates.wait_for_writers(1, 10s));

  // Two sessions of the same device: the second starts 100 s after the first's last epoch.
  const auto run_session = [&](TimestampNs first_stamp, int epochs, int answered_from) {
    mission::SimulatedRescuer sim(two_victim_scenario(), "good");
    for (int k = 0; k < epochs; ++k) {
      const TimestampNs stamp = first_stamp + 1'000'000'000LL * k;
      if (k > 0) {
        ASSERT_TRUE(odometry.write(to_idl(sim.walk(0.0, 1.0, stamp - 1'000'000'000LL, stamp))));
      }
      const auto epoch = sim.measure(stamp);
      for (const auto& m : epoch) ASSERT_TRUE(measurements.write(to_idl(m)));
      if (k < answered_from) continue;
      std::unique_lock<std::mutex> lock(mutex);
      ASSERT_TRUE(cv.wait_for(lock, 10s,
                              [&] {
                                for (const auto& m : epoch) {
                                  if (answered.count({m.stamp, m.sequence}) == 0) return false;
                                }
                                return true;
                              }))
          << "no estimate for epoch " << k << " of the session from " << first_stamp;
    }
  };
  run_session(1'000'000'000LL, 6, 0);
  // Its first epoch has no step yet: its samples are refused as numbered backwards; its first
  // step says the device restarted, and from then on it is answered.
  run_session(106'000'000'000LL, 6, 1);
  EXPECT_LE(node->counters().rejected, 2U) << "at most the restarted session's first samples";
}

}  // namespace
}  // namespace sarloc::dds
