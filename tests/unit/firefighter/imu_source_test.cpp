// Any foot IMU's recording read by its source description: columns by name or index, units,
// axes, the time rules (repeated, out of order, gaps, no time column), the range rule, the
// vendor's valid flags, and bad rows named by file and line with nothing else lost.
#include "sarloc/core/firefighter/imu_source.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::firefighter {
namespace {

std::vector<ImuSample> read_all(ImuSourceReader& reader) {
  std::vector<ImuSample> out;
  while (auto s = reader.next()) out.push_back(*s);
  return out;
}

std::vector<double> times(const std::vector<ImuSample>& samples) {
  std::vector<double> t;
  for (const auto& s : samples) t.push_back(s.t);
  return t;
}

// The x-io layout: time in s, gyro in deg/s before accel in g.
ImuSourceFormat xio_like() {
  ImuSourceFormat f;
  f.time = ImuColumn{"Time (s)", -1};
  f.gyro = {ImuColumn{"gx", -1}, ImuColumn{"gy", -1}, ImuColumn{"gz", -1}};
  f.accel = {ImuColumn{"ax", -1}, ImuColumn{"ay", -1}, ImuColumn{"az", -1}};
  f.accel_scale_mps2 = kGravity;
  f.gyro_scale_radps = kDeg;
  f.rate_hz = 100.0;
  return f;
}

TEST(ImuSource, ReadsColumnsByNameInTheirUnitsAndRepeatedTimesAreSpreadToTheNext) {
  std::istringstream in(
      "Time (s),gx,gy,gz,ax,ay,az\n"
      "10.00,0,0,90,0,0,1\n"
      "10.01,0,0,0,0,0,1\n"
      "10.01,0,0,0,0,0,1\n"  // repeated
      "10.01,0,0,0,0,0,1\n"  // repeated again
      "10.04,0,0,0,0,0,1\n"
      "10.03,0,0,0,0,0,1\n"  // out of order
      "10.05,0,0,0,0,0,1\n");
  ImuSourceReader reader(in, "walk.csv", xio_like());
  const auto samples = read_all(reader);
  const std::vector<double> t = times(samples);
  ASSERT_EQ(t.size(), 6u);
  const std::vector<double> expected{0.0, 0.01, 0.02, 0.03, 0.04, 0.05};
  for (std::size_t i = 0; i < t.size(); ++i) EXPECT_NEAR(t[i], expected[i], 1e-9) << i;
  EXPECT_NEAR(samples[0].angular_rate.z(), kPi / 2.0, 1e-12);
  EXPECT_NEAR(samples[0].specific_force.z(), kGravity, 1e-12);
  EXPECT_EQ(reader.counts().repeated_time, 2u);
  EXPECT_EQ(reader.counts().repeated_dropped, 0u);
  EXPECT_EQ(reader.counts().out_of_order, 1u);
  ASSERT_EQ(reader.problems().size(), 1u);
  EXPECT_NE(reader.problems()[0].find("walk.csv:7: time = 10.03 s: before the previous row's 10.04 s"),
            std::string::npos)
      << reader.problems()[0];
}

TEST(ImuSource, DropRuleMalformedRowsAndTheFirstBadFieldAreNamedAndNothingElseIsLost) {
  ImuSourceFormat f = sarloc_csv();
  std::istringstream in(
      "# comment\n"
      "t_s,ax_mps2,ay_mps2,az_mps2,gx_radps,gy_radps,gz_radps\n"
      "0.00,0,0,9.81,0,0,0\n"
      "0.01,0,0,9.81,abc,0,0\n"  // line 4: not a number
      "0.01,0,0,9.81,0,0,0\n"
      "0.01,0,0,9.81,0,0,0\n"  // line 6: repeated, dropped by sarloc's rule
      "0.02,0,0\n"             // line 7: too few cells
      "0.03,0,0,9.81,0,0,0\n");
  ImuSourceReader reader(in, "boot.csv", f);
  EXPECT_EQ(times(read_all(reader)), (std::vector<double>{0.0, 0.01, 0.03}));
  EXPECT_EQ(reader.counts().malformed, 2u);
  EXPECT_EQ(reader.counts().repeated_dropped, 1u);
  EXPECT_EQ(reader.counts().refused(), 3u);
  ASSERT_EQ(reader.problems().size(), 3u);
  auto said = [&](const std::string& text) {
    for (const auto& p : reader.problems())
      if (p.find(text) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(said("boot.csv:4: gyro x (column 5) = 'abc': not a finite number"));
  EXPECT_TRUE(said("boot.csv:6: time = 0.01 s repeats the previous row's"));
  EXPECT_TRUE(said("boot.csv:7: 3 cells, the source needs 7"));
}

TEST(ImuSource, NoTimeColumnIsPacedByTheRateAndAxesTurnAZDownSensorUp) {
  ImuSourceFormat f;
  f.header = false;
  f.rate_hz = 820.0;
  f.accel = {ImuColumn{"", 0}, ImuColumn{"", 1}, ImuColumn{"", 2}};
  f.gyro = {ImuColumn{"", 3}, ImuColumn{"", 4}, ImuColumn{"", 5}};
  f.axes << 1, 0, 0, 0, -1, 0, 0, 0, -1;  // [x, -y, -z]
  std::istringstream in("0.1,0.2,-9.8,0.01,0.02,0.03\n0.1,0.2,-9.8,0.01,0.02,0.03\n");
  ImuSourceReader reader(in, "shoe.txt", f);
  const auto s = read_all(reader);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_NEAR(s[1].t, 1.0 / 820.0, 1e-12);
  EXPECT_TRUE(s[0].specific_force.isApprox(Eigen::Vector3d(0.1, -0.2, 9.8)));
  EXPECT_TRUE(s[0].angular_rate.isApprox(Eigen::Vector3d(0.01, -0.02, -0.03)));
}

TEST(ImuSource, BeyondTheRangeIsClippedOrRefusedByItsRuleAndValidFlagsAreRead) {
  for (const OverRangeRule rule : {OverRangeRule::kClip, OverRangeRule::kRefuse}) {
    ImuSourceFormat f = sarloc_csv();
    f.over_range = rule;
    f.valid_flags = {ImuColumn{"ok", -1}};
    std::istringstream in(
        "t_s,ax_mps2,ay_mps2,az_mps2,gx_radps,gy_radps,gz_radps,ok\n"
        "0.00,0,0,9.81,0,0,0,1\n"
        "0.01,0,0,170,0,0,0,1\n"   // 17.3 g: beyond 16 g
        "0.02,0,0,9.81,0,0,0,0\n"  // not valid
        "0.03,0,0,9.81,0,0,0,1\n");
    ImuSourceReader reader(in, "heel.csv", f);
    const auto s = read_all(reader);
    EXPECT_EQ(reader.counts().invalid_flag, 1u);
    if (rule == OverRangeRule::kClip) {
      ASSERT_EQ(s.size(), 3u);
      EXPECT_NEAR(s[1].specific_force.z(), 16.0 * kGravity, 1e-9);
      EXPECT_EQ(reader.counts().clipped, 1u);
    } else {
      EXPECT_EQ(s.size(), 2u);
      EXPECT_EQ(reader.counts().over_range, 1u);
    }
  }
}

TEST(ImuSource, AHeaderWithoutADeclaredColumnIsRefusedNamingFileColumnAndSource) {
  std::istringstream in("Time (s),gx,gy,gz,ax,ay\n");
  try {
    ImuSourceReader reader(in, "walk.csv", xio_like());
    FAIL() << "a missing column";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("walk.csv:1: accel z column 'az' is not in the header"), std::string::npos)
        << e.what();
  }
  std::istringstream empty("");
  EXPECT_THROW(ImuSourceReader(empty, "empty.csv", xio_like()), ConfigError);
}

TEST(ImuSource, GapsAndARateThatIsNotTheDeclaredOneAreReported) {
  ImuSourceFormat f = sarloc_csv();
  f.rate_hz = 400.0;  // declared; the rows are 100 Hz
  std::ostringstream text;
  text << "t_s,ax_mps2,ay_mps2,az_mps2,gx_radps,gy_radps,gz_radps\n";
  for (int k = 0; k < 300; ++k) text << (k < 250 ? k : k + 20) * 0.01 << ",0,0,9.81,0,0,0\n";
  std::istringstream in(text.str());
  ImuSourceReader reader(in, "slow.csv", f);
  read_all(reader);
  EXPECT_NEAR(reader.rate_hz(), 100.0, 1.0);
  EXPECT_EQ(reader.counts().gaps, 1u);
  EXPECT_NEAR(reader.counts().longest_gap_s, 0.21, 1e-9);
  ASSERT_FALSE(reader.problems().empty());
  EXPECT_NE(reader.problems()[0].find("declares 400 Hz (rate mismatch"), std::string::npos) << reader.problems()[0];
}

// A source file's stance settings and noise are its sensor's: they win over an ins: section
// (the noise as the process noise, inflated as the INS's own is), and what the file does not
// declare stays as configured.
TEST(ImuSource, TheSensorsDeclaredSettingsWinOverTheInsConfiguration) {
  ZuptInsConfig config;
  config.detector_threshold = 2e4;  // as an ins: section set it
  config.adaptive_stance = false;
  config.stance_votes = 3;
  ImuSourceFormat gx5;
  gx5.stance_threshold = 1e5;
  gx5.adaptive_stance = true;
  apply_declared(gx5, config);
  EXPECT_EQ(config.detector_threshold, 1e5);
  EXPECT_TRUE(config.adaptive_stance);
  EXPECT_EQ(config.detector, StanceDetector::kShoe) << "not declared: as configured";
  EXPECT_EQ(config.stance_votes, 3u);
  const double accel_noise = config.accel_noise_density;
  gx5.gyro_noise_density = 1.2e-4;
  apply_declared(gx5, config);
  EXPECT_DOUBLE_EQ(config.gyro_noise_density, kProcessNoiseInflation * 1.2e-4);
  EXPECT_EQ(config.accel_noise_density, accel_noise) << "not declared: as configured";
}

}  // namespace
}  // namespace sarloc::firefighter
