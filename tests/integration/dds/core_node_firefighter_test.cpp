// sarloc-core's node serves firefighters next to avalanche rescuers: the mission file names a
// building and the firefighters' reported entries; a device publishes its boot INS odometry
// (FirefighterDevice on a simulated right-hand search) and the daemon answers every step with a
// map-aided ResponderPosition in the incident frame, on the right floor, that tracks the truth.
#include <gtest/gtest.h>

#include <cmath>
#include <condition_variable>
#include <map>
#include <mutex>
#include <random>

#include "sarloc/app/mission_config.hpp"
#include "sarloc/core/estimator/firefighter_device.hpp"
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

TEST(CoreNodeFirefighter, AnswersBootOdometryWithMapAidedPositionsThatTrackTheSearch) {
  const auto mission =
      app::load_mission_config(std::string(SARLOC_SOURCE_DIR) + "/tests/integration/mission/firefighters.yaml");
  ASSERT_EQ(mission.dds.domain_id, test::kDomainCoreFirefighter);
  auto daemon_participant = test::make_participant(test::kDomainCoreFirefighter, "core");
  auto node = std::make_unique<CoreNode>(daemon_participant, mission.core_config(""));

  auto device_participant = test::make_participant(test::kDomainCoreFirefighter, "ff1");
  Writer<::sarloc::Odometry> odometry(device_participant);
  std::mutex mutex;
  std::condition_variable cv;
  std::map<TimestampNs, responder::ResponderPosition> positions;
  Reader<::sarloc::ResponderPosition> reader(device_participant, [&](const ::sarloc::ResponderPosition& p, const auto&) {
    if (p.responder_id().to_string() != "ff1") return;
    std::lock_guard<std::mutex> lock(mutex);
    const auto r = to_core(p);
    positions[r.stamp] = r;
    cv.notify_all();
  });
  ASSERT_TRUE(odometry.wait_for_readers(1, 10s));
  ASSERT_TRUE(reader.wait_for_writers(1, 10s));

  // The truth: a right-hand search of the mission's building from its front door.
  const auto& plan = mission.estimators.firefighter.building->plan();
  std::mt19937_64 rng(21);
  firefighter::SearchWalkConfig walk;
  walk.duration_s = 120.0;
  const auto search = firefighter::generate_search_walk(plan, walk, firefighter::Hand::kRight, rng);
  const firefighter::FootTrajectory foot(search.leader);
  firefighter::ImuErrors errors(firefighter::ImuErrorConfig{}, rng);
  estimator::FirefighterDevice device("ff1", "alpha", estimator::FirefighterDeviceConfig{}, kOrigin);
  std::vector<TimestampNs> sent;
  for (const auto& ideal : foot.imu_samples(100.0)) {
    device.push(errors.apply(ideal, rng));
    const auto o = device.take_odometry();
    if (!o) continue;
    ASSERT_TRUE(odometry.write(to_idl(*o)));
    sent.push_back(o->interval_end);
    if (sent.size() % 40 == 0) {  // pace: no more than 40 steps ahead of the daemon's answers
      std::unique_lock<std::mutex> lock(mutex);
      ASSERT_TRUE(cv.wait_for(lock, 10s, [&] { return positions.size() + 10 >= sent.size(); }))
          << positions.size() << " answers to " << sent.size() << " steps";
    }
  }
  {
    std::unique_lock<std::mutex> lock(mutex);
    ASSERT_TRUE(cv.wait_for(lock, 10s, [&] { return positions.size() >= sent.size(); }))
        << positions.size() << " answers to " << sent.size() << " steps";
  }
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

}  // namespace
}  // namespace sarloc::dds
