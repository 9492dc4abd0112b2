#include "sarloc/core/avalanche/stall_detector.hpp"

#include <cmath>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::avalanche {

StallDetector::StallDetector(int window_steps, double min_improvement)
    : window_steps_(window_steps), min_improvement_(min_improvement) {
  if (window_steps_ <= 0 || !(min_improvement_ >= 0.0 && min_improvement_ < 1.0)) {
    throw ConfigError("StallDetector: window_steps = " + config_value(window_steps) +
                      ", min_improvement = " + config_value(min_improvement) + ": must be > 0 and in [0, 1)");
  }
}

bool StallDetector::add(double radius) {
  if (std::isfinite(radius) && (!best_ || radius < (1.0 - min_improvement_) * *best_)) {
    best_ = radius;
    steps_since_improvement_ = 0;
  } else {
    ++steps_since_improvement_;
  }
  return stalled();
}

void StallDetector::reset() {
  best_.reset();
  steps_since_improvement_ = 0;
}

}  // namespace sarloc::avalanche
