#pragma once
// How much of the recorded avalanche deposit the rescuers' recorded walks searched: the strips
// incident command's planner cuts it into for them (search_strips.hpp, default width, one per
// rescuer when more), each with the share of its cells a track passed within half a strip width
// of (SearchCoverage), and the deposit's. For the report's table and its GeoJSON.
#include <vector>

#include "mission_record.hpp"
#include "sarloc/app/incident_geojson.hpp"

namespace sarloc::report {

struct RecordedCoverage {
  std::vector<app::GeoJsonStrip> strips;
  double deposit_searched = 0.0;  ///< share of the deposit's cells
};

/// Nullopt without a recorded deposit.
std::optional<RecordedCoverage> recorded_coverage(const MissionRecord& record);

}  // namespace sarloc::report
