#include "imu_file.hpp"

#include <spdlog/spdlog.h>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::rescuer {

ImuFile::ImuFile(const std::string& path, firefighter::ImuSourceFormat format) : in_(path) {
  if (!in_) throw ConfigError("--source '" + path + "': cannot open the IMU file");
  reader_ = std::make_unique<firefighter::ImuSourceReader>(in_, path, std::move(format));
}

std::optional<firefighter::ImuSample> ImuFile::next() {
  auto sample = reader_->next();
  const auto& problems = reader_->problems();
  for (; problems_logged_ < problems.size(); ++problems_logged_) spdlog::warn("{}", problems[problems_logged_]);
  return sample;
}

}  // namespace sarloc::rescuer
