// Who sarloc-core keeps state for: its roster decides inside DDS (responder_filter.hpp), so a
// publisher cycling through ids nobody serves neither takes the reader's instances nor stops
// a real rescuer; idle state is released and rebuilt when the rescuer is heard again.
#include <gtest/gtest.h>

#include <condition_variable>
#include <map>
#include <mutex>

#include "sarloc/core/mission/simulated_rescuer.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/core_node.hpp"
#include "support/dds_test_domains.hpp"
#include "support/dds_test_helpers.hpp"

namespace sarloc::dds {
namespace {

using namespace std::chrono_literals;

mission::MissionScenario one_victim_scenario() {
  mission::MissionScenario s;
  s.victims = {{"A", Vec3(-5.0, 25.0, -1.0), Vec3(0.01, -0.005, 0.004), {}, {}}};
  s.rescuers = {{"good", "t", Vec3(0.0, 0.0, 0.0), 90.0}};
  s.seed = 5;
  // A sample of every victim every epoch: the daemon's input handling is under test, not separation.
  s.sensors.receiver.kind = avalanche::ReceiverKind::kIdeal;
  return s;
}

CoreNodeConfig small_node(bool open, double idle_evict_s) {
  CoreNodeConfig config;
  config.estimators.avalanche_rescuer.sog.initial_components = 300;  // about admission, not accuracy
  config.roster.open = open;
  config.roster.listed = {"good"};
  config.roster.idle_evict_s = idle_evict_s;
  config.status_period_s = 0.2;
  config.warning_interval_s = 60.0;
  return config;
}

// The rescuer "good": publishes epochs and waits for the daemon's estimates of each.
class GoodRescuer {
 public:
  explicit GoodRescuer(std::uint32_t domain)
      : participant_(test::make_participant(domain, "good")),
        measurements_(participant_),
        odometry_(participant_),
        estimates_(participant_, [this](const ::sarloc::VictimEstimate& e, const auto&) {
          if (e.rescuer_id().to_string() != "good") return;
          std::lock_guard<std::mutex> lock(mutex_);
          answered_.insert(e.measurement_sequence());
          cv_.notify_all();
        }),
        scenario_(one_victim_scenario()),
        sim_(scenario_, "good") {}

  bool matched() {
    return measurements_.wait_for_readers(1, 10s) && odometry_.wait_for_readers(1, 10s) &&
           estimates_.wait_for_writers(1, 10s);
  }

  /// Epoch k (stamps k seconds): odometry from the previous epoch, then the field samples;
  /// true once every sample of it was answered.
  bool epoch(int k) {
    const TimestampNs stamp = 1'000'000'000LL * k;
    if (k > 1 && !odometry_.write(to_idl(sim_.walk(0.0, 1.0, stamp - 1'000'000'000LL, stamp)))) return false;
    const auto samples = sim_.measure(stamp);
    if (samples.empty()) return false;
    for (const auto& m : samples) {
      if (!measurements_.write(to_idl(m))) return false;
    }
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_for(lock, 10s, [&] {
      for (const auto& m : samples) {
        if (answered_.count(m.sequence) == 0) return false;
      }
      return true;
    });
  }

  avalanche::FieldMeasurement sample_at(TimestampNs stamp) {
    mission::SimulatedRescuer probe(scenario_, "good");
    return probe.measure(stamp).front();
  }

 private:
  std::shared_ptr<Participant> participant_;
  Writer<::sarloc::FieldMeasurement> measurements_;
  Writer<::sarloc::Odometry> odometry_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::set<std::uint64_t> answered_;
  Reader<::sarloc::VictimEstimate> estimates_;
  mission::MissionScenario scenario_;
  mission::SimulatedRescuer sim_;
};

TEST(CoreNodeAdmission, IdsOffTheRosterTakeNoReaderInstanceAndTheRescuerIsStillServed) {
  auto node = std::make_unique<CoreNode>(test::make_participant(test::kDomainAdmissionRoster, "core"), small_node(false, 300));
  GoodRescuer good(test::kDomainAdmissionRoster);
  auto intruder_participant = test::make_participant(test::kDomainAdmissionRoster, "intruder");
  Writer<::sarloc::FieldMeasurement> intruder(intruder_participant);
  ASSERT_TRUE(good.matched());
  ASSERT_TRUE(intruder.wait_for_readers(1, 10s));

  // As many distinct ids as the field reader has instances (topics.xml: 1024). Were they let
  // into its history, the rescuer's own keys would find no instance left.
  constexpr std::uint64_t kIntruderIds = 1024;
  auto fake = to_idl(good.sample_at(1'000'000'000LL));
  for (std::uint64_t k = 0; k < kIntruderIds; ++k) {
    fake.rescuer_id("intruder-" + std::to_string(k));
    ASSERT_TRUE(intruder.write(fake)) << "intruder sample " << k;
  }
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  while (node->counters().rejected < kIntruderIds && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(10ms);
  }
  ASSERT_EQ(node->counters().rejected, kIntruderIds);
  EXPECT_EQ(node->counters().by_reason.at("unknown_rescuer"), kIntruderIds);

  for (int k = 1; k <= 5; ++k) ASSERT_TRUE(good.epoch(k)) << "the listed rescuer was not answered in epoch " << k;
  EXPECT_EQ(node->rescuers_served(), 1U) << "state for the listed rescuer only";
}

TEST(CoreNodeAdmission, IdleStateIsReleasedAndRebuiltWhenTheRescuerIsHeardAgain) {
  auto node = std::make_unique<CoreNode>(test::make_participant(test::kDomainAdmissionEviction, "core"), small_node(true, 1.0));
  GoodRescuer good(test::kDomainAdmissionEviction);
  ASSERT_TRUE(good.matched());
  for (int k = 1; k <= 3; ++k) ASSERT_TRUE(good.epoch(k));
  EXPECT_EQ(node->rescuers_served(), 1U);
  std::this_thread::sleep_for(1800ms);  // idle for longer than idle_evict_s (1 s), status period 0.2 s
  ASSERT_TRUE(good.epoch(4)) << "not served again after its idle state was released";
  EXPECT_EQ(node->rescuers_served(), 2U) << "its state was not released and rebuilt";
}

// A daemon, the rescuer "good" it serves from epoch 1 on, and the rescuer "late" who comes after.
struct GoodThenLate {
  GoodThenLate(std::uint32_t domain, const CoreNodeConfig& config)
      : node(std::make_unique<CoreNode>(test::make_participant(domain, "core"), config)),
        good(domain),
        late_participant(test::make_participant(domain, "late")),
        late(late_participant) {}
  /// Everyone matched, and "good" answered in epoch 1.
  bool ready() { return good.matched() && late.wait_for_readers(1, 10s) && good.epoch(1); }
  /// A sample of "late" (stamp 2 s).
  ::sarloc::FieldMeasurement late_sample() {
    auto sample = to_idl(good.sample_at(2'000'000'000LL));
    sample.rescuer_id("late");
    return sample;
  }
  std::uint64_t daemon_busy() const { return node->counters().rejected_for("daemon_busy"); }

  std::unique_ptr<CoreNode> node;
  GoodRescuer good;
  std::shared_ptr<Participant> late_participant;
  Writer<::sarloc::FieldMeasurement> late;
};

// Overload (issue 64, item 5): while a worker's queue holds samples too long, a new rescuer is
// refused by reason and the one served already is answered on. "Too long" is 1 us here, so
// that the first sample's own hand-over to the worker closes the gate.
TEST(CoreNodeAdmission, ABusyDaemonRefusesANewRescuerByReasonAndServesTheAdmittedOne) {
  auto config = small_node(true, 300);
  config.busy.max_wait_s = 1e-6;
  config.busy.hold_s = 600.0;
  GoodThenLate two(test::kDomainAdmissionBusy, config);
  ASSERT_TRUE(two.ready());

  auto sample = two.late_sample();
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  for (std::uint64_t k = 0; two.daemon_busy() < 3 && std::chrono::steady_clock::now() < deadline; ++k) {
    sample.sequence_number(1000 + k);
    ASSERT_TRUE(two.late.write(sample));
    std::this_thread::sleep_for(50ms);
  }
  EXPECT_GE(two.daemon_busy(), 3U) << "the new rescuer was not refused as daemon_busy";
  for (int k = 2; k <= 5; ++k) ASSERT_TRUE(two.good.epoch(k)) << "the admitted rescuer was not answered in epoch " << k;
  EXPECT_EQ(two.node->rescuers_served(), 1U) << "state for the admitted rescuer only";
}

// Overload of those served (issue 64, item 5): when a sample waits longer than
// core.busy_shed_wait_s, the daemon releases the responder it admitted last, with its waiting
// samples, and serves the first on. Here "late", admitted after "good", sends a burst of 600
// samples on five signals (odometry_wait_s 0: each is processed at once), which a worker cannot
// take within the bound (20 ms): "late" is released (its waiting samples counted daemon_busy),
// and "good" keeps its state (no new one is made for it) and is answered. Without the release,
// nothing is counted. The gate's other signs are off, so that only the release refuses anything.
TEST(CoreNodeAdmission, AnOverloadedDaemonReleasesTheResponderAdmittedLastAndServesTheFirst) {
  auto config = small_node(true, 300);
  config.workers = 1;
  config.odometry_wait_s = 0.0;
  config.busy.max_wait_s = 0.0;
  config.busy.max_utilisation = 0.0;
  config.busy.shed_wait_s = 0.02;
  GoodThenLate two(test::kDomainAdmissionShed, config);
  ASSERT_TRUE(two.ready());
  // The worker's account of who takes its time forgets "good"'s opening (halved every second),
  // so that "late"'s burst is what it sees when the wait comes.
  std::this_thread::sleep_for(3s);

  auto sample = two.late_sample();
  for (std::uint32_t k = 0; k < 600; ++k) {
    sample.signal_id(1 + k % 5);
    sample.sequence_number(1000 + k);
    sample.stamp(2'000'000'000LL + 10'000'000LL * k);
    ASSERT_TRUE(two.late.write(sample));
  }
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  while (two.daemon_busy() == 0 && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(10ms);
  EXPECT_GE(two.daemon_busy(), 1U) << "no sample of the responder admitted last was released";
  // What was left of the burst has arrived (a sample of "late" after its release makes it a new
  // responder again: a state counted before the snapshot below), and the worker is done with it.
  ASSERT_EQ(two.late.get()->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(20, 0)),
            eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK);
  std::this_thread::sleep_for(1500ms);
  const std::size_t states = two.node->rescuers_served();
  for (int k = 2; k <= 5; ++k) ASSERT_TRUE(two.good.epoch(k)) << "the first rescuer was not answered in epoch " << k;
  EXPECT_EQ(two.node->rescuers_served(), states) << "the first rescuer's state was released and made anew";
}

}  // namespace
}  // namespace sarloc::dds
