#pragma once
// A recorded boot IMU file for a firefighter's device (sarloc-rescuer --source FILE): CSV, one
// sample per row, as docs/configuration.md ("Recorded boot IMU files") documents:
//   # comments and blank lines are skipped
//   t_s,ax_mps2,ay_mps2,az_mps2,gx_radps,gy_radps,gz_radps      (this header, first)
//   0.00,0.12,-0.03,9.80,0.001,0.000,-0.002
// t_s: seconds since the recording started, strictly increasing (100 Hz nominal); specific
// force in m/s^2 and angular rate in rad/s in the sensor frame (x forward along the boot, y
// left, z up; at rest it reads +g up). A malformed row is skipped with a warning naming the
// file, the line and the field; nothing else is lost.
#include <fstream>
#include <optional>
#include <string>

#include "sarloc/core/firefighter/imu_sample.hpp"

namespace sarloc::rescuer {

class ImuFile {
 public:
  /// Throws ConfigError naming the path when it cannot be opened or its header is not the one above.
  explicit ImuFile(const std::string& path);
  /// The next well-formed sample, nullopt at the end of the file.
  std::optional<firefighter::ImuSample> next();
  std::size_t skipped_rows() const { return skipped_; }
  std::size_t line_number() const { return line_number_; }

  static constexpr const char* kHeader = "t_s,ax_mps2,ay_mps2,az_mps2,gx_radps,gy_radps,gz_radps";

 private:
  std::ifstream in_;
  std::string path_;
  std::size_t line_number_ = 0;
  std::size_t skipped_ = 0;
  std::optional<double> last_t_;
};

}  // namespace sarloc::rescuer
