#pragma once
// JSON of sarloc's core types and summaries, written (and read back) in one place with
// nlohmann-json. Key names are part of the tools' documented output (docs/getting-started.md);
// tests read them. The evaluations' summaries are in evaluation_json.hpp.
//
//   app::write_json_file(path, app::to_json(summary));    // throws on I/O failure
#include <nlohmann/json.hpp>
#include <string>

#include "sarloc/core/incident/fused_victim.hpp"
#include "sarloc/core/incident/team_status.hpp"
#include "sarloc/core/mission/firefighter_summary.hpp"
#include "sarloc/core/mission/mission_summary.hpp"

namespace sarloc::app {

nlohmann::json to_json(const Vec3& v);
nlohmann::json to_json(const incident::FusedVictim& victim);
/// One row per member: team_id, responder_id, link, accountability.
nlohmann::json to_json(const std::vector<incident::TeamStatus>& teams);
nlohmann::json to_json(const mission::DeviceSummary& device);
nlohmann::json to_json(const mission::MissionSummary& summary);

/// A firefighter device's summary (role "firefighter"): fixes, convergence, RMSE, alarms.
nlohmann::json to_json(const mission::FirefighterDeviceSummary& firefighter);
/// Throws std::runtime_error naming the key for a document that is not one.
mission::FirefighterDeviceSummary firefighter_summary_from_json(const nlohmann::json& j);

/// Throws std::runtime_error naming the key for a document that is not a device summary.
mission::DeviceSummary device_summary_from_json(const nlohmann::json& j);

/// The names used in JSON and on the rescuer's display ("FOUND", ...).
const char* status_name(responder::EstimatorStatus status);

/// Writes `j` (indented) to `path`; throws std::runtime_error naming the path if it cannot.
void write_json_file(const std::string& path, const nlohmann::json& j);

}  // namespace sarloc::app
