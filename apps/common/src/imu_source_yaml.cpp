#include "sarloc/app/imu_source_yaml.hpp"

#include <cstdlib>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::app {
namespace {

using firefighter::ImuColumn;

ImuColumn column_of(const std::string& text, bool header, const std::string& key) {
  if (header) return ImuColumn{text, -1};
  char* end = nullptr;
  const long index = std::strtol(text.c_str(), &end, 10);
  require(!text.empty() && *end == '\0' && index >= 0 && index < 1000, key, text,
          "without a header, a column is its 0-based index");
  return ImuColumn{"", static_cast<int>(index)};
}

std::array<ImuColumn, 3> three_columns(YamlReader& section, bool header, double& scale,
                                       const std::map<std::string, double>& units) {
  std::vector<std::string> names;
  section.require("columns", names);
  const std::string key = section.source() + ": " + section.path() + ".columns";
  require(names.size() == 3, key, std::to_string(names.size()) + " columns", "must name x, y and z");
  std::string unit;
  section.require("unit", unit);
  const auto it = units.find(unit);
  if (it == units.end()) {
    std::string known;
    for (const auto& [name, value] : units) known += (known.empty() ? "" : ", ") + name;
    require(false, section.source() + ": " + section.path() + ".unit", unit, "must be one of " + known);
  }
  scale = it->second;
  section.expect_done();
  return {column_of(names[0], header, key + "[0]"), column_of(names[1], header, key + "[1]"),
          column_of(names[2], header, key + "[2]")};
}

Eigen::Matrix3d axes_of(const std::vector<std::string>& axes, const std::string& key) {
  require(axes.size() == 3, key, std::to_string(axes.size()) + " entries", "must give boot x, y, z");
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (int row = 0; row < 3; ++row) {
    const std::string& a = axes[static_cast<std::size_t>(row)];
    const bool negative = !a.empty() && a.front() == '-';
    const std::string axis = negative ? a.substr(1) : a;
    require(axis == "x" || axis == "y" || axis == "z", key, a, "must be x, y, z, -x, -y or -z");
    m(row, axis[0] - 'x') = negative ? -1.0 : 1.0;
  }
  return m;
}

}  // namespace

firefighter::ImuSourceFormat read_imu_source(YamlReader& yaml) {
  YamlReader s = yaml.child("imu_source");
  const std::string where = s.source() + ": imu_source";
  firefighter::ImuSourceFormat f;
  f.time.reset();
  f.rate_hz = 0.0;
  f.repeated_time = firefighter::RepeatedTimeRule::kInterpolate;
  s.require("name", f.name);
  std::string delimiter = ",";
  s.read("delimiter", delimiter);
  require(delimiter.size() == 1, where + ".delimiter", delimiter, "must be one character");
  f.delimiter = delimiter[0];
  s.read("header", f.header);
  if (s.has("time")) {
    YamlReader t = s.child("time");
    std::string column, unit = "s";
    t.require("column", column);
    t.read("unit", unit);
    require(unit == "s" || unit == "ms" || unit == "us", where + ".time.unit", unit, "must be s, ms or us");
    f.time = column_of(column, f.header, where + ".time.column");
    f.time_scale_s = unit == "s" ? 1.0 : unit == "ms" ? 1e-3 : 1e-6;
    t.expect_done();
  }
  s.read("rate_hz", f.rate_hz);
  YamlReader accel = s.child("accel");
  f.accel = three_columns(accel, f.header, f.accel_scale_mps2, {{"g", firefighter::kGravity}, {"m/s^2", 1.0}});
  YamlReader gyro = s.child("gyro");
  f.gyro = three_columns(gyro, f.header, f.gyro_scale_radps, {{"deg/s", kDeg}, {"rad/s", 1.0}});
  std::vector<std::string> flags;
  s.read("valid_flags", flags);
  for (std::size_t i = 0; i < flags.size(); ++i)
    f.valid_flags.push_back(column_of(flags[i], f.header, where + ".valid_flags[" + std::to_string(i) + "]"));
  std::vector<std::string> axes{"x", "y", "z"};
  s.read("axes", axes);
  f.axes = axes_of(axes, where + ".axes");
  YamlReader range = s.child("range");
  double accel_g = f.accel_range_mps2 / firefighter::kGravity, gyro_deg_s = f.gyro_range_radps / kDeg;
  range.read("accel_g", accel_g);
  range.read("gyro_deg_s", gyro_deg_s);
  f.accel_range_mps2 = accel_g * firefighter::kGravity;
  f.gyro_range_radps = gyro_deg_s * kDeg;
  std::string beyond = "clip";
  range.read("beyond", beyond);
  require(beyond == "clip" || beyond == "refuse", where + ".range.beyond", beyond, "must be clip or refuse");
  f.over_range = beyond == "clip" ? firefighter::OverRangeRule::kClip : firefighter::OverRangeRule::kRefuse;
  range.expect_done();
  std::string repeated = "interpolate";
  s.read("repeated_time", repeated);
  require(repeated == "interpolate" || repeated == "drop", where + ".repeated_time", repeated,
          "must be interpolate or drop");
  f.repeated_time =
      repeated == "drop" ? firefighter::RepeatedTimeRule::kDrop : firefighter::RepeatedTimeRule::kInterpolate;
  s.read("gap_periods", f.gap_periods);
  YamlReader noise = s.child("noise");
  noise.read("accel_density", f.accel_noise_density);
  noise.read("gyro_density", f.gyro_noise_density);
  noise.expect_done();
  YamlReader stance = s.child("stance");
  if (stance.has("threshold")) {
    double threshold = 0.0;
    stance.read("threshold", threshold);
    f.stance_threshold = threshold;
  }
  if (stance.has("adaptive")) {
    bool adaptive = false;
    stance.read("adaptive", adaptive);
    f.adaptive_stance = adaptive;
  }
  if (stance.has("detector")) {
    std::string detector;
    stance.read("detector", detector);
    require(detector == "shoe" || detector == "vote", where + ".stance.detector", detector, "must be shoe or vote");
    f.stance_detector = detector == "vote" ? firefighter::StanceDetector::kVote : firefighter::StanceDetector::kShoe;
  }
  if (stance.has("votes")) {
    int votes = 0;
    stance.read("votes", votes);
    require(votes == 2 || votes == 3, where + ".stance.votes", std::to_string(votes), "must be 2 or 3");
    f.stance_votes = static_cast<std::uint32_t>(votes);
  }
  stance.expect_done();
  s.expect_done();
  try {
    f.validate();
  } catch (const ConfigError& e) {
    throw ConfigError(s.source() + ": " + e.what());
  }
  return f;
}

firefighter::ImuSourceFormat load_imu_source(const std::string& path) {
  YamlReader yaml = YamlReader::from_file(path);
  firefighter::ImuSourceFormat f = read_imu_source(yaml);
  yaml.expect_done();
  return f;
}

}  // namespace sarloc::app
