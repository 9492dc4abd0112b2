#include "sarloc/core/incident/responder_track.hpp"

#include <algorithm>
#include <cstdlib>

namespace sarloc::incident {
namespace {
constexpr auto kBeforeStamp = [](const auto& f, TimestampNs s) { return f.stamp < s; };
}  // namespace

void ResponderTrack::add(TimestampNs stamp, const ReporterFix& fix) {
  auto it = std::lower_bound(fixes_.begin(), fixes_.end(), stamp, kBeforeStamp);
  if (it != fixes_.end() && it->stamp == stamp) {
    it->fix = fix;
    return;
  }
  fixes_.insert(it, Fix{stamp, fix});
  while (fixes_.size() > capacity_) fixes_.pop_front();
}

std::optional<ReporterFix> ResponderTrack::at(TimestampNs stamp, TimestampNs max_age_ns,
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
  if (std::llabs(nearest->stamp - stamp) <= max_age_ns) return nearest->fix;
  if (after == fixes_.end() || after == fixes_.begin()) return std::nullopt;  // not bracketed
  const Fix& a = *std::prev(after);
  const Fix& b = *after;
  if (b.stamp - a.stamp > max_gap_ns) return std::nullopt;
  if (a.fix.floor != b.fix.floor || a.fix.heights_above_surface != b.fix.heights_above_surface) return std::nullopt;
  const double alpha = static_cast<double>(stamp - a.stamp) / static_cast<double>(b.stamp - a.stamp);
  const GaussianPosition& pa = a.fix.antenna;
  const GaussianPosition& pb = b.fix.antenna;
  ReporterFix out = a.fix;
  out.antenna.position = (1.0 - alpha) * pa.position + alpha * pb.position;
  out.antenna.covariance = pa.covariance.trace() >= pb.covariance.trace() ? pa.covariance : pb.covariance;
  const double curve = 0.25 * (pb.position - pa.position).head<2>().norm();
  out.antenna.covariance(0, 0) += curve * curve;
  out.antenna.covariance(1, 1) += curve * curve;
  return out;
}

}  // namespace sarloc::incident
