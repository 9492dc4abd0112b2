#pragma once
// Where each sector of an incident lies, and so which sector's core daemon serves a device
// where it stands (issue 64, item 4). A device moves to the sector whose area it walks into:
// its samples then reach that sector's daemon, which takes its estimator over from the daemon
// of the sector it left (docs/architecture.md, "Hand-over between sectors").
//
// The rule, with hysteresis so that a rescuer walking along a border does not hand his filters
// back and forth at every step: a device stays in its sector while inside its area or within
// `margin_m` of it; beyond that, it moves to the sector whose area holds it; between areas, it
// stays where it was.
//
//   const SectorAreas areas({{"west", west_outline}, {"east", east_outline}}, 5.0, "sectors");
//   sector = areas.sector_for(sector, fix);   // each epoch, with the device's own position
#include <string>
#include <vector>

#include "sarloc/core/incident/deposit.hpp"

namespace sarloc::incident {

class SectorAreas {
 public:
  struct Area {
    std::string sector;
    std::vector<Vec2> outline;  ///< incident frame (east, north; m), any orientation
  };
  /// Throws ConfigError naming `key` and the sector: an outline that is no simple polygon
  /// (incident::Deposit's rules), two areas that overlap, a margin not in [0, 100] m.
  SectorAreas(std::vector<Area> areas, double margin_m, const std::string& key);
  SectorAreas() = default;

  bool empty() const { return areas_.empty(); }
  const std::vector<Area>& areas() const { return areas_; }
  double margin_m() const { return margin_m_; }
  /// The sector of a device at `position` (incident frame) that is in `current` (the rule above).
  std::string sector_for(const std::string& current, const Vec2& position) const;

 private:
  std::vector<Area> areas_;  ///< outlines checked and counter-clockwise
  double margin_m_ = 0.0;
};

}  // namespace sarloc::incident
