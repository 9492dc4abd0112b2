#include <algorithm>
#include <cmath>
#include <sstream>

#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/avalanche/transmitter_standard.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::avalanche {

double TransmitterStandard::moment_min() const {
  return 4.0 * kPi * std::pow(reference_distance_m, 3) * field_min_A_per_m;
}
double TransmitterStandard::moment_max() const {
  return 4.0 * kPi * std::pow(reference_distance_m, 3) * field_max_A_per_m;
}
double TransmitterStandard::strongest_on_axis_field(double r) const {
  return 2.0 * moment_max() / (4.0 * kPi * r * r * r);
}

bool TransmitterStandard::allows(const Vec3& m, const Mat3& covariance, double margin) const {
  const double magnitude = m.norm();
  if (!(magnitude > 0.0)) return false;
  const Vec3 u = m / magnitude;
  const double sd = std::sqrt(std::max(0.0, u.dot(covariance * u)));
  const double lo = moment_min() * (1.0 - margin);
  const double hi = moment_max() * (1.0 + margin);
  return magnitude + 2.0 * sd >= lo && magnitude - 2.0 * sd <= hi;
}

void TransmitterStandard::validate(const std::string& prefix) const {
  require(std::isfinite(field_min_A_per_m) && field_min_A_per_m > 0.0 && field_min_A_per_m <= 1e-3,
          prefix + ".field_min_A_per_m", field_min_A_per_m, "must be in (0, 1e-3]");
  require(std::isfinite(field_max_A_per_m) && field_max_A_per_m >= field_min_A_per_m && field_max_A_per_m <= 1e-3,
          prefix + ".field_max_A_per_m", field_max_A_per_m, "must be in [field_min_A_per_m, 1e-3]");
  require(std::isfinite(reference_distance_m) && reference_distance_m > 0.0 && reference_distance_m <= 1000.0,
          prefix + ".reference_distance_m", reference_distance_m, "must be in (0, 1000]");
}

}  // namespace sarloc::avalanche
