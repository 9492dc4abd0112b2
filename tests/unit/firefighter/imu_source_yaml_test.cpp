// The shipped IMU source descriptions (config/imu/) load, the sarloc CSV's is the built-in
// default, and a bad description is refused naming its file, key and value.
#include "sarloc/app/imu_source_yaml.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>

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
  expect_refused(columns + "  stance: {detector: ared}\n", "imu_source.stance.detector = 'ared': must be shoe or vote");
  expect_refused(columns + "  stance: {detector: vote, votes: 1}\n", "imu_source.stance.votes = '1': must be 2 or 3");
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

// docs/configuration.md's example under "## IMU sources" is a valid description, and it shows
// exactly the keys the loader reads.
TEST(ImuSourceYaml, TheDocumentedKeysAreExactlyThoseTheLoaderReads) {
  std::ifstream in(fs::path(SARLOC_SOURCE_DIR) / "docs/configuration.md");
  std::string line, block;
  bool section = false, inside = false;
  while (std::getline(in, line)) {
    if (line.rfind("## ", 0) == 0) section = line.rfind("## IMU sources", 0) == 0;
    if (!section) continue;
    if (line.rfind("```", 0) == 0) {
      if (inside) break;
      inside = true;
      continue;
    }
    if (inside) block += line + "\n";
  }
  ASSERT_FALSE(block.empty()) << "docs/configuration.md: no example under ## IMU sources";
  std::set<std::string> documented;
  std::function<void(const YAML::Node&, const std::string&)> flatten = [&](const YAML::Node& n, const std::string& at) {
    for (const auto& kv : n) {
      const std::string key = at.empty() ? kv.first.as<std::string>() : at + "." + kv.first.as<std::string>();
      if (kv.second.IsMap()) flatten(kv.second, key);
      else documented.insert(key);
    }
  };
  flatten(YAML::Load(block), "");
  YamlReader::KeyRecorder recorder;
  auto yaml = YamlReader::from_string(block, "docs/configuration.md");
  EXPECT_NO_THROW(read_imu_source(yaml));
  std::set<std::string> read;
  for (const auto& k : recorder.keys())
    if (!k.empty() && k != "imu_source") read.insert(k);
  for (const auto& k : read) {
    // A section the loader opens (noise, stance) is documented through its keys.
    const bool section_only = std::any_of(read.begin(), read.end(), [&](const std::string& o) { return o.rfind(k + ".", 0) == 0; });
    if (!section_only) {
      EXPECT_EQ(documented.count(k), 1u) << k << ": read by the loader but not documented";
    }
  }
  for (const auto& k : documented) EXPECT_EQ(read.count(k), 1u) << k << ": documented but not read";
}

}  // namespace
}  // namespace sarloc::app
