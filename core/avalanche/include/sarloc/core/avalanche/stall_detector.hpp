#pragma once
// Has the uncertainty stopped shrinking? A patience rule on the 95 % radius of the estimate,
// used by the search controller to end a fine search that can no longer reach the fixed
// "located" radius (docs/estimation/avalanche.md, "The search always ends").
//
// The radius counts as improved when it falls below (1 - min_improvement) times the best
// radius recorded so far; the best is then replaced. The search is stalled once
// `window_steps` consecutive radii brought no such improvement. A search that keeps shrinking
// by at least `min_improvement` per window is never stalled; a plateau, however noisy, is
// stalled after at most `window_steps` steps past its last record (records of a stationary
// sequence become ever rarer, so a plateau always ends).
//
//   StallDetector stall(10, 0.05);
//   for (...) if (stall.add(radius95_3d(cov))) start_probe_pattern();
//   stall.reset();   // when the rescuer leaves the estimate
#include <optional>

namespace sarloc::avalanche {

class StallDetector {
 public:
  /// window_steps > 0 and 0 <= min_improvement < 1 (SearchConfig::validate names the keys).
  StallDetector(int window_steps, double min_improvement);

  /// Adds the radius of this step; true when the last window_steps radii were no improvement.
  bool add(double radius);
  void reset();

  bool stalled() const { return steps_since_improvement_ >= window_steps_; }
  int steps_since_improvement() const { return steps_since_improvement_; }
  /// Best radius recorded (nullopt before the first add()).
  std::optional<double> best() const { return best_; }

 private:
  int window_steps_;
  double min_improvement_;
  std::optional<double> best_;
  int steps_since_improvement_ = 0;
};

}  // namespace sarloc::avalanche
