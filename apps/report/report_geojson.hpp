#pragma once
// A recording as GeoJSON in WGS-84 (sarloc-report --geojson): the deposit and its strips with
// what the recorded tracks searched of each (recorded_coverage.hpp); every responder's track;
// every victim's last estimate with its 95 % ellipse, state and times.
#include <nlohmann/json.hpp>

#include "mission_record.hpp"

namespace sarloc::report {

/// Throws recording::RecordingError when the recording has no WGS-84 origin (no IncidentFrame
/// sample and no mission file): without one nothing can be placed on the earth.
nlohmann::json render_geojson(const MissionRecord& record);

}  // namespace sarloc::report
