#include "sarloc/core/incident/gnss_fix.hpp"

#include <algorithm>
#include <cmath>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::incident {
namespace {

void check_sigma(const char* field, double sigma) {
  if (!(std::isfinite(sigma) && sigma > 0.0 && sigma <= kMaxFixSigmaM)) {
    throw InputError(std::string("gnss.") + field + " = " + config_value(sigma) + ": must be in (0, " +
                     config_value(kMaxFixSigmaM) + "]");
  }
}

}  // namespace

GaussianPosition in_incident_frame(const GeodeticFrame& frame, const GnssFix& fix) {
  check_sigma("horizontal_sigma_m", fix.horizontal_sigma_m);
  check_sigma("vertical_sigma_m", fix.vertical_sigma_m);
  GaussianPosition p;
  p.position = frame.to_enu(fix.position);
  const double distance = p.position.head<2>().norm();
  if (distance > kMaxFixDistanceM) {
    throw InputError("gnss fix at " + format_wgs84(fix.position) + " is " + config_value(distance / 1000.0) +
                     " km from the incident's origin: at most " + config_value(kMaxFixDistanceM / 1000.0) + " km");
  }
  const double h2 = fix.horizontal_sigma_m * fix.horizontal_sigma_m;
  p.covariance = Vec3(h2, h2, fix.vertical_sigma_m * fix.vertical_sigma_m).asDiagonal();
  return p;
}

GnssFix as_receiver_fix(const GeodeticFrame& frame, TimestampNs stamp, const GaussianPosition& position) {
  GnssFix fix;
  fix.stamp = stamp;
  fix.position = frame.to_wgs84(position.position);
  fix.horizontal_sigma_m = std::sqrt(std::max(position.covariance(0, 0), position.covariance(1, 1)));
  fix.vertical_sigma_m = std::sqrt(position.covariance(2, 2));
  return fix;
}

}  // namespace sarloc::incident
