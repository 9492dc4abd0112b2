#pragma once
// The stance decision on a zero-velocity detector's statistic T (SHOE, zupt_ins.hpp), adapted
// to the sensor and the gait. A fixed threshold fits one sensor and one gait: on the x-io and
// OpenShoe boots a walking stance reads T ~ 1e2-1e4 and a swing 1e5-1e6, on the MicroStrain
// GX5 of the gait-driven walks a stance reads 2e4-1e5 and a swing 1e6-1e7 (measured, docs/
// estimation/firefighter.md "Real recordings"). So the threshold sits halfway, in log T,
// between the recent stance level (a low percentile of log T over the last window_s) and the
// swing level (a high percentile), never below `floor` (T under it is always a stance: the
// fixed threshold that serves the simulated gaits, crawling included) and with hysteresis
// (enter below mid - h, leave above mid + h, h = hysteresis x (swing - stance level)).
// Percentiles come from a histogram of log T in 0.05-decade bins: O(bins) per sample.
#include <cstdint>
#include <deque>
#include <vector>

namespace sarloc::firefighter {

/// Which zero-velocity test decides a stance (Skog et al. 2010): SHOE alone, or a vote of SHOE,
/// ARED (angular rate energy: the gyro term of SHOE) and AMVD (acceleration moving variance),
/// a stance when `stance_votes` of the three say so, each against the same threshold (fixed, or
/// adapted on its own statistic). Measured on the shared recordings, neither vote beat SHOE
/// overall (docs/estimation/firefighter.md, "Detectors combined"): every shipped source keeps SHOE.
enum class StanceDetector : unsigned char { kShoe, kVote };

struct StanceThresholdConfig {
  double floor = 1e4;
  double ceiling = 1e7;   ///< never above: a sensor at rest never reaches it
  double window_s = 3.0;  ///< a couple of gait cycles
  double stance_quantile = 0.05;
  double swing_quantile = 0.8;
  double hysteresis = 0.1;
  void validate() const;
};

class StanceThreshold {
 public:
  explicit StanceThreshold(StanceThresholdConfig config);
  /// One sample's statistic (rate_hz: the sample rate, for the window); true in stance.
  bool push(double statistic, double rate_hz);
  /// The current threshold (T units), for reports.
  double threshold() const;

 private:
  int bin_of(double log_t) const;
  double quantile(double q) const;

  StanceThresholdConfig config_;
  std::vector<std::uint32_t> counts_;
  std::deque<int> window_;
  bool stance_ = true;
  double mid_log_ = 0.0;
};

}  // namespace sarloc::firefighter
