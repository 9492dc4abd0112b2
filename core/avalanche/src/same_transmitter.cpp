#include "sarloc/core/avalanche/same_transmitter.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>

namespace sarloc::avalanche {
namespace {

using Vec6d = Eigen::Matrix<double, 6, 1>;
using Mat6d = Eigen::Matrix<double, 6, 6>;

Vec6d position_and_moment(const StateVec& x, double moment_sign) {
  Vec6d v;
  v << x.segment<3>(idx::kPos), moment_sign * x.segment<3>(idx::kMom);
  return v;
}

Mat6d position_and_moment_covariance(const StateCov& p, double moment_sign) {
  Mat6d c = p.block<6, 6>(idx::kPos, idx::kPos);
  c.block<3, 3>(0, 3) *= moment_sign;  // flipping m flips its cross-covariance with p
  c.block<3, 3>(3, 0) *= moment_sign;
  return c;
}

}  // namespace

double same_transmitter_distance2(const MixtureMoments& a, const MixtureMoments& b) {
  double best = std::numeric_limits<double>::infinity();
  bool tested = false;
  for (const double sign : {1.0, -1.0}) {
    const Vec6d d = position_and_moment(a.mean, 1.0) - position_and_moment(b.mean, sign);
    const Mat6d s = position_and_moment_covariance(a.covariance, 1.0) + position_and_moment_covariance(b.covariance, sign);
    const Eigen::LDLT<Mat6d> ldlt(0.5 * (s + s.transpose()));
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) continue;
    const double d2 = d.dot(ldlt.solve(d));
    if (!std::isfinite(d2)) continue;
    tested = true;
    best = std::min(best, std::max(d2, 0.0));
  }
  // Covariances the test cannot use tell nothing apart: possibly the same transmitter.
  return tested ? best : 0.0;
}

bool moment_determined(const MixtureMoments& m, double relative_spread) {
  const double spread = std::sqrt(std::max(m.covariance.block<3, 3>(idx::kMom, idx::kMom).trace(), 0.0));
  return std::isfinite(spread) && spread < relative_spread * m.mean.segment<3>(idx::kMom).norm();
}

}  // namespace sarloc::avalanche
