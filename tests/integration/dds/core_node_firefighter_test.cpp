// sarloc-core's node serves firefighters next to avalanche rescuers: the mission file names a
// building and the firefighters' reported entries; a device publishes its boot INS odometry
// (FirefighterDevice on a simulated right-hand search) and the daemon answers every step with a
// map-aided ResponderPosition in the incident frame, on the right floor, that tracks the truth.
#include <gtest/gtest.h>

#include <cmath>
#include <condition_variable>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <map>
#include <mutex>
#include <random>
#include <thread>

#include "sarloc/app/floor_plan_yaml.hpp"
#include "sarloc/app/mission_config.hpp"
#include "sarloc/core/estimator/firefighter_device.hpp"
#include "sarloc/core/estimator/make_estimator.hpp"
#include "sarloc/core/firefighter/foot_trajectory.hpp"
#include "sarloc/core/firefighter/imu_error_model.hpp"
#include "sarloc/core/firefighter/search_walk.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/core_node.hpp"
#include "support/dds_test_domains.hpp"
#include "support/dds_test_helpers.hpp"

namespace sarloc::dds {
namespace {

using namespace std::chrono_literals;

constexpr TimestampNs kOrigin = 1'700'000'000'000'000'000;
constexpr double kPi = 3.14159265358979323846;

// A right-hand search of the mission's building from its front door, and the boot odometry a
// FirefighterDevice makes of it on simulated MTi-3 samples.
struct SimulatedSearch {
  firefighter::FootTrajectory foot;
  std::vector<responder::Odometry> odometry;
};

SimulatedSearch simulated_search(const app::MissionConfig& mission, std::uint64_t seed, double duration_s) {
  std::mt19937_64 rng(seed);
  firefighter::SearchWalkConfig walk;
  walk.duration_s = duration_s;
  const auto search = firefighter::generate_search_walk(mission.estimators.firefighter.building->plan(), walk,
                                                        firefighter::Hand::kRight, rng);
  SimulatedSearch out{firefighter::FootTrajectory(search.leader), {}};
  firefighter::ImuErrors errors(firefighter::ImuErrorConfig{}, rng);
  estimator::FirefighterDevice device("ff1", "alpha", estimator::FirefighterDeviceConfig{}, kOrigin);
  for (const auto& ideal : out.foot.imu_samples(100.0)) {
    device.push(errors.apply(ideal, rng));
    if (auto o = device.take_odometry()) out.odometry.push_back(*o);
  }
  return out;
}

// The positions of one responder a participant hears, by stamp.
class HeardPositions {
 public:
  HeardPositions(std::shared_ptr<Participant> participant, std::string responder_id)
      : id_(std::move(responder_id)),
        reader_(std::move(participant), [this](const ::sarloc::ResponderPosition& p, const auto&) {
          if (p.responder_id().to_string() != id_) return;
          std::lock_guard<std::mutex> lock(mutex_);
          const auto r = to_core(p);
          positions_[r.stamp] = r;
          cv_.notify_all();
        }) {}
  /// Waits until positions of `count` stamps were heard; false after `timeout`.
  bool wait_for(std::size_t count, std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_for(lock, timeout, [&] { return positions_.size() >= count; });
  }
  std::map<TimestampNs, responder::ResponderPosition> all() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return positions_;
  }
  bool wait_for_writers(int count, std::chrono::milliseconds timeout) const {
    return reader_.wait_for_writers(count, timeout);
  }

 private:
  std::string id_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::map<TimestampNs, responder::ResponderPosition> positions_;
  Reader<::sarloc::ResponderPosition> reader_;  // last: it calls back as soon as it exists
};

TEST(CoreNodeFirefighter, AnswersBootOdometryWithMapAidedPositionsThatTrackTheSearch) {
  const auto mission =
      app::load_mission_config(std::string(SARLOC_SOURCE_DIR) + "/tests/integration/mission/firefighters.yaml");
  ASSERT_EQ(mission.dds.domain_id, test::kDomainCoreFirefighter);
  auto daemon_participant = test::make_participant(test::kDomainCoreFirefighter, "core");
  auto node = std::make_unique<CoreNode>(daemon_participant, mission.core_config(""));

  auto device_participant = test::make_participant(test::kDomainCoreFirefighter, "ff1");
  Writer<::sarloc::Odometry> odometry(device_participant);
  HeardPositions heard(device_participant, "ff1");
  ASSERT_TRUE(odometry.wait_for_readers(1, 10s));
  ASSERT_TRUE(heard.wait_for_writers(1, 10s));

  // The truth: a right-hand search of the mission's building from its front door.
  const auto search = simulated_search(mission, 21, 120.0);
  const auto& foot = search.foot;
  std::vector<TimestampNs> sent;
  for (const auto& o : search.odometry) {
    ASSERT_TRUE(odometry.write(to_idl(o)));
    sent.push_back(o.interval_end);
    if (sent.size() % 40 == 0) {  // pace: no more than 40 steps ahead of the daemon's answers
      ASSERT_TRUE(heard.wait_for(sent.size() - 10, 10s))
          << heard.all().size() << " answers to " << sent.size() << " steps";
    }
  }
  ASSERT_TRUE(heard.wait_for(sent.size(), 10s)) << heard.all().size() << " answers to " << sent.size() << " steps";
  const auto positions = heard.all();
  const auto& placement = mission.estimators.firefighter;
  const Eigen::Rotation2Dd R(placement.rotation_deg * kPi / 180.0);
  double sum2 = 0.0;
  std::size_t late = 0, confirmed = 0, confirmed_outside = 0;
  for (const auto& [stamp, p] : positions) {
    EXPECT_EQ(p.source, responder::PositionSource::kMapAided);
    EXPECT_EQ(p.floor, 0);
    const double t = 1e-9 * static_cast<double>(stamp - kOrigin);
    const Eigen::Vector2d truth = placement.origin + R * foot.at(t).position.head<2>();
    const Eigen::Vector2d err = p.position.position.head<2>() - truth;
    if (t > 60.0) {
      sum2 += err.squaredNorm();
      ++late;
    }
    if (p.confirmed) {
      ++confirmed;
      const Eigen::Matrix2d P = p.position.covariance.topLeftCorner<2, 2>() + 1e-9 * Eigen::Matrix2d::Identity();
      confirmed_outside += err.dot(P.ldlt().solve(err)) > 9.21 ? 1 : 0;
    }
  }
  ASSERT_GT(late, 100U);
  EXPECT_LT(std::sqrt(sum2 / static_cast<double>(late)), 1.0) << "RMSE after the first minute, incident frame";
  EXPECT_GT(confirmed, positions.size() / 2);
  EXPECT_LE(confirmed_outside, confirmed / 50 + 1);
  EXPECT_EQ(node->counters().rejected, 0U) << "nothing refused";
}

// A firefighter who falls silent: the daemon's position writer forgets his older positions
// after its lifespan (30 s; docs/topics.md, "Lifespan bounds what every heartbeat carries"),
// but writes his last one again within it, so a reader that joins later (a restarted incident
// command, a dashboard opened late) still gets where he was last known, and only that.
TEST(CoreNodeFirefighter, ASilentFirefightersLastPositionOutlivesTheWritersLifespanAndNothingOlderStays) {
  const auto mission =
      app::load_mission_config(std::string(SARLOC_SOURCE_DIR) + "/tests/integration/mission/firefighters.yaml");
  auto daemon_participant = test::make_participant(test::kDomainPositionRefresh, "core");
  auto node = std::make_unique<CoreNode>(daemon_participant, mission.core_config(""));
  std::chrono::seconds lifespan{0};
  {
    Writer<::sarloc::ResponderPosition> same_profile(daemon_participant);
    const auto& d = same_profile.get()->get_qos().lifespan().duration;
    ASSERT_NE(d, eprosima::fastrtps::c_TimeInfinite) << "the daemon's position writer has no lifespan";
    lifespan = std::chrono::seconds(d.seconds + (d.nanosec > 0 ? 1 : 0));
  }
  std::mutex mutex;
  std::condition_variable cv;
  std::map<TimestampNs, responder::ResponderPosition> live;
  TimestampNs newest = 0;
  {
    auto device_participant = test::make_participant(test::kDomainPositionRefresh, "ff1");
    Writer<::sarloc::Odometry> odometry(device_participant);
    Reader<::sarloc::ResponderPosition> reader(device_participant,
                                               [&](const ::sarloc::ResponderPosition& p, const auto&) {
                                                 std::lock_guard<std::mutex> lock(mutex);
                                                 const auto r = to_core(p);
                                                 live[r.stamp] = r;
                                                 cv.notify_all();
                                               });
    ASSERT_TRUE(odometry.wait_for_readers(1, 10s));
    const auto search = simulated_search(mission, 22, 20.0);
    for (const auto& o : search.odometry) ASSERT_TRUE(odometry.write(to_idl(o)));
    const std::size_t sent = search.odometry.size();
    std::unique_lock<std::mutex> lock(mutex);
    ASSERT_TRUE(cv.wait_for(lock, 10s, [&] { return live.size() >= sent; })) << live.size() << " answers to " << sent;
    ASSERT_GT(live.size(), 10U);
    newest = live.rbegin()->first;
  }  // the device is gone: ff1 falls silent
  std::this_thread::sleep_for(lifespan + 2s);

  auto late_participant = test::make_participant(test::kDomainPositionRefresh, "late");
  std::vector<responder::ResponderPosition> late;
  Reader<::sarloc::ResponderPosition> late_reader(late_participant,
                                                  [&](const ::sarloc::ResponderPosition& p, const auto&) {
                                                    std::lock_guard<std::mutex> lock(mutex);
                                                    late.push_back(to_core(p));
                                                    cv.notify_all();
                                                  });
  std::unique_lock<std::mutex> lock(mutex);
  ASSERT_TRUE(cv.wait_for(lock, 10s, [&] { return !late.empty(); })) << "his last position is gone";
  cv.wait_for(lock, 1s, [] { return false; });  // whatever else the history still holds
  for (const auto& p : late) {
    EXPECT_EQ(p.responder_id, "ff1");
    EXPECT_EQ(p.stamp, newest) << "a position older than his last outlived the lifespan";
  }
  EXPECT_DOUBLE_EQ(late.front().position.position.x(), live.rbegin()->second.position.position.x());
  EXPECT_LE(late.size(), 3U) << "copies within one lifespan";
}

// Issue 65: a firefighter in the warehouse whose entry nobody reported (an unknown start), whose
// cloud spends much of the walk between look-alike corridors. The daemon flags each such
// position ambiguous and writes its places beside it with the same stamp, and once with none
// when the ambiguity ends; a reader (the dashboard) pairs them by stamp.
TEST(CoreNodeFirefighter, AnAmbiguousPositionComesWithItsPlacesAndTheirEnd) {
  auto mission =
      app::load_mission_config(std::string(SARLOC_SOURCE_DIR) + "/tests/integration/mission/firefighters.yaml");
  mission.estimators.firefighter.building = std::make_shared<const firefighter::BuildingModel>(
      app::load_floor_plan(std::string(SARLOC_SOURCE_DIR) + "/config/buildings/warehouse-1040.yaml"),
      firefighter::BuildingModelConfig{});
  mission.estimators.firefighter.entry_of.clear();
  auto daemon_participant = test::make_participant(test::kDomainPositionCandidates, "core");
  auto node = std::make_unique<CoreNode>(daemon_participant, mission.core_config(""));

  auto device_participant = test::make_participant(test::kDomainPositionCandidates, "ff1");
  Writer<::sarloc::Odometry> odometry(device_participant);
  std::mutex mutex;
  std::condition_variable cv;
  std::map<TimestampNs, responder::ResponderPosition> positions;
  std::map<TimestampNs, responder::ResponderCandidates> places;
  Reader<::sarloc::ResponderPosition> position_reader(device_participant,
                                                      [&](const ::sarloc::ResponderPosition& p, const auto&) {
                                                        std::lock_guard<std::mutex> lock(mutex);
                                                        const auto r = to_core(p);
                                                        positions[r.stamp] = r;
                                                        cv.notify_all();
                                                      });
  Reader<::sarloc::ResponderCandidates> places_reader(device_participant,
                                                      [&](const ::sarloc::ResponderCandidates& c, const auto&) {
                                                        std::lock_guard<std::mutex> lock(mutex);
                                                        const auto r = to_core(c);
                                                        places[r.stamp] = r;
                                                      });
  ASSERT_TRUE(odometry.wait_for_readers(1, 10s));
  ASSERT_TRUE(position_reader.wait_for_writers(1, 10s));
  ASSERT_TRUE(places_reader.wait_for_writers(1, 10s));

  const auto search = simulated_search(mission, 2, 150.0);
  std::size_t sent = 0;
  for (const auto& o : search.odometry) {
    ASSERT_TRUE(odometry.write(to_idl(o)));
    if (++sent % 40 == 0) {
      std::unique_lock<std::mutex> lock(mutex);
      ASSERT_TRUE(cv.wait_for(lock, 20s, [&] { return positions.size() + 10 >= sent; }));
    }
  }
  std::unique_lock<std::mutex> lock(mutex);
  ASSERT_TRUE(cv.wait_for(lock, 20s, [&] { return positions.size() >= sent; })) << positions.size() << " of " << sent;
  lock.unlock();
  std::this_thread::sleep_for(500ms);  // the last places, on their own topic
  lock.lock();
  std::size_t ambiguous = 0, ends = 0;
  for (const auto& [stamp, p] : positions) {
    const auto it = places.find(stamp);
    if (p.ambiguous) {
      ++ambiguous;
      EXPECT_FALSE(p.converged);
      ASSERT_NE(it, places.end()) << "an ambiguous position at " << stamp << " without its places";
      EXPECT_GE(it->second.candidates.size(), 2U);
      EXPECT_LE(it->second.candidates.size(), 4U);
      for (const auto& c : it->second.candidates) EXPECT_EQ(c.floor, 0);
    } else if (it != places.end()) {
      EXPECT_TRUE(it->second.candidates.empty()) << "places beside a position that is not ambiguous";
      ++ends;
    }
  }
  EXPECT_EQ(places.size(), ambiguous + ends) << "every sample of places is beside a position of its stamp";
  EXPECT_GT(ambiguous, 10U) << "this walk no longer shows an ambiguous cloud";
  EXPECT_EQ(node->counters().rejected, 0U);
}

// Overload (issue 64): a busy daemon admits no new responder, but a firefighter's first step
// from a reported entry is the one start that cannot wait. Refused, the entry is lost with the
// steps before admission, and the filter made later starts spread over the plan (20000
// particles). Here the gate closes on ff2's first sample (a step mid-search: "too long" a wait
// is 1 us), the rescuer r1 is then refused as daemon_busy, and ff1's first step is still
// admitted and answered at the door, as are the steps after it.
TEST(CoreNodeFirefighter, ABusyDaemonStillAdmitsAFirefightersFirstStepFromItsReportedEntry) {
  const auto mission =
      app::load_mission_config(std::string(SARLOC_SOURCE_DIR) + "/tests/integration/mission/firefighters.yaml");
  auto config = mission.core_config("");
  config.busy.max_wait_s = 1e-6;
  config.busy.hold_s = 600.0;
  auto node = std::make_unique<CoreNode>(test::make_participant(test::kDomainAdmissionDoorStart, "core"), config);
  auto device_participant = test::make_participant(test::kDomainAdmissionDoorStart, "devices");
  Writer<::sarloc::Odometry> odometry(device_participant);
  Writer<::sarloc::FieldMeasurement> measurements(device_participant);
  std::mutex mutex;
  std::condition_variable cv;
  std::map<std::string, std::vector<responder::ResponderPosition>> positions;
  Reader<::sarloc::ResponderPosition> reader(device_participant,
                                             [&](const ::sarloc::ResponderPosition& p, const auto&) {
                                               std::lock_guard<std::mutex> lock(mutex);
                                               positions[p.responder_id().to_string()].push_back(to_core(p));
                                               cv.notify_all();
                                             });
  ASSERT_TRUE(odometry.wait_for_readers(1, 10s));
  ASSERT_TRUE(measurements.wait_for_readers(1, 10s));
  ASSERT_TRUE(reader.wait_for_writers(1, 10s));
  const auto answered = [&](const std::string& id, std::size_t n) {
    std::unique_lock<std::mutex> lock(mutex);
    return cv.wait_for(lock, 20s, [&] { return positions[id].size() >= n; });
  };
  const auto busy_refusals = [&] { return node->counters().rejected_for("daemon_busy"); };

  const auto search = simulated_search(mission, 21, 60.0);
  auto mid_search = search.odometry[10];
  mid_search.rescuer_id = "ff2";
  ASSERT_TRUE(odometry.write(to_idl(mid_search)));
  ASSERT_TRUE(answered("ff2", 1)) << "the first responder is admitted while the daemon is idle";

  avalanche::FieldMeasurement m;
  m.rescuer_id = "r1";
  m.signal_id = 1;
  m.stamp = kOrigin;
  m.field = Vec3(0.01, 0.0, 0.0);
  m.noise_stddev = Vec3::Constant(1e-4);
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  for (std::uint64_t k = 1; busy_refusals() == 0 && std::chrono::steady_clock::now() < deadline; ++k) {
    m.sequence = k;
    m.stamp = kOrigin + static_cast<TimestampNs>(k) * 1'000'000'000LL;
    ASSERT_TRUE(measurements.write(to_idl(m)));
    std::this_thread::sleep_for(50ms);
  }
  ASSERT_GE(busy_refusals(), 1U) << "the daemon never became busy: nothing under test";
  // Every measurement of r1 filtered (a refused sample is acknowledged) before the count is taken.
  ASSERT_EQ(measurements.get()->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(10, 0)),
            eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK);
  std::this_thread::sleep_for(100ms);
  const std::uint64_t refused_before = busy_refusals();

  ASSERT_EQ(search.odometry.front().sequence, 1U);
  for (std::size_t k = 0; k < 4; ++k) ASSERT_TRUE(odometry.write(to_idl(search.odometry[k])));
  ASSERT_TRUE(answered("ff1", 4)) << "the door start was refused";
  EXPECT_EQ(busy_refusals(), refused_before) << "a step of ff1 was refused";
  std::lock_guard<std::mutex> lock(mutex);
  const auto& first = positions["ff1"].front();
  EXPECT_LT(std::sqrt(first.position.covariance.topLeftCorner<2, 2>().trace()), 1.5)
      << "not started at the door: a cloud of " << std::sqrt(first.position.covariance.topLeftCorner<2, 2>().trace())
      << " m";
  EXPECT_EQ(node->rescuers_served(), 2U) << "ff2 and ff1; r1 refused";
}

// Issue 64, item 4: a firefighter who moves from one sector's daemon to another's keeps his
// filter. Each daemon serves its sector's partition; the device's steps go to the west daemon,
// then to the east one. The east daemon meets him, asks for his estimator on
// sarloc/rescuer_handover, the west daemon hands its journal over, and releases him once the
// east one says it took him over. From then on the east daemon answers exactly as one daemon
// that never lost him would have (bit for bit: the same filter, its particles' generator
// included); only the answers to the steps sent while the journal was on its way, from the
// fresh filter it ran meanwhile, may differ. A straggler of the switch still reaching the west
// daemon is refused there, not answered from a filter started again.
TEST(CoreNodeFirefighter, AFirefighterWhoMovesToAnotherSectorKeepsHisFilterThere) {
  const auto mission =
      app::load_mission_config(std::string(SARLOC_SOURCE_DIR) + "/tests/integration/mission/firefighters.yaml");
  const auto config_of = [&](const std::string& sector) {
    CoreNodeConfig c = mission.core_config("");
    c.node_id = "core-" + sector;
    c.partitions = {"sector-" + sector};
    c.roster.open = true;
    c.handover_journal_entries = 4096;
    return c;
  };
  auto west = std::make_unique<CoreNode>(test::make_participant(test::kDomainHandover, "core-west"), config_of("west"));
  auto east = std::make_unique<CoreNode>(test::make_participant(test::kDomainHandover, "core-east"), config_of("east"));
  auto device_participant = test::make_participant(test::kDomainHandover, "ff1");
  Writer<::sarloc::Odometry> to_west(device_participant, EndpointOptions::in({"sector-west"}));
  Writer<::sarloc::Odometry> to_east(device_participant, EndpointOptions::in({"sector-east"}));
  HeardPositions heard(device_participant, "ff1");
  ASSERT_TRUE(to_west.wait_for_readers(1, 10s));
  ASSERT_TRUE(to_east.wait_for_readers(1, 10s));
  ASSERT_TRUE(heard.wait_for_writers(2, 10s));

  const auto search = simulated_search(mission, 22, 80.0);
  const auto& steps = search.odometry;
  constexpr std::size_t kSwitch = 100;  // 50 s into the search
  ASSERT_GT(steps.size(), kSwitch + 40);
  const auto answered = [&](std::size_t n) { return heard.wait_for(n, 20s); };
  for (std::size_t k = 0; k < kSwitch; ++k) {
    ASSERT_TRUE(to_west.write(to_idl(steps[k])));
    if (k % 40 == 39) {
      ASSERT_TRUE(answered(k - 9)) << "step " << k;
    }
  }
  ASSERT_TRUE(answered(kSwitch));
  // The first steps in the east go out at once, while the request and the journal are on their
  // way: the east daemon answers them from a fresh filter, then merges them into the journal's.
  constexpr std::size_t kInFlight = 5;
  for (std::size_t k = kSwitch; k < kSwitch + kInFlight; ++k) ASSERT_TRUE(to_east.write(to_idl(steps[k])));
  ASSERT_TRUE(test::eventually([&] { return east->taken_over() == 1; }, 20s))
      << "the journal never reached the east daemon";
  ASSERT_TRUE(test::eventually([&] { return west->handed_over() == 1; }, 10s)) << "the west daemon kept him";
  ASSERT_TRUE(to_west.write(to_idl(steps[kSwitch - 1])));  // a straggler of the switch
  ASSERT_TRUE(test::eventually([&] { return west->counters().rejected_for("handed_over") == 1; }, 10s));
  ASSERT_TRUE(answered(kSwitch + kInFlight));
  for (std::size_t k = kSwitch + kInFlight; k < steps.size(); ++k) ASSERT_TRUE(to_east.write(to_idl(steps[k])));
  ASSERT_TRUE(answered(steps.size()));

  // One daemon that never lost him, with the same configuration.
  auto never_moved =
      estimator::make_estimator(estimator::ResponderRole::kFirefighter, "ff1", config_of("west").estimators);
  const auto positions = heard.all();
  std::size_t compared = 0;
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const auto outcome = never_moved->add_odometry(steps[k]);
    const auto* out = std::get_if<estimator::EstimatorOutput>(&outcome);
    ASSERT_TRUE(out != nullptr && out->position) << "step " << k;
    if (k >= kSwitch && k < kSwitch + kInFlight)
      continue;  // perhaps the east daemon's fresh filter, before the journal
    const auto it = positions.find(steps[k].interval_end);
    ASSERT_NE(it, positions.end()) << "no answer to step " << k;
    EXPECT_EQ(it->second.position.position, out->position->position.position) << "step " << k;
    EXPECT_EQ(it->second.position.covariance, out->position->position.covariance) << "step " << k;
    EXPECT_EQ(it->second.confirmed, out->position->confirmed) << "step " << k;
    ++compared;
  }
  EXPECT_EQ(compared, steps.size() - kInFlight);
  EXPECT_EQ(east->counters().rejected, 0U);
}

}  // namespace
}  // namespace sarloc::dds
