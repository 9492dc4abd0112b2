// sarloc-rescuer's recorded sensor files (docs/configuration.md): epochs grouped by the field
// samples' stamp, malformed lines skipped without losing the rest.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "sarloc/core/common/errors.hpp"
#include "sensor_source.hpp"

namespace sarloc::rescuer {
namespace {

const sarloc::avalanche::FieldMeasurement& field(const sarloc::estimator::SensorSample& s) {
  return std::get<sarloc::avalanche::FieldMeasurement>(s);
}

std::string write_file(const std::string& text) {
  // One file per test: ctest runs this file's tests as parallel processes, and both wrote
  // recorded.jsonl (one failed once under ctest -j2).
  const std::string path = ::testing::TempDir() + "/recorded-" +
                           ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".jsonl";
  std::ofstream(path) << text;
  return path;
}

const GeodeticOrigin kOrigin{46.9480, 7.4474, 2100.0};

const char* kCov6 = "[1e-4,0,0,0,0,0, 0,1e-4,0,0,0,0, 0,0,1e-4,0,0,0, 0,0,0,1e-5,0,0, 0,0,0,0,1e-5,0, 0,0,0,0,0,1e-4]";

TEST(RecordedSource, GroupsEpochsByFieldStampAndSkipsMalformedLines) {
  std::string text;
  text += std::string(R"({"type":"odometry","sequence":1,"interval_start_ns":0,"interval_end_ns":1000000000,"translation":[1,0,0],"rotation_rpy":[0,0,0.1],"covariance":)") + kCov6 + "}\n";
  text += R"({"type":"position","stamp_ns":1000000000,"position":[10,20,1],"covariance":[1,0,0,0,1,0,0,0,4]})" "\n";
  text += R"({"type":"field","signal_id":1,"sequence":1,"stamp_ns":1000000000,"field":[1e-7,2e-8,-3e-9],"noise_stddev":[2e-9,2e-9,2e-9]})" "\n";
  text += R"({"type":"field","signal_id":2,"sequence":1,"stamp_ns":1000000000,"field":[4e-8,1e-8,0],"noise_stddev":[2e-9,2e-9,2e-9],"orientation_rpy":[0,0,1.5],"orientation_covariance":[1e-4,0,0,0,1e-4,0,0,0,1e-3]})" "\n";
  text += "this is not json\n";
  text += R"({"type":"field","signal_id":1,"sequence":2,"stamp_ns":2000000000,"field":[1e-7,"x",0],"noise_stddev":[2e-9,2e-9,2e-9]})" "\n";
  text += R"({"type":"teleport","stamp_ns":2000000000})" "\n";
  text += "\n";
  text += std::string(R"({"type":"odometry","sequence":2,"interval_start_ns":1000000000,"interval_end_ns":2000000000,"translation":[0.5,0,0],"rotation_rpy":[0,0,0],"covariance":)") + kCov6 + "}\n";
  text += R"({"type":"field","signal_id":1,"sequence":2,"stamp_ns":2000000000,"field":[2e-7,0,0],"noise_stddev":[2e-9,2e-9,2e-9]})" "\n";

  RecordedSource source(write_file(text), "r9", "team-x", kOrigin);
  const auto first = source.next(0, std::nullopt);
  ASSERT_TRUE(first.has_value());
  EXPECT_EQ(first->stamp, 1'000'000'000);
  ASSERT_EQ(first->odometry.size(), 1U);
  EXPECT_EQ(first->odometry[0].rescuer_id, "r9");
  EXPECT_DOUBLE_EQ(first->odometry[0].covariance(5, 5), 1e-4);
  ASSERT_TRUE(first->position.has_value());
  EXPECT_EQ(first->position->team_id, "team-x");
  ASSERT_EQ(first->samples.size(), 2U);
  EXPECT_FALSE(field(first->samples[0]).orientation.has_value());
  ASSERT_TRUE(field(first->samples[1]).orientation.has_value());
  EXPECT_DOUBLE_EQ(field(first->samples[1]).orientation->rpy.z(), 1.5);

  const auto second = source.next(0, std::nullopt);
  ASSERT_TRUE(second.has_value());
  EXPECT_EQ(second->stamp, 2'000'000'000);
  ASSERT_EQ(second->odometry.size(), 1U);
  ASSERT_EQ(second->samples.size(), 1U) << "the malformed field line of this stamp must be skipped";
  EXPECT_DOUBLE_EQ(field(second->samples[0]).field.x(), 2e-7);
  EXPECT_EQ(source.skipped_lines(), 3U);  // not JSON, a string in "field", an unknown type
  EXPECT_NEAR(source.distance_walked_m(), 1.5, 1e-12);
  EXPECT_FALSE(source.next(0, std::nullopt).has_value());
}

TEST(RecordedSource, ReadsTheSeparationsAxesAndEventsAndSkipsBadOnes) {
  std::string text;
  text += R"({"type":"field","signal_id":1,"sequence":1,"stamp_ns":1000000000,"field":[1e-7,0,0],"noise_stddev":[2e-9,2e-9,2e-9],"valid_axes":5,"signal_event":"separated"})" "\n";
  text += R"({"type":"field","signal_id":2,"sequence":1,"stamp_ns":1000000000,"field":[1e-7,0,0],"noise_stddev":[2e-9,2e-9,2e-9],"valid_axes":0})" "\n";
  text += R"({"type":"field","signal_id":3,"sequence":1,"stamp_ns":1000000000,"field":[1e-7,0,0],"noise_stddev":[2e-9,2e-9,2e-9],"signal_event":"swapped"})" "\n";
  text += R"({"type":"field","signal_id":4,"sequence":1,"stamp_ns":1000000000,"field":[1e-7,0,0],"noise_stddev":[2e-9,2e-9,2e-9],"valid_axes":8})" "\n";
  RecordedSource source(write_file(text), "r9", "team-x", kOrigin);
  const auto epoch = source.next(0, std::nullopt);
  ASSERT_TRUE(epoch.has_value());
  ASSERT_EQ(epoch->samples.size(), 2U) << "a mask beyond the three axes and an unknown event are skipped";
  EXPECT_EQ(field(epoch->samples[0]).valid_axes, 5U);
  EXPECT_EQ(field(epoch->samples[0]).event, sarloc::avalanche::SignalEvent::kSeparated);
  EXPECT_EQ(field(epoch->samples[1]).valid_axes, 0U) << "0: a pulse due and not heard (a miss)";
  EXPECT_EQ(source.skipped_lines(), 2U);
}

// A real receiver's fixes in WGS-84: converted about the incident's origin on the device; a fix
// out of range, far away or without an accuracy is skipped, naming the field.
TEST(RecordedSource, ReadsGnssFixesInWgs84AndSkipsBadOnes) {
  const incident::GeodeticFrame frame(kOrigin);
  const incident::Geodetic fix = frame.to_wgs84(Vec3(30.0, -40.0, -12.0));
  char good[256];
  std::snprintf(
      good, sizeof good,
      R"({"type":"gnss","stamp_ns":1000000000,"latitude_deg":%.10f,"longitude_deg":%.10f,"altitude_m":%.4f,"horizontal_sigma_m":2.5,"vertical_sigma_m":5})",
      fix.latitude_deg, fix.longitude_deg, fix.altitude_m);
  std::string text = std::string(good) + "\n";
  text +=
      R"({"type":"gnss","stamp_ns":1000000000,"latitude_deg":95,"longitude_deg":7.4474,"altitude_m":2100,"horizontal_sigma_m":2.5,"vertical_sigma_m":5})"
      "\n";
  text +=
      R"({"type":"gnss","stamp_ns":1000000000,"latitude_deg":47.9480,"longitude_deg":7.4474,"altitude_m":2100,"horizontal_sigma_m":2.5,"vertical_sigma_m":5})"
      "\n";
  text +=
      R"({"type":"gnss","stamp_ns":1000000000,"latitude_deg":46.9480,"longitude_deg":7.4474,"altitude_m":2100,"horizontal_sigma_m":0,"vertical_sigma_m":5})"
      "\n";
  text +=
      R"({"type":"gnss","stamp_ns":1000000000,"latitude_deg":46.9480,"altitude_m":2100,"horizontal_sigma_m":2.5,"vertical_sigma_m":5})"
      "\n";
  RecordedSource source(write_file(text), "r9", "team-x", kOrigin);
  const auto epoch = source.next(0, std::nullopt);
  ASSERT_TRUE(epoch.has_value());
  ASSERT_TRUE(epoch->position.has_value());
  EXPECT_LT((epoch->position->position.position - Vec3(30.0, -40.0, -12.0)).norm(), 1e-3);
  EXPECT_DOUBLE_EQ(epoch->position->position.covariance(0, 0), 2.5 * 2.5);
  EXPECT_DOUBLE_EQ(epoch->position->position.covariance(1, 1), 2.5 * 2.5);
  EXPECT_DOUBLE_EQ(epoch->position->position.covariance(2, 2), 25.0);
  EXPECT_EQ(epoch->position->responder_id, "r9");
  // Latitude 95, a fix 111 km away, an accuracy of 0, no longitude.
  EXPECT_EQ(source.skipped_lines(), 4U);
}

TEST(RecordedSource, MissingFileIsAConfigError) {
  EXPECT_THROW(RecordedSource("/nonexistent/sensors.jsonl", "r", "t", kOrigin), ConfigError);
}

}  // namespace
}  // namespace sarloc::rescuer
