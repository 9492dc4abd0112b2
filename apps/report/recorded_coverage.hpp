#pragma once
// How much of the recorded avalanche deposit was searched: incident command's strips and
// coverage as its last recorded search plan had them; for a recording without one (made before
// the plan was published), the strips the planner would cut (search_strips.hpp, default width,
// one per rescuer when more), each with the share of its cells the recorded tracks passed within
// half a strip width of (SearchCoverage). For the report's table and its GeoJSON.
#include <vector>

#include "mission_record.hpp"
#include "sarloc/app/incident_geojson.hpp"

namespace sarloc::report {

struct RecordedCoverage {
  std::vector<app::GeoJsonStrip> strips;
  double deposit_searched = 0.0;  ///< share of the deposit's cells
  bool from_plan = false;         ///< incident command's recorded plan, not recomputed
  std::vector<std::string> rescuers;  ///< per strip, from the plan: who walked it last ("" nobody)
};

/// Nullopt without a recorded deposit.
std::optional<RecordedCoverage> recorded_coverage(const MissionRecord& record);

}  // namespace sarloc::report
