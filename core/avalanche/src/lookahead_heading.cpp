#include "sarloc/core/avalanche/lookahead_heading.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::avalanche {
namespace {

using Hypothesis = TransmitterHypothesis;

// Systematic draw by weight: an even sample of the ring (the heaviest components alone would
// be an arbitrary arc of a near-uniform ring). Repeated draws of a component add up its weight.
std::vector<Hypothesis> draw_hypotheses(const std::vector<TransmitterHypothesis>& components, int count) {
  std::vector<double> cumulative(components.size());
  double total = 0.0;
  for (std::size_t k = 0; k < components.size(); ++k) {
    total += components[k].weight;
    cumulative[k] = total;
  }
  std::vector<Hypothesis> out;
  std::size_t k = 0;
  for (int n = 0; n < count; ++n) {
    const double u = (n + 0.5) / count * total;
    while (k + 1 < components.size() && cumulative[k] < u) ++k;
    if (!out.empty() && out.back().position == components[k].position) {
      out.back().weight += 1.0 / count;
      continue;
    }
    out.push_back({components[k].position, components[k].moment, 1.0 / count});
  }
  return out;
}

double horizontal_distance(const Vec3& a, const Vec3& b) { return (a - b).head<2>().norm(); }

}  // namespace

void LookaheadConfig::validate() const {
  require(hypotheses >= 2 && hypotheses <= 1000, "search.lookahead_hypotheses", hypotheses, "must be in [2, 1000]");
  require(headings >= 2 && headings <= 360, "search.lookahead_headings", headings, "must be in [2, 360]");
  require(horizon_steps >= 1 && horizon_steps <= 100, "search.lookahead_horizon_steps", horizon_steps,
          "must be in [1, 100]");
  require(detour_weight >= 0.0 && detour_weight <= 10.0, "search.lookahead_detour_weight", detour_weight,
          "must be in [0, 10]");
  require(information_scale > 0.0 && information_scale <= 10.0, "search.lookahead_information_scale", information_scale,
          "must be in (0, 10]");
}

double lookahead_heading(const std::vector<TransmitterHypothesis>& hypotheses, const LookaheadConfig& cfg,
                         double step_length_m, const FieldNoiseModel& noise, double floor_A_per_m) {
  if (hypotheses.empty()) throw std::invalid_argument("lookahead_heading: empty mixture");
  const std::vector<Hypothesis> hyp = draw_hypotheses(hypotheses, cfg.hypotheses);
  const Eigen::Index n = static_cast<Eigen::Index>(hyp.size());
  const int steps = cfg.horizon_steps;
  // Fields in units of the noise floor (keeps the squares near 1). Row i of `field` holds
  // hypothesis i's predictions along the walk; `scaled` the same times its inverse variances.
  Eigen::MatrixXd field(n, 3 * steps), scaled(n, 3 * steps), inv_var(n, steps), sq_norm(n, steps);
  Eigen::VectorXd to_end(n), log_q(n), log_w(n);
  Eigen::MatrixXd apart(n, n);  // horizontal distance between hypotheses
  for (Eigen::Index i = 0; i < n; ++i) {
    log_w(i) = std::log(hyp[i].weight);
    for (Eigen::Index j = 0; j < n; ++j) apart(i, j) = horizontal_distance(hyp[i].position, hyp[j].position);
  }

  double best_cost = std::numeric_limits<double>::infinity();
  double best_heading = 0.0;
  for (int k = 0; k < cfg.headings; ++k) {
    const double theta = -kPi + 2.0 * kPi * k / cfg.headings;
    const Vec3 dir(std::cos(theta), std::sin(theta), 0.0);
    for (Eigen::Index i = 0; i < n; ++i) {
      for (int t = 0; t < steps; ++t) {
        const Vec3 receiver = (t + 1) * step_length_m * dir;
        Vec3 r = receiver - hyp[i].position;
        if (r.squaredNorm() < 1e-6) r = Vec3(0.0, 0.0, 1e-3);  // walking over a hypothesis
        const Vec3 h = DipoleField::field(r, hyp[i].moment) / floor_A_per_m;
        const double sigma = noise.sigma(h.norm(), 1.0);
        field.block<1, 3>(i, 3 * t) = h.transpose();
        scaled.block<1, 3>(i, 3 * t) = h.transpose() / (sigma * sigma);
        inv_var(i, t) = 1.0 / (sigma * sigma);
        sq_norm(i, t) = h.squaredNorm();
      }
    }
    const Vec3 end = steps * step_length_m * dir;
    for (Eigen::Index i = 0; i < n; ++i) to_end(i) = horizontal_distance(end, hyp[i].position);
    // D_ij = sum_t |h_i(t) - h_j(t)|^2 / sigma_i(t)^2, expanded into matrix products.
    const Eigen::MatrixXd d2 =
        (inv_var.cwiseProduct(sq_norm).rowwise().sum()).replicate(1, n) +
        inv_var * sq_norm.transpose() - 2.0 * scaled * field.transpose();

    double cost = 0.0;
    for (Eigen::Index i = 0; i < n; ++i) {
      log_q = log_w - 0.5 * cfg.information_scale * d2.row(i).transpose().cwiseMax(0.0);
      const double max_lq = log_q.maxCoeff();
      double norm = 0.0;
      double detour = 0.0;
      for (Eigen::Index j = 0; j < n; ++j) {
        if (log_q(j) - max_lq < -30.0) continue;  // q < 1e-13: saves the exp on most pairs
        const double q = std::exp(log_q(j) - max_lq);
        norm += q;
        if (j != i)
          detour += q * (to_end(j) + apart(i, j) - to_end(i));
      }
      cost += hyp[i].weight * (to_end(i) + cfg.detour_weight * detour / norm);
    }
    if (cost < best_cost) {
      best_cost = cost;
      best_heading = theta;
    }
  }
  return best_heading;
}

}  // namespace sarloc::avalanche
