#include "sarloc/core/firefighter/imu_source.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::firefighter {
namespace {

std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\"");
  const auto e = s.find_last_not_of(" \t\r\"");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

bool skippable(const std::string& line) {
  const std::string t = trimmed(line);
  return t.empty() || t.front() == '#';
}

std::vector<std::string> cells_of(const std::string& line, char delimiter) {
  std::vector<std::string> cells;
  std::stringstream row(line);
  std::string cell;
  while (std::getline(row, cell, delimiter)) cells.push_back(trimmed(cell));
  if (!line.empty() && line.back() == delimiter) cells.emplace_back();
  return cells;
}

std::optional<double> number(const std::string& text) {
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end == text.c_str() || *end != '\0' || errno == ERANGE || !std::isfinite(value))
    return std::nullopt;
  return value;
}

constexpr std::size_t kRateIntervals = 200;  // the first intervals give the rate

}  // namespace

void ImuSourceFormat::validate() const {
  auto column = [](const std::string& key, const ImuColumn& c, bool named) {
    require(!c.name.empty() || c.index >= 0, key, "unset", "needs a column name or index");
    require(c.name.empty() || named, key, c.name, "a column by name needs header: true");
  };
  if (time) column("imu_source.time.column", *time, header);
  for (int i = 0; i < 3; ++i) {
    column("imu_source.accel.columns[" + std::to_string(i) + "]", accel[static_cast<std::size_t>(i)], header);
    column("imu_source.gyro.columns[" + std::to_string(i) + "]", gyro[static_cast<std::size_t>(i)], header);
  }
  for (const ImuColumn& c : valid_flags) column("imu_source.valid_flags[]", c, header);
  require(time.has_value() || rate_hz > 0.0, "imu_source.rate_hz", rate_hz, "must be > 0 without a time column");
  require(rate_hz >= 0.0 && rate_hz <= 10000.0, "imu_source.rate_hz", rate_hz, "must be within [0, 10000]");
  require(time_scale_s > 0.0 && std::isfinite(time_scale_s), "imu_source.time.unit scale", time_scale_s, "must be > 0");
  require(accel_scale_mps2 > 0.0, "imu_source.accel.unit scale", accel_scale_mps2, "must be > 0");
  require(gyro_scale_radps > 0.0, "imu_source.gyro.unit scale", gyro_scale_radps, "must be > 0");
  const double orthogonality = (axes * axes.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  // Right-handed: the third row is the cross product of the first two (a determinant of +1).
  const bool right_handed = axes.row(0).cross(axes.row(1)).dot(axes.row(2)) > 0.0;
  require(axes.allFinite() && orthogonality < 1e-6 && right_handed, "imu_source.axes", "the given rows",
          "must be a rotation (orthonormal rows, right-handed)");
  require(accel_range_mps2 > 0.0, "imu_source.range.accel", accel_range_mps2, "must be > 0");
  require(gyro_range_radps > 0.0, "imu_source.range.gyro", gyro_range_radps, "must be > 0");
  require(gap_periods >= 1.5, "imu_source.gap_periods", gap_periods, "must be >= 1.5");
  require(accel_noise_density >= 0.0 && accel_noise_density < 1.0, "imu_source.noise.accel_density",
          accel_noise_density, "must be within [0, 1) m/s^2/sqrt(Hz)");
  require(gyro_noise_density >= 0.0 && gyro_noise_density < 0.1, "imu_source.noise.gyro_density", gyro_noise_density,
          "must be within [0, 0.1) rad/s/sqrt(Hz)");
  if (stance_threshold)
    require(*stance_threshold >= 1.0 && *stance_threshold <= 1e9, "imu_source.stance.threshold", *stance_threshold,
            "must be within [1, 1e9]");
}

void apply_declared(const ImuSourceFormat& format, ZuptInsConfig& config) {
  if (format.stance_threshold) config.detector_threshold = *format.stance_threshold;
  if (format.adaptive_stance) config.adaptive_stance = *format.adaptive_stance;
  if (format.stance_detector) config.detector = *format.stance_detector;
  if (format.stance_votes) config.stance_votes = *format.stance_votes;
  if (format.accel_noise_density > 0.0)
    config.accel_noise_density = kProcessNoiseInflation * format.accel_noise_density;
  if (format.gyro_noise_density > 0.0) config.gyro_noise_density = kProcessNoiseInflation * format.gyro_noise_density;
}

ImuSourceFormat sarloc_csv() {
  ImuSourceFormat f;
  f.time = ImuColumn{"t_s", -1};
  f.accel = {ImuColumn{"ax_mps2", -1}, ImuColumn{"ay_mps2", -1}, ImuColumn{"az_mps2", -1}};
  f.gyro = {ImuColumn{"gx_radps", -1}, ImuColumn{"gy_radps", -1}, ImuColumn{"gz_radps", -1}};
  f.rate_hz = 100.0;
  // sarloc's own recordings are the device's: every time is new, nothing to re-time.
  f.repeated_time = RepeatedTimeRule::kDrop;
  return f;
}

ImuSourceReader::ImuSourceReader(std::istream& in, std::string file, ImuSourceFormat format)
    : in_(in), file_(std::move(file)), format_(std::move(format)) {
  format_.validate();
  std::vector<std::string> names;
  if (format_.header) {
    std::string line;
    while (std::getline(in_, line)) {
      ++line_;
      if (!skippable(line)) break;
      line.clear();
    }
    if (line.empty()) throw ConfigError(file_ + ": no header line (the source '" + format_.name + "' has one)");
    names = cells_of(line, format_.delimiter);
  }
  auto place = [&](const ImuColumn& c, const std::string& role) {
    if (c.index >= 0) return c.index;
    const auto it = std::find(names.begin(), names.end(), c.name);
    if (it == names.end()) {
      std::string header;
      for (const auto& n : names) header += (header.empty() ? "'" : ", '") + n + "'";
      throw ConfigError(file_ + ":" + std::to_string(line_) + ": " + role + " column '" + c.name +
                        "' is not in the header (" + header + "); the source is '" + format_.name + "'");
    }
    return static_cast<int>(it - names.begin());
  };
  if (format_.time) time_col_ = place(*format_.time, "time");
  const char* axis[] = {"x", "y", "z"};
  for (std::size_t i = 0; i < 3; ++i) {
    accel_col_[i] = place(format_.accel[i], std::string("accel ") + axis[i]);
    gyro_col_[i] = place(format_.gyro[i], std::string("gyro ") + axis[i]);
  }
  for (const ImuColumn& c : format_.valid_flags) flag_cols_.push_back(place(c, "valid flag"));
  int widest = time_col_;
  for (std::size_t i = 0; i < 3; ++i) widest = std::max({widest, accel_col_[i], gyro_col_[i]});
  for (int c : flag_cols_) widest = std::max(widest, c);
  width_ = static_cast<std::size_t>(widest + 1);
}

void ImuSourceReader::problem(std::size_t line, const std::string& text) {
  if (problems_.size() < kMaxProblems) problems_.push_back(file_ + ":" + std::to_string(line) + ": " + text);
}

std::optional<ImuSourceReader::Row> ImuSourceReader::read_row() {
  std::string line;
  while (std::getline(in_, line)) {
    ++line_;
    if (skippable(line)) continue;
    ++counts_.rows;
    const std::size_t paced = rows_paced_++;
    const std::vector<std::string> cells = cells_of(line, format_.delimiter);
    if (cells.size() < width_) {
      ++counts_.malformed;
      problem(line_,
              std::to_string(cells.size()) + " cells, the source needs " + std::to_string(width_) + ": row skipped");
      continue;
    }
    auto read = [&](int col, const char* field, double& out) {
      const auto v = number(cells[static_cast<std::size_t>(col)]);
      if (!v) {
        problem(line_, std::string(field) + " (column " + std::to_string(col + 1) + ") = '" +
                           cells[static_cast<std::size_t>(col)] + "': not a finite number: row skipped");
        return false;
      }
      out = *v;
      return true;
    };
    Row r;
    r.line = line_;
    bool ok = true;
    if (time_col_ >= 0) {
      ok = read(time_col_, "time", r.t);
      r.t *= format_.time_scale_s;
    } else {
      r.t = static_cast<double>(paced) / format_.rate_hz;
    }
    const char* fields[] = {"accel x", "accel y", "accel z", "gyro x", "gyro y", "gyro z"};
    for (std::size_t i = 0; ok && i < 3; ++i) ok = read(accel_col_[i], fields[i], r.f[static_cast<Eigen::Index>(i)]);
    for (std::size_t i = 0; ok && i < 3; ++i) ok = read(gyro_col_[i], fields[3 + i], r.w[static_cast<Eigen::Index>(i)]);
    if (!ok) {
      ++counts_.malformed;
      continue;
    }
    bool valid = true;
    for (int c : flag_cols_) {
      double flag = 0.0;
      if (!read(c, "valid flag", flag)) {
        valid = false;
        ++counts_.malformed;
        break;
      }
      if (flag == 0.0) {
        valid = false;
        ++counts_.invalid_flag;
        problem(line_, "valid flag (column " + std::to_string(c + 1) + ") = 0: row skipped");
        break;
      }
    }
    if (!valid) continue;
    r.f *= format_.accel_scale_mps2;
    r.w *= format_.gyro_scale_radps;
    return r;
  }
  return std::nullopt;
}

double ImuSourceReader::rate_hz() const {
  if (time_col_ < 0 || intervals_.size() < 10) return format_.rate_hz;
  std::vector<double> sorted(intervals_);
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
  return 1.0 / sorted[sorted.size() / 2];
}

std::optional<ImuSample> ImuSourceReader::emit(const Row& row) {
  const bool beyond =
      row.f.cwiseAbs().maxCoeff() > format_.accel_range_mps2 || row.w.cwiseAbs().maxCoeff() > format_.gyro_range_radps;
  Row r = row;
  if (beyond) {
    std::ostringstream os;
    os << "|f| " << row.f.cwiseAbs().maxCoeff() << " m/s^2, |w| " << row.w.cwiseAbs().maxCoeff()
       << " rad/s: beyond the range " << format_.accel_range_mps2 << " m/s^2, " << format_.gyro_range_radps << " rad/s";
    if (format_.over_range == OverRangeRule::kRefuse) {
      ++counts_.over_range;
      problem(row.line, os.str() + ": row refused");
      return std::nullopt;
    }
    ++counts_.clipped;
    r.f = r.f.cwiseMax(-format_.accel_range_mps2).cwiseMin(format_.accel_range_mps2);
    r.w = r.w.cwiseMax(-format_.gyro_range_radps).cwiseMin(format_.gyro_range_radps);
  }
  if (last_t_) {
    const double dt = r.t - *last_t_;
    if (intervals_.size() < kRateIntervals) {
      intervals_.push_back(dt);
      if (intervals_.size() == kRateIntervals && time_col_ >= 0 && format_.rate_hz > 0.0) {
        const double seen = rate_hz();
        if (std::abs(seen / format_.rate_hz - 1.0) > 0.1) {
          std::ostringstream os;
          os << "time: the rows' times show " << seen << " Hz, the source '" << format_.name << "' declares "
             << format_.rate_hz << " Hz (rate mismatch: the times are used)";
          problem(row.line, os.str());
        }
      }
    }
    // Gaps against the rate the times show (once ten intervals show it).
    if (intervals_.size() >= 10 && dt > format_.gap_periods / rate_hz()) {
      ++counts_.gaps;
      counts_.longest_gap_s = std::max(counts_.longest_gap_s, dt);
    }
  }
  last_t_ = r.t;
  if (!first_t_) first_t_ = r.t;
  ++counts_.samples;
  ImuSample s;
  s.t = r.t - *first_t_;
  s.specific_force = format_.axes * r.f;
  s.angular_rate = format_.axes * r.w;
  return s;
}

std::optional<ImuSample> ImuSourceReader::next() {
  for (;;) {
    if (!pending_.empty()) {
      const Row r = pending_.front();
      pending_.pop_front();
      if (auto s = emit(r)) return s;
      continue;
    }
    std::optional<Row> r;
    if (held_) {
      r = held_;
      held_.reset();
    } else {
      r = read_row();
    }
    if (!r) return std::nullopt;
    if (last_t_ && r->t < *last_t_) {
      ++counts_.out_of_order;
      std::ostringstream os;
      os << "time = " << r->t << " s: before the previous row's " << *last_t_ << " s (out of order): row dropped";
      problem(r->line, os.str());
      continue;
    }
    if (!last_t_ || r->t > *last_t_) {
      if (auto s = emit(*r)) return s;
      continue;
    }
    // A run of rows at the previous time: re-timed evenly up to the next later time, or dropped.
    std::vector<Row> run{*r};
    std::optional<Row> after;
    while ((after = read_row())) {
      if (after->t > *last_t_) break;
      if (after->t == *last_t_) {
        run.push_back(*after);
      } else {
        ++counts_.out_of_order;
        problem(after->line, "time before the previous row's (out of order): row dropped");
      }
    }
    counts_.repeated_time += run.size();
    if (format_.repeated_time == RepeatedTimeRule::kDrop || !after) {
      counts_.repeated_dropped += run.size();
      std::ostringstream os;
      os << "time = " << r->t << " s repeats the previous row's: " << run.size() << " row(s) dropped";
      problem(r->line, os.str());
      held_ = after;
      continue;
    }
    const double step = (after->t - *last_t_) / static_cast<double>(run.size() + 1);
    for (std::size_t k = 0; k < run.size(); ++k) {
      run[k].t = *last_t_ + static_cast<double>(k + 1) * step;
      pending_.push_back(run[k]);
    }
    held_ = after;
  }
}

}  // namespace sarloc::firefighter
