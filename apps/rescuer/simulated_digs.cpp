#include "simulated_digs.hpp"

#include <spdlog/spdlog.h>

#include "sarloc/core/common/time_units.hpp"

namespace sarloc::rescuer {

void simulate_digs(dds::RescuerNode& node, SensorSource& sensors, const mission::MissionScenario& scenario,
                   const dds::EpochResult& epoch, TimestampNs stamp, SimulatedDigs& digs) {
  for (const std::size_t index : digs.world.take_switched_off()) {
    if (sensors.switch_off_transmitter(index)) {
      spdlog::info("the transmitter of '{}' is switched off (another rescuer's dig)",
                   index < scenario.victims.size() ? scenario.victims[index].name : std::to_string(index));
    }
  }
  for (const auto& [victim_id, where] : node.take_recovered()) {
    if (const auto index = sensors.switch_off_transmitter_near(where, kSwitchOffReachM)) {
      spdlog::info("victim {} dug out: the transmitter of '{}' is switched off", victim_id,
                   scenario.victims[*index].name);
    } else {
      spdlog::info(
          "victim {} dug out: no transmitter still on within {} m of it (switched off by its digger, or none there)",
          victim_id, kSwitchOffReachM);
    }
  }
  if (scenario.dig_out_after_s <= 0.0) return;
  for (const auto& [signal, status] : epoch.signals)
    if (status == responder::EstimatorStatus::kFound) digs.found_since.emplace(signal, stamp);
  // A found signal leaves the device's list once its rescuer walks out of range: the dig's
  // clock runs from its FOUND all the same.
  for (const auto& [signal, since] : digs.found_since) {
    if (ns_to_seconds(stamp - since) < scenario.dig_out_after_s) continue;
    const auto victim = node.picture_victim_of(signal);
    if (!victim || !digs.reported.insert(victim->victim_id).second) continue;
    if (!node.report_dug_out(victim->victim_id)) {
      spdlog::error("DDS refused the report that victim {} is dug out", victim->victim_id);
      continue;
    }
    spdlog::info("signal {}: victim {} dug out ({:.0f} s after FOUND, simulated)", signal, victim->victim_id,
                 ns_to_seconds(stamp - since));
    if (const auto index = sensors.switch_off_transmitter_near(victim->position, kSwitchOffReachM)) {
      spdlog::info("victim {} dug out here: the transmitter of '{}' is switched off", victim->victim_id,
                   scenario.victims[*index].name);
      digs.world.switched_off(*index);
    }
  }
}

}  // namespace sarloc::rescuer
