#pragma once
// A simulated mission's digs (simulation.dig_out_after_s): the device that FOUND a victim
// reports it dug out some mission seconds later, as its finder would after digging, and every
// simulated receiver stops hearing a transmitter once the picture says its victim is dug out
// (rescuers switch a dug-out victim's transmitter off). A real device does neither: its
// rescuer marks the dig on the dashboard and switches the transmitter off by hand.
#include <cstdint>
#include <map>
#include <set>

#include "sarloc/core/mission/mission_scenario.hpp"
#include "sarloc/dds/rescuer_node.hpp"
#include "sensor_source.hpp"

namespace sarloc::rescuer {

struct SimulatedDigs {
  std::map<std::uint32_t, TimestampNs> found_since;  ///< own signal -> first epoch it was FOUND
  std::set<std::uint32_t> reported;                  ///< victims this device reported dug out
};

/// A picture's dug-out victim switches off the true transmitter nearest its position within
/// this reach (m): a FOUND estimate is well inside it, another victim seldom is.
inline constexpr double kSwitchOffReachM = 3.0;

/// One epoch of the above, after node.epoch() returned `epoch`.
void simulate_digs(dds::RescuerNode& node, SensorSource& sensors, const mission::MissionScenario& scenario,
                   const dds::EpochResult& epoch, TimestampNs stamp, SimulatedDigs& digs);

}  // namespace sarloc::rescuer
