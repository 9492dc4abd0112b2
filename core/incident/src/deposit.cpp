#include "sarloc/core/incident/deposit.hpp"

#include <cmath>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"
#include "search_geometry.hpp"

namespace sarloc::incident {

Deposit::Deposit(std::vector<Vec2> outline, const std::string& key) {
  if (outline.size() >= 2 && outline.front() == outline.back()) outline.pop_back();
  if (outline.size() < 3)
    throw ConfigError(key + ": " + std::to_string(outline.size()) + " vertices: an outline needs at least 3");
  for (std::size_t k = 0; k < outline.size(); ++k)
    if (!outline[k].allFinite())
      throw ConfigError(key + "[" + std::to_string(k) + "] = (" + config_value(outline[k].x()) + ", " +
                        config_value(outline[k].y()) + "): not finite");
  geometry::Polygon polygon = geometry::to_polygon(outline);
  // Asked first: for a bow tie is_valid names its orientation, which tells an operator nothing.
  if (boost::geometry::intersects(polygon)) throw ConfigError(key + ": not a simple polygon (its edges cross)");
  std::string why;
  if (!boost::geometry::is_valid(polygon, why)) throw ConfigError(key + ": not a simple polygon (" + why + ")");
  area_m2_ = boost::geometry::area(polygon);
  if (!(area_m2_ > 1.0))
    throw ConfigError(key + ": an area of " + config_value(area_m2_) + " m^2: must be more than 1");
  vertices_ = geometry::to_vertices(polygon);
}

bool Deposit::contains(const Vec2& p) const {
  return boost::geometry::covered_by(geometry::to_point(p), geometry::to_polygon(vertices_));
}

}  // namespace sarloc::incident
