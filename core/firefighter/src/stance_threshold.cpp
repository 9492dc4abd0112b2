#include "sarloc/core/firefighter/stance_threshold.hpp"

#include <algorithm>
#include <cmath>

#include "sarloc/core/common/validate.hpp"

namespace sarloc::firefighter {
namespace {

constexpr double kLogLo = -2.0, kLogHi = 12.0, kBin = 0.05;  // T from 1e-2 to 1e12
constexpr int kBins = static_cast<int>((kLogHi - kLogLo) / kBin) + 1;

}  // namespace

void StanceThresholdConfig::validate() const {
  check_range("ins", "stance_floor", floor, 1.0, 1e9);
  check_range("ins", "stance_ceiling", ceiling, floor, 1e11);
  check_range("ins", "stance_window_s", window_s, 0.5, 30.0);
  check_range("ins", "stance_quantile", stance_quantile, 0.0, 0.5);
  check_range("ins", "swing_quantile", swing_quantile, stance_quantile, 1.0);
  check_range("ins", "stance_hysteresis", hysteresis, 0.0, 0.5);
}

StanceThreshold::StanceThreshold(StanceThresholdConfig config)
    : config_((config.validate(), config)), counts_(kBins, 0), mid_log_(std::log10(config.floor)) {}

int StanceThreshold::bin_of(double log_t) const {
  return std::clamp(static_cast<int>((log_t - kLogLo) / kBin), 0, kBins - 1);
}

double StanceThreshold::quantile(double q) const {
  const auto target = static_cast<std::uint32_t>(q * static_cast<double>(window_.size() - 1));
  std::uint32_t seen = 0;
  for (int b = 0; b < kBins; ++b) {
    seen += counts_[static_cast<std::size_t>(b)];
    if (seen > target) return kLogLo + (b + 0.5) * kBin;
  }
  return kLogHi;
}

bool StanceThreshold::push(double statistic, double rate_hz) {
  const double log_t = std::log10(std::max(statistic, 1e-12));
  const int bin = bin_of(log_t);
  window_.push_back(bin);
  ++counts_[static_cast<std::size_t>(bin)];
  const auto keep = static_cast<std::size_t>(std::max(1.0, config_.window_s * rate_hz));
  while (window_.size() > keep) {
    --counts_[static_cast<std::size_t>(window_.front())];
    window_.pop_front();
  }
  const double stance_level = quantile(config_.stance_quantile), swing_level = quantile(config_.swing_quantile);
  mid_log_ = std::clamp(0.5 * (stance_level + swing_level), std::log10(config_.floor), std::log10(config_.ceiling));
  const double h = config_.hysteresis * (swing_level - stance_level);
  stance_ = statistic < config_.floor || log_t < (stance_ ? mid_log_ + h : mid_log_ - h);
  return stance_;
}

double StanceThreshold::threshold() const { return std::pow(10.0, mid_log_); }

}  // namespace sarloc::firefighter
