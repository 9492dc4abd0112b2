#include "sarloc/core/incident/covariance_intersection.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::incident {
namespace {

[[noreturn]] void input_fail(std::size_t i, const char* rule) {
  throw InputError("covariance_intersection.inputs[" + std::to_string(i) + "]: " + rule);
}

Mat3 inverse_spd(const Mat3& p, std::size_t i) {
  const Mat3 sym = 0.5 * (p + p.transpose());
  Eigen::LLT<Mat3> llt(sym);
  if (llt.info() != Eigen::Success) input_fail(i, "covariance must be positive definite");
  return llt.solve(Mat3::Identity());
}

// Fuse with given weights; information form (Julier & Uhlmann 1997, eq. (4)-(5)).
GaussianPosition fuse(const std::vector<Vec3>& x, const std::vector<Mat3>& info,
                      const std::vector<double>& w) {
  Mat3 y = Mat3::Zero();
  Vec3 b = Vec3::Zero();
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (w[i] == 0.0) continue;
    y += w[i] * info[i];
    b += w[i] * (info[i] * x[i]);
  }
  GaussianPosition out;
  const Eigen::LLT<Mat3> llt(0.5 * (y + y.transpose()));
  out.covariance = llt.solve(Mat3::Identity());
  out.covariance = 0.5 * (out.covariance + out.covariance.transpose()).eval();
  out.position = out.covariance * b;
  return out;
}

// Optimal w for two sources: minimise tr((w Y1 + (1-w) Y2)^-1), convex in w.
double min_trace_weight(const Mat3& y1, const Mat3& y2) {
  auto tr = [&](double w) {
    const Mat3 y = w * y1 + (1.0 - w) * y2;
    return Eigen::LLT<Mat3>(y).solve(Mat3::Identity()).trace();
  };
  constexpr double kInvPhi = 0.6180339887498949;
  double lo = 0.0, hi = 1.0;
  double c = hi - kInvPhi * (hi - lo), d = lo + kInvPhi * (hi - lo);
  double fc = tr(c), fd = tr(d);
  for (int it = 0; it < 60 && hi - lo > 1e-10; ++it) {
    if (fc < fd) {
      hi = d; d = c; fd = fc;
      c = hi - kInvPhi * (hi - lo); fc = tr(c);
    } else {
      lo = c; c = d; fc = fd;
      d = lo + kInvPhi * (hi - lo); fd = tr(d);
    }
  }
  const double w = 0.5 * (lo + hi);
  // The optimum may sit on the boundary (one source dominates): compare with the ends.
  const double f0 = tr(0.0), f1 = tr(1.0), fw = tr(w);
  if (f1 <= fw && f1 <= f0) return 1.0;
  if (f0 <= fw) return 0.0;
  return w;
}

}  // namespace

CiResult covariance_intersection(const std::vector<GaussianPosition>& inputs,
                                 CiWeighting weighting) {
  if (inputs.empty()) throw InputError("covariance_intersection.inputs: must not be empty");
  const std::size_t n = inputs.size();
  std::vector<Vec3> x(n);
  std::vector<Mat3> info(n);
  std::vector<double> trace(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!inputs[i].position.allFinite()) input_fail(i, "position must be finite");
    if (!inputs[i].covariance.allFinite()) input_fail(i, "covariance must be finite");
    x[i] = inputs[i].position;
    info[i] = inverse_spd(inputs[i].covariance, i);
    trace[i] = inputs[i].covariance.trace();
  }
  CiResult r;
  if (n == 1) {
    r.fused = inputs[0];
    r.weights = {1.0};
    return r;
  }
  if (weighting == CiWeighting::kInverseTrace) {
    r.weights.resize(n);
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) sum += (r.weights[i] = 1.0 / trace[i]);
    for (double& w : r.weights) w /= sum;
    r.fused = fuse(x, info, r.weights);
    return r;
  }
  // kMinTrace: pairwise in order of increasing trace. Effective weight of source i is the
  // product of the weights it received at each later stage.
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return trace[a] < trace[b]; });
  r.weights.assign(n, 0.0);
  r.weights[order[0]] = 1.0;
  Vec3 acc_x = x[order[0]];
  Mat3 acc_y = info[order[0]];
  for (std::size_t k = 1; k < n; ++k) {
    const std::size_t j = order[k];
    const double w = min_trace_weight(acc_y, info[j]);
    for (std::size_t i = 0; i < k; ++i) r.weights[order[i]] *= w;
    r.weights[j] = 1.0 - w;
    const GaussianPosition f = fuse({acc_x, x[j]}, {acc_y, info[j]}, {w, 1.0 - w});
    acc_x = f.position;
    acc_y = Eigen::LLT<Mat3>(f.covariance).solve(Mat3::Identity());
  }
  r.fused = fuse(x, info, r.weights);  // same as the sequential result, information form
  return r;
}

}  // namespace sarloc::incident
