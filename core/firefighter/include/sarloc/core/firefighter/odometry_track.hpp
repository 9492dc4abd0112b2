#pragma once
// The odometry trajectory the pattern comparison reads (seed 004 section IV-D): INS positions
// in the INS navigation frame at the odometry rate (2 Hz, section V-B), the distance walked,
// and when the next comparison is due (every `compare_every_m` walked).
//
//   OdometryTrack track(PatternMatchConfig{});
//   track.add(ins_position);
//   if (track.comparison_due()) { obs = matcher.compare(track.recent()); track.compared(); }
#include <Eigen/Core>
#include <deque>
#include <vector>

#include "sarloc/core/firefighter/pattern_matcher.hpp"

namespace sarloc::firefighter {

class OdometryTrack {
 public:
  explicit OdometryTrack(PatternMatchConfig config);

  void add(const Eigen::Vector3d& position);
  bool comparison_due() const;
  void compared();
  /// The last pattern_length_m of horizontal positions, oldest first.
  std::vector<Vec2> recent() const;
  /// Walking direction (INS frame) over the last metre.
  double walk_heading() const;
  double walked_m() const { return walked_; }

 private:
  PatternMatchConfig config_;
  std::deque<Vec2> points_;
  std::deque<double> along_;  ///< distance walked at each point
  double walked_ = 0.0;
  double compared_at_ = 0.0;
};

}  // namespace sarloc::firefighter
