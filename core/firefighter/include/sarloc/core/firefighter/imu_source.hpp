#pragma once
// Any foot-mounted IMU's recording, read by its description (config/imu/*.yaml, docs/
// configuration.md "IMU sources"): which columns hold time, specific force and angular rate, in
// which units, how the sensor is mounted, its range and its noise. A new sensor is a
// description, not code; sarloc's own boot IMU CSV is one such description (sarloc_csv()).
//
// Rules the reader applies, each counted in ImuSourceCounts and reported with file and line:
//   - a cell that is not a finite number, or a row with too few cells: the row is skipped;
//   - a time equal to the previous row's (a logger's quantisation: about 1 % of x-io's rows):
//     kInterpolate spreads the run of equal times evenly up to the next later time (a run at
//     the end of the file is dropped), kDrop drops the row;
//   - a time before the previous row's: the row is dropped (out of order);
//   - an interval longer than gap_periods nominal periods: counted as a gap, passed on (the INS
//     decides what it can bridge);
//   - a component beyond the declared range: kClip sets it to the range (a heel strike that
//     saturated the sensor), kRefuse drops the row.
// Samples come out in the boot frame (x forward, y left, z up: +g up at rest), m/s^2 and rad/s,
// seconds from the first row kept.
//
//   ImuSourceReader reader(stream, "walk.csv", format);  // ConfigError: header does not match
//   while (auto s = reader.next()) ins.push(*s);
//   reader.counts();  reader.problems();
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <deque>
#include <istream>
#include <optional>
#include <string>
#include <vector>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/firefighter/imu_sample.hpp"
#include "sarloc/core/firefighter/stance_threshold.hpp"
#include "sarloc/core/firefighter/zupt_ins.hpp"

namespace sarloc::firefighter {

/// A column by its header name, or (without a header) by its 0-based index.
struct ImuColumn {
  std::string name;
  int index = -1;
};

enum class RepeatedTimeRule : std::uint8_t { kInterpolate, kDrop };
enum class OverRangeRule : std::uint8_t { kClip, kRefuse };

struct ImuSourceFormat {
  std::string name = "sarloc boot IMU CSV";
  char delimiter = ',';
  bool header = true;  ///< the first line that is not a comment names the columns
  /// Time column and its scale to seconds (1 for s, 1e-3 for ms); without one, rate_hz paces
  /// the rows.
  std::optional<ImuColumn> time;
  double time_scale_s = 1.0;
  double rate_hz = 0.0;  ///< nominal rate: required without a time column, else checked
  std::array<ImuColumn, 3> accel;
  double accel_scale_mps2 = 1.0;  ///< 1 for m/s^2, kGravity for g
  std::array<ImuColumn, 3> gyro;
  double gyro_scale_radps = 1.0;  ///< 1 for rad/s, pi/180 for deg/s
  /// Columns that must read non-zero for the row to count (a vendor's ":valid" flags).
  std::vector<ImuColumn> valid_flags;
  /// Boot frame from sensor frame: boot = axes * sensor (a signed permutation or any rotation).
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  double accel_range_mps2 = 16.0 * kGravity;
  double gyro_range_radps = 2000.0 * kDeg;
  OverRangeRule over_range = OverRangeRule::kClip;
  RepeatedTimeRule repeated_time = RepeatedTimeRule::kInterpolate;
  double gap_periods = 3.0;
  /// The sensor's white-noise densities (m/s^2/sqrt(Hz), rad/s/sqrt(Hz)); 0 = not declared: the
  /// INS keeps its own (the MTi-3's). `sarloc-eval ins` prints what it measured at rest.
  double accel_noise_density = 0.0;
  double gyro_noise_density = 0.0;
  /// The stance detector for this sensor and mounting (ZuptInsConfig::detector_threshold,
  /// adaptive_stance); unset: the INS's defaults. A boot that rolls through its stance (the
  /// GX5 of the gait-driven walks: 10-30 deg/s) needs a higher floor than one that stands.
  std::optional<double> stance_threshold;
  std::optional<bool> adaptive_stance;
  std::optional<StanceDetector> stance_detector;  ///< stance.detector: shoe or vote
  std::optional<std::uint32_t> stance_votes;      ///< stance.votes: 2 or 3, with vote
  void validate() const;
};

/// What the sensor's source file declares for the INS, over `config`: its stance detector, and
/// its noise densities as the process noise (times kProcessNoiseInflation). The same on a device
/// and in `sarloc-eval ins`, after any ins: section, since the file knows the sensor and its
/// mounting.
void apply_declared(const ImuSourceFormat& format, ZuptInsConfig& config);

/// sarloc's documented boot IMU CSV: t_s,ax_mps2,ay_mps2,az_mps2,gx_radps,gy_radps,gz_radps.
ImuSourceFormat sarloc_csv();

struct ImuSourceCounts {
  std::size_t rows = 0;           ///< data rows read (comments and blank lines aside)
  std::size_t samples = 0;        ///< samples given out
  std::size_t malformed = 0;      ///< a cell not a number, too few cells
  std::size_t invalid_flag = 0;   ///< a valid flag read 0
  std::size_t repeated_time = 0;  ///< re-timed (kInterpolate) or dropped (kDrop, or at the end)
  std::size_t repeated_dropped = 0;
  std::size_t out_of_order = 0;
  std::size_t gaps = 0;
  double longest_gap_s = 0.0;
  std::size_t clipped = 0;     ///< rows with a component clipped to the range
  std::size_t over_range = 0;  ///< rows refused beyond the range (kRefuse)
  std::size_t refused() const { return malformed + invalid_flag + repeated_dropped + out_of_order + over_range; }
};

class ImuSourceReader {
 public:
  /// Reads the header (if the format has one) and maps the columns; throws ConfigError naming
  /// `file` and the missing column.
  ImuSourceReader(std::istream& in, std::string file, ImuSourceFormat format);

  /// The next sample in the boot frame, nullopt at the end.
  std::optional<ImuSample> next();

  const ImuSourceCounts& counts() const { return counts_; }
  /// "file:line: field = 'value': rule", the first kMaxProblems of them (all are counted).
  const std::vector<std::string>& problems() const { return problems_; }
  /// The rate the rows' times show (median interval of the first rows), or the declared one.
  double rate_hz() const;
  const ImuSourceFormat& format() const { return format_; }

  static constexpr std::size_t kMaxProblems = 50;

 private:
  struct Row {
    double t = 0.0;
    Eigen::Vector3d f = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();
    std::size_t line = 0;
  };
  std::optional<Row> read_row();
  void problem(std::size_t line, const std::string& text);
  std::optional<ImuSample> emit(const Row& row);

  std::istream& in_;
  std::string file_;
  ImuSourceFormat format_;
  std::size_t line_ = 0;
  std::size_t rows_paced_ = 0;
  int time_col_ = -1;
  std::array<int, 3> accel_col_{}, gyro_col_{};
  std::vector<int> flag_cols_;
  std::size_t width_ = 0;
  std::deque<Row> pending_;       ///< re-timed rows waiting to go out
  std::optional<Row> held_;       ///< read ahead, not yet placed
  std::optional<double> last_t_;  ///< the last time given out (raw, before offset)
  std::optional<double> first_t_;
  std::vector<double> intervals_;  ///< the first intervals, for the rate
  ImuSourceCounts counts_;
  std::vector<std::string> problems_;
};

}  // namespace sarloc::firefighter
