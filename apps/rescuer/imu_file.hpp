#pragma once
// A recorded boot IMU file for a firefighter's device (sarloc-rescuer --source FILE), read by its
// IMU source description (--imu-source config/imu/X.yaml; firefighter/imu_source.hpp). Without
// one it is sarloc's boot IMU CSV (docs/configuration.md, "Recorded boot IMU files"):
//   # comments and blank lines are skipped
//   t_s,ax_mps2,ay_mps2,az_mps2,gx_radps,gy_radps,gz_radps      (this header, first)
//   0.00,0.12,-0.03,9.80,0.001,0.000,-0.002
// A row the reader refuses (a cell not a number, a time not after the previous, ...) is skipped
// with a warning naming the file, the line and the field; nothing else is lost.
#include <fstream>
#include <memory>
#include <optional>
#include <string>

#include "sarloc/core/firefighter/imu_sample.hpp"
#include "sarloc/core/firefighter/imu_source.hpp"

namespace sarloc::rescuer {

class ImuFile {
 public:
  /// Throws ConfigError naming the path when it cannot be opened or its header does not have
  /// the columns `format` names.
  explicit ImuFile(const std::string& path, firefighter::ImuSourceFormat format = firefighter::sarloc_csv());
  /// The next sample in the boot frame, nullopt at the end of the file.
  std::optional<firefighter::ImuSample> next();
  std::size_t skipped_rows() const { return reader_->counts().refused(); }
  const firefighter::ImuSourceCounts& counts() const { return reader_->counts(); }

  static constexpr const char* kHeader = "t_s,ax_mps2,ay_mps2,az_mps2,gx_radps,gy_radps,gz_radps";

 private:
  std::ifstream in_;
  std::unique_ptr<firefighter::ImuSourceReader> reader_;
  std::size_t problems_logged_ = 0;
};

}  // namespace sarloc::rescuer
