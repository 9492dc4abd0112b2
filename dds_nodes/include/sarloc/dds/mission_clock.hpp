#pragma once
// Time as every node of one mission agrees on it. In the field: the wall clock (speedup 1).
// In a simulated mission: t = epoch + speedup * (wall - wall_at_epoch), so several processes
// started by sarloc-mission stamp samples on one accelerated timeline. A replay (sarloc-replay)
// runs fresh nodes on the recorded timeline: the recorded epoch, reached at a later wall time.
#include <chrono>
#include <cstdint>

#include "sarloc/core/common/time_units.hpp"
#include "sarloc/core/common/types.hpp"

namespace sarloc::dds {

class MissionClock {
 public:
  /// Wall clock, unscaled.
  MissionClock() : MissionClock(wall_now_ns(), 1.0) {}
  /// Mission time `epoch_ns` at wall time `epoch_ns`, running `speedup` times faster.
  MissionClock(TimestampNs epoch_ns, double speedup) : MissionClock(epoch_ns, speedup, epoch_ns) {}
  /// Mission time `epoch_ns` at wall time `wall_at_epoch_ns`.
  MissionClock(TimestampNs epoch_ns, double speedup, TimestampNs wall_at_epoch_ns)
      : epoch_ns_(epoch_ns), speedup_(speedup), wall_at_epoch_ns_(wall_at_epoch_ns) {}

  TimestampNs now() const {
    return epoch_ns_ + static_cast<TimestampNs>(speedup_ * static_cast<double>(wall_now_ns() - wall_at_epoch_ns_));
  }
  /// Wall duration of `mission_seconds` of mission time.
  std::chrono::nanoseconds wall_duration(double mission_seconds) const {
    return std::chrono::nanoseconds(seconds_to_ns(mission_seconds / speedup_));
  }
  double speedup() const { return speedup_; }
  TimestampNs epoch() const { return epoch_ns_; }

  static TimestampNs wall_now_ns() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
        .count();
  }

 private:
  TimestampNs epoch_ns_;
  double speedup_;
  TimestampNs wall_at_epoch_ns_;
};

}  // namespace sarloc::dds
