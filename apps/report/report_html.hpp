#pragma once
// The post-mission report: one self-contained HTML file (inline CSS and SVG, no script, no
// external asset) that an incident commander reads after the mission.
#include <string>

#include "basemap.hpp"
#include "mission_record.hpp"

namespace sarloc::report {

/// The report of `record`; with `baseline`, also how `record` differs from it (two recordings
/// of the same inputs replayed with different configurations); with `basemap`, its tiles under
/// the avalanche field's map, embedded (placed by the recording's WGS-84 origin).
std::string render_report(const MissionRecord& record, const MissionRecord* baseline = nullptr,
                          const app::Basemap* basemap = nullptr);

}  // namespace sarloc::report
