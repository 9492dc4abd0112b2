#pragma once
// An indoor map in IMDF (Apple's Indoor Mapping Data Format, OGC Community Standard 20-094: a
// directory of GeoJSON feature collections in WGS-84) -> firefighter::FloorPlan
// (docs/configuration.md, "Indoor maps in IMDF").
//
// The plan frame: metres east (x) and north (y) of the venue's display point (GeographicLib
// LocalCartesian, incident::GeodeticFrame). What is read:
//   level.geojson    a floor per level; its elevation is ordinal x storey_height_m (IMDF gives
//                    no heights); its id the level's short_name (else the feature id)
//   unit.geojson     every edge of every unit's rings is a wall, collinear edges merged into one
//                    (two rooms share the wall between them)
//   opening.geojson  a door (with a `door` property) or an opening on those walls; one that
//                    leads out of every unit of its level is also an entry, 0.5 m inside it
//   detail.geojson   optional: line strings are walls too (an inner wall that bounds no unit)
//   fixture.geojson  optional: furniture, the bounding box of each (the simulated world only)
//   stairs           a `stairs` unit on one level over a `stairs` unit on the level above is a
//                    flight: it leaves the lower level through the opening on its edge there and
//                    reaches the upper level through the opening on its edge there
// Anything it cannot map is a ConfigError naming the file and the feature id.
#include <string>

#include "sarloc/core/firefighter/floor_plan.hpp"

namespace sarloc::app {

struct ImdfImport {
  double storey_height_m = 3.0;  ///< a level's elevation is its ordinal times this
};

/// True when `path` is an IMDF directory (it holds a manifest.json).
bool is_imdf_directory(const std::string& path);

firefighter::FloorPlan load_floor_plan_imdf(const std::string& directory, const ImdfImport& options = {});

}  // namespace sarloc::app
