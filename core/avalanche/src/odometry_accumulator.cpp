#include "sarloc/core/avalanche/odometry_accumulator.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <sstream>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::avalanche {
namespace {

[[noreturn]] void bad(const std::string& field, const std::string& value, const char* rule) {
  throw InputError("odometry." + field + " = " + value + ": " + rule);
}

std::string fmt(const Eigen::MatrixXd& m) {
  std::ostringstream os;
  os << m.transpose();
  return "[" + os.str() + "]";
}

}  // namespace

OdometryAccumulator::OdometryAccumulator(double idle_translation_sigma_m,
                                         double idle_rotation_sigma_rad)
    : idle_translation_sigma_m_(idle_translation_sigma_m),
      idle_rotation_sigma_rad_(idle_rotation_sigma_rad) {
  if (!(idle_translation_sigma_m > 0.0) || !std::isfinite(idle_translation_sigma_m))
    throw ConfigError("idle_translation_sigma_m = " + config_value(idle_translation_sigma_m) +
                      ": must be finite and > 0");
  if (!(idle_rotation_sigma_rad > 0.0) || !std::isfinite(idle_rotation_sigma_rad))
    throw ConfigError("idle_rotation_sigma_rad = " + config_value(idle_rotation_sigma_rad) +
                      ": must be finite and > 0");
}

namespace {

void check_covariance(const Mat6& c) {
  if (!c.allFinite()) bad("covariance", "non-finite", "must be finite");
  if (!c.isApprox(c.transpose(), 1e-9)) bad("covariance", "asymmetric", "must be symmetric");
  Eigen::LLT<Mat6> llt(c);
  if (llt.info() != Eigen::Success || c.diagonal().minCoeff() <= 0.0)
    bad("covariance", "diag " + fmt(c.diagonal()), "must be positive definite");
  if (c.diagonal().maxCoeff() > 100.0)
    bad("covariance", "diag " + fmt(c.diagonal()), "variances must be <= 100");
}

}  // namespace

void OdometryAccumulator::add(const Odometry& o) {
  if (!o.translation.allFinite()) bad("translation", fmt(o.translation), "must be finite");
  if (o.translation.norm() > 50.0) bad("translation", fmt(o.translation), "|t| must be <= 50 m");
  if (!o.rotation_rpy.allFinite() || o.rotation_rpy.cwiseAbs().maxCoeff() > kPi + 1e-9)
    bad("rotation_rpy", fmt(o.rotation_rpy), "must be finite and within [-pi, pi]");
  check_covariance(o.covariance);
  if (last_sequence_ && o.sequence <= *last_sequence_)
    bad("sequence", std::to_string(o.sequence),
        ("must be > previous " + std::to_string(*last_sequence_)).c_str());
  last_sequence_ = o.sequence;
  DispVec d;
  d << o.translation, o.rotation_rpy;
  compose(d, o.covariance);
}

void OdometryAccumulator::add_unknown(const DispCov& covariance) {
  check_covariance(covariance);
  compose(DispVec::Zero(), covariance);
}

void OdometryAccumulator::compose(const DispVec& d, const DispCov& covariance) {
  if (acc_.samples == 0) {
    acc_.mean = d;
    acc_.covariance = covariance;
  } else {
    Mat6 j1, j2;
    acc_.mean = compose_displacements(acc_.mean, d, &j1, &j2);
    acc_.covariance = j1 * acc_.covariance * j1.transpose() + j2 * covariance * j2.transpose();
    acc_.covariance = 0.5 * (acc_.covariance + acc_.covariance.transpose()).eval();
  }
  ++acc_.samples;
}

Displacement OdometryAccumulator::pending_displacement() const {
  Displacement out = acc_;
  if (out.samples == 0) {
    out.mean.setZero();
    out.covariance.setZero();
    const double vt = idle_translation_sigma_m_ * idle_translation_sigma_m_;
    const double vr = idle_rotation_sigma_rad_ * idle_rotation_sigma_rad_;
    out.covariance.diagonal() << vt, vt, vt, vr, vr, vr;
  }
  return out;
}

Displacement OdometryAccumulator::take() {
  Displacement out = pending_displacement();
  acc_ = Displacement{};
  return out;
}

}  // namespace sarloc::avalanche
