#include "sarloc/core/avalanche/quiet_span.hpp"

#include <algorithm>
#include <cmath>

namespace sarloc::avalanche {

void QuietSpan::add_window(double w0, double w1, double on_time_s, const std::vector<Interval>& other_pulses,
                           double margin_s) {
  std::vector<Interval> blocked;
  for (const auto& [a, b] : other_pulses) blocked.emplace_back(a - on_time_s - margin_s, b + margin_s);
  std::sort(blocked.begin(), blocked.end());
  double from = w0;
  const double last = w1 - on_time_s;
  for (const auto& [a, b] : blocked) {
    if (a > from && from < last) clear_starts_.emplace_back(from, std::min(a, last));
    from = std::max(from, b);
  }
  if (from < last) clear_starts_.emplace_back(from, last);
  if (clear_starts_.size() > kMaxIntervals) {
    clear_starts_.erase(clear_starts_.begin(), clear_starts_.end() - static_cast<std::ptrdiff_t>(kMaxIntervals));
  }
}

bool QuietSpan::every_phase_covered(double period_s, double period_spread_s) const {
  if (clear_starts_.empty() || !(period_s > 0.0)) return false;
  const double origin = clear_starts_.front().first;
  // Phases (start - origin mod period) covered, each interval narrowed by the drift of a period
  // off by period_spread_s over the periods from the origin to its end.
  std::vector<Interval> phases;
  for (const auto& [a, b] : clear_starts_) {
    const double drift = std::ceil((b - origin) / period_s) * period_spread_s;
    const double lo = a + drift;
    const double hi = b - drift;
    if (hi <= lo) continue;
    if (hi - lo >= period_s) return true;
    const double p_lo = std::fmod(lo - origin, period_s);
    const double p_hi = p_lo + (hi - lo);
    if (p_hi <= period_s) {
      phases.emplace_back(p_lo, p_hi);
    } else {
      phases.emplace_back(p_lo, period_s);
      phases.emplace_back(0.0, p_hi - period_s);
    }
  }
  std::sort(phases.begin(), phases.end());
  double reached = 0.0;
  for (const auto& [lo, hi] : phases) {
    if (lo > reached) return false;
    reached = std::max(reached, hi);
  }
  return reached >= period_s;
}

}  // namespace sarloc::avalanche
