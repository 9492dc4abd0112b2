#pragma once
// A simulated mission's digs (simulation.dig_out_after_s): the device that FOUND a victim
// reports it dug out some mission seconds later, as its finder would after digging, and
// switches its transmitter off (the true one nearest the picture's victim): every simulated
// receiver of the mission stops hearing it at once, through the shared SimulatedWorld, as on a
// real dig. A dig reported by someone else (an operator) silences the transmitter when the
// picture says its victim is dug out. A real device does neither: its rescuer marks the dig
// on the dashboard and switches the transmitter off by hand.
#include <cstdint>
#include <map>
#include <set>

#include "sarloc/core/mission/mission_scenario.hpp"
#include "sarloc/dds/rescuer_node.hpp"
#include "sensor_source.hpp"
#include "simulated_world.hpp"

namespace sarloc::rescuer {

struct SimulatedDigs {
  std::map<std::uint32_t, TimestampNs> found_since;  ///< own signal -> first epoch it was FOUND
  std::set<std::uint32_t> reported;                  ///< victims this device reported dug out
  SimulatedWorld world;                              ///< the mission's shared switch-offs
};

/// A picture's dug-out victim switches off the true transmitter nearest its position within
/// this reach (m): a FOUND estimate is well inside it, another victim seldom is.
inline constexpr double kSwitchOffReachM = 3.0;

/// One epoch of the above, after node.epoch() returned `epoch`.
void simulate_digs(dds::RescuerNode& node, SensorSource& sensors, const mission::MissionScenario& scenario,
                   const dds::EpochResult& epoch, TimestampNs stamp, SimulatedDigs& digs);

}  // namespace sarloc::rescuer
