#include "sarloc/core/incident/responder_track.hpp"

#include <algorithm>
#include <cstdlib>

namespace sarloc::incident {
namespace {
constexpr auto kBeforeStamp = [](const auto& f, TimestampNs s) { return f.stamp < s; };
}  // namespace

void ResponderTrack::add(TimestampNs stamp, const GaussianPosition& antenna) {
  auto it = std::lower_bound(fixes_.begin(), fixes_.end(), stamp, kBeforeStamp);
  if (it != fixes_.end() && it->stamp == stamp) {
    it->antenna = antenna;
    return;
  }
  fixes_.insert(it, Fix{stamp, antenna});
  while (fixes_.size() > capacity_) fixes_.pop_front();
}

std::optional<GaussianPosition> ResponderTrack::at(TimestampNs stamp, TimestampNs max_age_ns,
                                                   TimestampNs max_gap_ns) const {
  if (fixes_.empty()) return std::nullopt;
  const auto after = std::lower_bound(fixes_.begin(), fixes_.end(), stamp, kBeforeStamp);
  // Nearest fix: the first at or after the stamp, or the last before it.
  const Fix* nearest = nullptr;
  if (after != fixes_.end()) nearest = &*after;
  if (after != fixes_.begin()) {
    const Fix& before = *std::prev(after);
    if (nearest == nullptr || stamp - before.stamp < nearest->stamp - stamp) nearest = &before;
  }
  if (std::llabs(nearest->stamp - stamp) <= max_age_ns) return nearest->antenna;
  if (after == fixes_.end() || after == fixes_.begin()) return std::nullopt;  // not bracketed
  const Fix& a = *std::prev(after);
  const Fix& b = *after;
  if (b.stamp - a.stamp > max_gap_ns) return std::nullopt;
  const double alpha = static_cast<double>(stamp - a.stamp) / static_cast<double>(b.stamp - a.stamp);
  GaussianPosition p;
  p.position = (1.0 - alpha) * a.antenna.position + alpha * b.antenna.position;
  p.covariance = a.antenna.covariance.trace() >= b.antenna.covariance.trace() ? a.antenna.covariance
                                                                             : b.antenna.covariance;
  const double curve = 0.25 * (b.antenna.position - a.antenna.position).head<2>().norm();
  p.covariance(0, 0) += curve * curve;
  p.covariance(1, 1) += curve * curve;
  return p;
}

}  // namespace sarloc::incident
