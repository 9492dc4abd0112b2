#pragma once
// The map-error flag of the floor-plan particle filter (seed 004 section V-E): raised when a
// converged cloud stops fitting the plan, cleared once it has fitted again for a while. Kept apart
// from the filter so that its alarm logic, which reaches incident command's board as
// ALARM_MAP_ERROR, is tested on its own.
#include <cstdint>

namespace sarloc::firefighter {

struct MapErrorFlagConfig {
  double converged_variance_m2 = 3.0;  ///< concentrated under this horizontal variance (trace)
  /// A concentrated cloud that spreads raises the flag only past this many times
  /// converged_variance_m2: a deadband (ISA-18.2), since a cloud whose variance hovers at the
  /// threshold on a plan that is right went in and out of convergence and raised a false alarm
  /// each time (docs/estimation/firefighter.md, "False map errors").
  double spread_factor = 2.0;
  double removed_fraction = 0.5;     ///< one step removing more of the weight at walls raises it
  /// Concentrated refreshes in a row that clear it: one per odometry step (2 Hz) and one per
  /// pattern comparison (every 2 m walked), about 25 s at walking pace.
  std::uint32_t clear_updates = 60;
};

/// The cloud at one refresh.
struct CloudSpread {
  double variance_m2 = 0.0;          ///< horizontal position variance (trace) over every particle
  bool split_across_floors = false;  ///< 5-95 % of the weight on another floor
  double removed_weight = 0.0;       ///< the share of the weight this step removed at walls
};

class MapErrorFlag {
 public:
  explicit MapErrorFlag(const MapErrorFlagConfig& config) : config_(config) {}

  /// A new start. `armed`: the cloud is one the map locked (a known start at an entry, an unknown
  /// start); otherwise a prior told by someone else, whose first brushes with walls are no map
  /// error, and the flag arms once it has been concentrated for clear_updates refreshes.
  void restart(bool armed);
  /// One refresh; returns whether the cloud is concentrated now.
  bool refresh(const CloudSpread& cloud);

  bool concentrated() const { return concentrated_; }
  /// Concentrated at some refresh since the flag armed.
  bool ever_concentrated() const { return ever_concentrated_; }
  bool up() const { return up_; }
  /// Raised at some time since the start (it stays said after the flag clears).
  bool since_start() const { return since_start_; }

 private:
  MapErrorFlagConfig config_;
  bool armed_ = true;
  bool concentrated_ = false;
  bool ever_concentrated_ = false;
  bool up_ = false;
  bool since_start_ = false;
  std::uint32_t concentrated_run_ = 0;
};

}  // namespace sarloc::firefighter
