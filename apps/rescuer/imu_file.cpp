#include "imu_file.hpp"

#include <spdlog/spdlog.h>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::rescuer {
namespace {

constexpr std::array<const char*, 7> kFields{"t_s", "ax_mps2", "ay_mps2", "az_mps2", "gx_radps", "gy_radps", "gz_radps"};

std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  const auto e = s.find_last_not_of(" \t\r");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

bool skippable(const std::string& line) {
  const std::string t = trimmed(line);
  return t.empty() || t.front() == '#';
}

}  // namespace

ImuFile::ImuFile(const std::string& path) : in_(path), path_(path) {
  if (!in_) throw ConfigError("--source '" + path + "': cannot open the IMU file");
  std::string line;
  while (std::getline(in_, line)) {
    ++line_number_;
    if (skippable(line)) continue;
    if (trimmed(line) != kHeader) {
      throw ConfigError(path + ":" + config_value(line_number_) + ": header '" + trimmed(line) +
                        "': expected '" + kHeader + "'");
    }
    return;
  }
  throw ConfigError(path + ": no header line: expected '" + std::string(kHeader) + "'");
}

std::optional<firefighter::ImuSample> ImuFile::next() {
  std::string line;
  while (std::getline(in_, line)) {
    ++line_number_;
    if (skippable(line)) continue;
    std::array<double, 7> v{};
    std::stringstream row(line);
    std::string cell;
    std::string problem;
    std::size_t k = 0;
    for (; std::getline(row, cell, ','); ++k) {
      if (k >= v.size()) {
        problem = "more than 7 columns";
        break;
      }
      const std::string text = trimmed(cell);
      char* end = nullptr;
      errno = 0;
      const double value = std::strtod(text.c_str(), &end);
      if (text.empty() || end == text.c_str() || *end != '\0' || errno == ERANGE || !std::isfinite(value)) {
        problem = std::string(kFields[k]) + " = '" + text + "': not a finite number";
        break;
      }
      v[k] = value;
    }
    if (problem.empty() && k < v.size()) problem = "only " + std::to_string(k) + " of 7 columns";
    if (problem.empty() && last_t_ && v[0] <= *last_t_) {
      std::ostringstream os;
      os << "t_s = " << v[0] << ": not after the previous row's " << *last_t_;
      problem = os.str();
    }
    if (!problem.empty()) {
      ++skipped_;
      spdlog::warn("{}:{}: {}: row skipped", path_, line_number_, problem);
      continue;
    }
    last_t_ = v[0];
    firefighter::ImuSample s;
    s.t = v[0];
    s.specific_force = Eigen::Vector3d(v[1], v[2], v[3]);
    s.angular_rate = Eigen::Vector3d(v[4], v[5], v[6]);
    return s;
  }
  return std::nullopt;
}

}  // namespace sarloc::rescuer
