#pragma once
// The recent position fixes of one responder, and his position at a given stamp: incident command
// places a rescuer-relative victim estimate with the fix of the same epoch. Under packet loss
// that very fix can be lost (ResponderPosition keeps only the newest sample per responder), so
// a stamp between two fixes close enough in time is interpolated instead, with the covariance
// widened for a path that need not be straight.
//
//   ResponderTrack track;  track.add(stamp, fix);
//   if (auto p = track.at(estimate.stamp, max_age_ns, max_gap_ns)) place(estimate, *p);
#include <deque>
#include <optional>

#include "sarloc/core/incident/source_estimate.hpp"

namespace sarloc::incident {

class ResponderTrack {
 public:
  /// Keeps the newest `capacity` fixes (in stamp order; a duplicate stamp replaces the fix).
  explicit ResponderTrack(std::size_t capacity = 64) : capacity_(capacity) {}

  void add(TimestampNs stamp, const ReporterFix& fix);

  /// The fix nearest to `stamp` if within `max_age_ns`; otherwise the interpolation between
  /// the fixes just before and just after it if they are at most `max_gap_ns` apart (position
  /// linear in time; covariance the larger of the two plus, horizontally, (gap distance / 4)^2
  /// for a curved path; never across a change of floor or of height reference); otherwise
  /// nullopt.
  std::optional<ReporterFix> at(TimestampNs stamp, TimestampNs max_age_ns, TimestampNs max_gap_ns) const;

  bool empty() const { return fixes_.empty(); }

 private:
  struct Fix {
    TimestampNs stamp = 0;
    ReporterFix fix;
  };
  std::size_t capacity_;
  std::deque<Fix> fixes_;  ///< ascending stamps
};

}  // namespace sarloc::incident
