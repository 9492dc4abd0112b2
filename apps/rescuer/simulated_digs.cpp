#include "simulated_digs.hpp"

#include <spdlog/spdlog.h>

#include "sarloc/core/common/time_units.hpp"

namespace sarloc::rescuer {

void simulate_digs(dds::RescuerNode& node, SensorSource& sensors, const mission::MissionScenario& scenario,
                   const dds::EpochResult& epoch, TimestampNs stamp, SimulatedDigs& digs) {
  for (const auto& [victim_id, where] : node.take_recovered()) {
    if (const auto index = sensors.switch_off_transmitter_near(where, kSwitchOffReachM)) {
      spdlog::info("victim {} dug out: the transmitter of '{}' is switched off", victim_id,
                   scenario.victims[*index].name);
    } else {
      spdlog::warn("victim {} dug out, but no transmitter within {} m of it: nothing switched off", victim_id,
                   kSwitchOffReachM);
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
    if (!victim || !digs.reported.insert(*victim).second) continue;
    if (node.report_dug_out(*victim)) {
      spdlog::info("signal {}: victim {} dug out ({:.0f} s after FOUND, simulated)", signal, *victim,
                   ns_to_seconds(stamp - since));
    } else {
      spdlog::error("DDS refused the report that victim {} is dug out", *victim);
    }
  }
}

}  // namespace sarloc::rescuer
