#include "sarloc/core/avalanche/pulse_timing.hpp"

#include <cmath>

namespace sarloc::avalanche {

double TimingFit::sigmas() const { return std::fabs(innovation_s) / std::sqrt(variance_s2); }

double PulseTiming::period_sigma_s() const { return period_s_ ? std::sqrt(covariance_(1, 1)) : 0.0; }

namespace {

struct Prediction {
  double periods;
  Eigen::Vector2d state;
  Eigen::Matrix2d covariance;
};

Prediction predict(double last_start, double period, const Eigen::Matrix2d& covariance, double start_s,
                   double jitter_s) {
  const double k = std::round((start_s - last_start) / period);
  Eigen::Matrix2d f;
  f << 1.0, k, 0.0, 1.0;
  Eigen::Matrix2d c = f * covariance * f.transpose();
  c(0, 0) += std::fabs(k) * jitter_s * jitter_s;
  return {k, Eigen::Vector2d(last_start + k * period, period), c};
}

}  // namespace

std::optional<TimingFit> PulseTiming::fit(double start_s, double edge_sigma_s) const {
  if (!last_start_s_ || !period_s_) return std::nullopt;
  const Prediction p = predict(*last_start_s_, *period_s_, covariance_, start_s, config_.clock_jitter_s);
  return TimingFit{p.periods, start_s - p.state(0), p.covariance(0, 0) + edge_sigma_s * edge_sigma_s};
}

void PulseTiming::update(double start_s, double edge_sigma_s) {
  const double r = edge_sigma_s * edge_sigma_s;
  if (!last_start_s_) {
    last_start_s_ = start_s;
    covariance_(0, 0) = r;
    covariance_(0, 1) = covariance_(1, 0) = 0.0;
    return;
  }
  if (!period_s_) {
    const double gap = start_s - *last_start_s_;
    if (gap >= config_.min_period_s && gap <= config_.max_period_s) {
      // Period = difference of two starts: correlated with the newer start.
      period_s_ = gap;
      const double previous = covariance_(0, 0);
      covariance_ << r, r, r, r + previous;
    } else {
      covariance_(0, 0) = r;  // not one period apart: this pulse becomes the phase reference
    }
    last_start_s_ = start_s;
    return;
  }
  const Prediction p = predict(*last_start_s_, *period_s_, covariance_, start_s, config_.clock_jitter_s);
  if (p.periods < 1.0) return;  // the pulse already anchored (or an earlier one): nothing new
  const double s = p.covariance(0, 0) + r;
  const Eigen::Vector2d gain = p.covariance.col(0) / s;
  const Eigen::Vector2d state = p.state + gain * (start_s - p.state(0));
  covariance_ = p.covariance - gain * p.covariance.row(0);
  last_start_s_ = state(0);
  period_s_ = state(1);
}

void PulseTiming::reanchor() {
  last_start_s_.reset();
  if (period_s_) {
    covariance_.setZero();
    covariance_(1, 1) = config_.reanchor_period_sigma_s * config_.reanchor_period_sigma_s;
  }
}

}  // namespace sarloc::avalanche
