#pragma once
// One shared central-difference Jacobian for every analytic-Jacobian test (STYLE: manif's
// common tester). J(:, i) = (f(x + h_i e_i) - f(x - h_i e_i)) / (2 h_i), h_i = step * max(1, |x_i|)
// or a per-coordinate step given by the caller (moments are ~1e-2, angles ~1).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>

namespace sarloc::test {

template <int Out, int In>
Eigen::Matrix<double, Out, In> numeric_jacobian(
    const std::function<Eigen::Matrix<double, Out, 1>(const Eigen::Matrix<double, In, 1>&)>& f,
    const Eigen::Matrix<double, In, 1>& x, const Eigen::Matrix<double, In, 1>& steps) {
  Eigen::Matrix<double, Out, In> j;
  for (int i = 0; i < In; ++i) {
    Eigen::Matrix<double, In, 1> xp = x, xm = x;
    xp[i] += steps[i];
    xm[i] -= steps[i];
    j.col(i) = (f(xp) - f(xm)) / (2.0 * steps[i]);
  }
  return j;
}

template <int Out, int In>
Eigen::Matrix<double, Out, In> numeric_jacobian(
    const std::function<Eigen::Matrix<double, Out, 1>(const Eigen::Matrix<double, In, 1>&)>& f,
    const Eigen::Matrix<double, In, 1>& x, double step = 1e-6) {
  Eigen::Matrix<double, In, 1> steps;
  for (int i = 0; i < In; ++i) steps[i] = step * std::max(1.0, std::abs(x[i]));
  return numeric_jacobian<Out, In>(f, x, steps);
}

/// max |A - B| relative to max(|B|_max, floor): the figure every Jacobian test bounds.
template <class A, class B>
double relative_error(const A& a, const B& b, double floor = 1e-300) {
  const double scale = std::max(b.cwiseAbs().maxCoeff(), floor);
  return (a - b).cwiseAbs().maxCoeff() / scale;
}

}  // namespace sarloc::test
