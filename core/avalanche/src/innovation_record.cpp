#include "sarloc/core/avalanche/innovation_record.hpp"

#include <algorithm>

#include "sarloc/core/common/chi_square.hpp"

namespace sarloc::avalanche {

InnovationRecord::InnovationRecord(std::uint32_t window, double gate_probability)
    : window_(window),
      window_gate_(window > 0 ? chi_square_quantile(gate_probability, 3.0 * window) : 0.0) {
  window_values_.reserve(window_);
  // ratio_over is asked for on every sample: its gates are found once.
  for (std::size_t n = 1; n <= kHistory; ++n)
    history_gates_[n] = chi_square_quantile(gate_probability, 3.0 * static_cast<double>(n));
}

void InnovationRecord::clear() {
  window_values_.clear();
  history_.clear();
  next_ = 0;
  last_min_nis_ = 0.0;
}

void InnovationRecord::add(double min_nis, int dof, double radius95_before) {
  last_min_nis_ = min_nis;
  history_.push_back({min_nis, dof, radius95_before});
  if (history_.size() > kHistory) history_.pop_front();
  if (window_ == 0) return;
  if (window_values_.size() < window_) window_values_.push_back(min_nis);
  else window_values_[next_] = min_nis;
  next_ = (next_ + 1) % window_;
}

bool InnovationRecord::window_exceeded() const {
  if (window_ == 0 || window_values_.size() < window_) return false;
  double sum = 0.0;
  for (double v : window_values_) sum += v;
  return sum > window_gate_;
}

double InnovationRecord::recent_ratio() const {
  if (window_ == 0 || window_values_.size() < window_) return 0.0;
  double sum = 0.0;
  for (double v : window_values_) sum += v;
  return sum / window_gate_;
}

double InnovationRecord::ratio_over(std::size_t samples) const {
  const std::size_t n = std::min(samples, history_.size());
  if (n == 0) return 0.0;
  double sum = 0.0;
  for (auto it = history_.end() - static_cast<std::ptrdiff_t>(n); it != history_.end(); ++it) sum += it->min_nis;
  return sum / history_gates_[n];
}

InnovationRecord::Sum InnovationRecord::within(double max_radius95, std::size_t samples) const {
  Sum out;
  std::size_t taken = 0;
  for (auto it = history_.rbegin(); it != history_.rend() && taken < samples; ++it) {
    if (it->radius95_before > max_radius95) continue;
    out.nis += it->min_nis;
    out.dof += it->dof;
    ++taken;
  }
  return out;
}

}  // namespace sarloc::avalanche
