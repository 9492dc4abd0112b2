// The shipped IMU source descriptions (config/imu/) load, the sarloc CSV's is the built-in
// default, and a bad description is refused naming its file, key and value.
#include "sarloc/app/imu_source_yaml.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::app {
namespace {

namespace fs = std::filesystem;

TEST(ImuSourceYaml, EveryShippedSourceLoadsAndSarlocsCsvIsTheDefault) {
  std::size_t loaded = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(SARLOC_SOURCE_DIR) / "config/imu")) {
    if (entry.path().extension() != ".yaml") continue;
    EXPECT_NO_THROW(load_imu_source(entry.path().string())) << entry.path();
    ++loaded;
  }
  EXPECT_GE(loaded, 5u);
  const auto shipped = load_imu_source(std::string(SARLOC_SOURCE_DIR) + "/config/imu/sarloc-csv.yaml");
  const auto built_in = firefighter::sarloc_csv();
  EXPECT_EQ(shipped.time->name, built_in.time->name);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(shipped.accel[i].name, built_in.accel[i].name);
    EXPECT_EQ(shipped.gyro[i].name, built_in.gyro[i].name);
  }
  EXPECT_EQ(shipped.accel_scale_mps2, built_in.accel_scale_mps2);
  EXPECT_EQ(shipped.gyro_scale_radps, built_in.gyro_scale_radps);
  EXPECT_EQ(shipped.rate_hz, built_in.rate_hz);
  EXPECT_EQ(shipped.repeated_time, built_in.repeated_time);
  EXPECT_TRUE(shipped.axes.isApprox(built_in.axes));
}

void expect_refused(const std::string& body, const std::string& expected) {
  const std::string text = "imu_source:\n  name: test\n" + body;
  try {
    auto yaml = YamlReader::from_string(text, "test.yaml");
    read_imu_source(yaml);
    FAIL() << "accepted: " << body;
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
}

TEST(ImuSourceYaml, ABadDescriptionIsRefusedNamingKeyAndValue) {
  const std::string columns =
      "  time: {column: t}\n  accel: {columns: [a, b, c], unit: g}\n  gyro: {columns: [d, e, f], unit: rad/s}\n";
  expect_refused(
      "  time: {column: t}\n  accel: {columns: [a, b, c], unit: G}\n  gyro: {columns: [d, e, f], unit: rad/s}\n",
      "imu_source.accel.unit = 'G': must be one of g, m/s^2");
  expect_refused(columns + "  axes: [x, y, w]\n", "imu_source.axes = 'w'");
  expect_refused(columns + "  axes: [x, x, z]\n", "must be a rotation");
  expect_refused(columns + "  range: {beyond: wrap}\n", "imu_source.range.beyond = 'wrap'");
  expect_refused(columns + "  colour: red\n", "imu_source.colour");
  expect_refused(
      "  header: false\n  accel: {columns: ['0', '1', '2'], unit: g}\n  gyro: {columns: ['3', '4', x], unit: rad/s}\n  "
      "rate_hz: 100\n",
      "without a header, a column is its 0-based index");
  expect_refused(
      "  header: false\n  accel: {columns: ['0', '1', '2'], unit: g}\n  gyro: {columns: ['3', '4', '5'], unit: "
      "rad/s}\n",
      "imu_source.rate_hz = 0: must be > 0 without a time column");
}

}  // namespace
}  // namespace sarloc::app
