#pragma once
// Simulated firefighters for the latency bench: a mixed incident on one daemon (issue 64).
//
// N firefighters in teams of two search the mission's building, teams alternating its entries
// and both hands and going in 0.4 s apart, each walk drawn as sarloc-rescuer's simulated device
// draws it (mission::SimulatedFirefighter: the real boot model with MTi-3-class errors); past 40,
// members repeat one of the first 40 walks under their own id and entry time. Their boot
// odometry (estimator::FirefighterDevice, about 2 steps a second each) is made before the run,
// so the load generator only publishes it, each step when its stride ends, with the device's own
// position (its dead reckoning, POSITION_DEAD_RECKONING) once a mission second, as
// sarloc-rescuer's device publishes it: the start a daemon that meets the firefighter mid-search
// takes. These devices reckon from the reported entry only (they never take the daemon's fixes,
// made up front as they are), so their reckoning grows 2 % of the distance walked, and ends
// when the entry leaves the device's INS history (history_s, 600 s after going in). The daemon
// answers every step with a map-aided ResponderPosition stamped with the step's end: a
// firefighter's latency is the publication of a step to that answer's arrival.
//
//   FirefighterCrew crew(mission, 200, 600.0, seed);   // seconds of search after each team's entry
//   crew.write_roster(yaml_rescuers);                  // the daemon must know their entries
//   for (const auto& step : crew.schedule()) ...       // in time order; stamps from t = 0
#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "sarloc/app/mission_config.hpp"
#include "sarloc/core/responder/odometry.hpp"
#include "sarloc/core/responder/responder_position.hpp"

namespace sarloc::bench {

class FirefighterCrew {
 public:
  struct Step {
    double at_s = 0.0;             ///< when the stride ends, seconds from the crew's t = 0 (= its interval_end)
    responder::Odometry odometry;  ///< stamps in ns from t = 0: add the run's origin before sending
    /// The device's own position at the step's end, on the steps it publishes one (as the
    /// odometry, stamped from t = 0).
    std::optional<responder::ResponderPosition> reckoning;
  };

  /// Throws ConfigError when n > 0 and the mission has no building: section.
  FirefighterCrew(const app::MissionConfig& mission, std::size_t n, double search_s, std::uint64_t seed);

  std::size_t size() const { return members_.size(); }
  /// Appends the crew to a mission file's rescuers: (role firefighter, team, entry, hand, member).
  void write_roster(YAML::Node& rescuers) const;
  const std::vector<Step>& schedule() const { return schedule_; }

 private:
  std::vector<app::FirefighterEntry> members_;
  std::vector<Step> schedule_;
};

}  // namespace sarloc::bench
