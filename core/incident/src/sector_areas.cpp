#include "sarloc/core/incident/sector_areas.hpp"

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"
#include "search_geometry.hpp"

namespace sarloc::incident {

SectorAreas::SectorAreas(std::vector<Area> areas, double margin_m, const std::string& key) : margin_m_(margin_m) {
  if (!(margin_m >= 0.0 && margin_m <= 100.0)) {
    throw ConfigError(key + " margin = " + config_value(margin_m) + ": must be in [0, 100] m");
  }
  for (auto& area : areas) {
    area.outline = Deposit(std::move(area.outline), key + "[" + area.sector + "].area").vertices();
  }
  for (std::size_t i = 0; i < areas.size(); ++i) {
    for (std::size_t j = i + 1; j < areas.size(); ++j) {
      geometry::MultiPolygon common;
      boost::geometry::intersection(geometry::to_polygon(areas[i].outline), geometry::to_polygon(areas[j].outline),
                                    common);
      if (boost::geometry::area(common) > 1e-6) {
        throw ConfigError(key + ": the areas of '" + areas[i].sector + "' and '" + areas[j].sector + "' overlap by " +
                          config_value(boost::geometry::area(common)) + " m^2: a place belongs to one sector");
      }
    }
  }
  areas_ = std::move(areas);
}

std::string SectorAreas::sector_for(const std::string& current, const Vec2& position) const {
  if (!position.allFinite()) return current;
  const auto at = geometry::to_point(position);
  for (const auto& area : areas_) {
    if (area.sector == current && boost::geometry::distance(at, geometry::to_polygon(area.outline)) <= margin_m_) {
      return current;
    }
  }
  for (const auto& area : areas_) {
    if (boost::geometry::covered_by(at, geometry::to_polygon(area.outline))) return area.sector;
  }
  return current;
}

}  // namespace sarloc::incident
