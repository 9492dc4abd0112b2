#include "sarloc/core/firefighter/map_error_flag.hpp"

namespace sarloc::firefighter {

void MapErrorFlag::restart(bool armed) {
  armed_ = armed;
  concentrated_ = ever_concentrated_ = up_ = since_start_ = false;
  concentrated_run_ = 0;
}

bool MapErrorFlag::refresh(const CloudSpread& cloud) {
  const bool was = concentrated_;
  concentrated_ = cloud.variance_m2 < config_.converged_variance_m2 && !cloud.split_across_floors;
  if (!armed_) {
    concentrated_run_ = concentrated_ ? concentrated_run_ + 1 : 0;
    armed_ = concentrated_run_ >= config_.clear_updates;
  } else {
    const bool had_converged = was || ever_concentrated_;
    // Spread out of convergence past the deadband, or onto two floors: the paper's flag.
    const bool spread =
        !concentrated_ && ever_concentrated_ &&
        (cloud.split_across_floors || cloud.variance_m2 >= config_.spread_factor * config_.converged_variance_m2);
    if ((cloud.removed_weight > config_.removed_fraction && had_converged) || spread) {
      up_ = true;
      concentrated_run_ = 0;
    } else if (!concentrated_) {
      concentrated_run_ = 0;
    } else if (++concentrated_run_ >= config_.clear_updates) {
      up_ = false;
    }
    since_start_ = since_start_ || up_;
    if (concentrated_) ever_concentrated_ = true;
  }
  return concentrated_;
}

}  // namespace sarloc::firefighter
