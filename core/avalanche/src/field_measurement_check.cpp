#include "sarloc/core/avalanche/field_measurement_check.hpp"

#include <Eigen/Cholesky>
#include <cmath>

#include "sog_filter_detail.hpp"

namespace sarloc::avalanche {

using sog_detail::input_fail;
using sog_detail::vec_text;

void validate_field_measurement(const FieldMeasurement& m) {
  if (!m.field.allFinite()) input_fail("field", vec_text(m.field), "must be finite");
  if (m.field.norm() > 10.0) input_fail("field", vec_text(m.field), "|field| must be <= 10 A/m");
  if (!m.noise_stddev.allFinite() || m.noise_stddev.minCoeff() < 0.0 ||
      m.noise_stddev.maxCoeff() > 1.0)
    input_fail("noise_stddev", vec_text(m.noise_stddev), "must be finite and in [0, 1] A/m");
  if (m.valid_axes > kAllAxes)
    input_fail("valid_axes", std::to_string(m.valid_axes), "must be a mask of axes 0-2 (0..7; 0: a pulse due, not heard)");
  if (m.orientation) {
    const auto& o = *m.orientation;
    if (!o.rpy.allFinite() || o.rpy.cwiseAbs().maxCoeff() > kPi + 1e-9)
      input_fail("orientation.rpy", vec_text(o.rpy), "must be finite and within [-pi, pi]");
    if (std::fabs(o.rpy.y()) > 1.4)
      input_fail("orientation.rpy", vec_text(o.rpy), "|pitch| must be <= 1.4 rad (Euler singularity)");
    if (!o.covariance.allFinite() || !o.covariance.isApprox(o.covariance.transpose(), 1e-9))
      input_fail("orientation.covariance", "non-finite or asymmetric", "must be symmetric");
    Eigen::LLT<Mat3> llt(o.covariance);
    if (llt.info() != Eigen::Success || o.covariance.diagonal().minCoeff() <= 0.0)
      input_fail("orientation.covariance", "diag " + vec_text(o.covariance.diagonal()),
                 "must be positive definite");
  }
}

}  // namespace sarloc::avalanche
