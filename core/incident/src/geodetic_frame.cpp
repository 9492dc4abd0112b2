#include "sarloc/core/incident/geodetic_frame.hpp"

#include <cmath>
#include <cstdio>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::incident {
namespace {

void check_wgs84(const std::string& what, double latitude_deg, double longitude_deg, double altitude_m,
                 bool as_config) {
  const auto fail = [&](const std::string& field, double v, const std::string& rule) {
    const std::string message = what + "." + field + " = " + config_value(v) + ": " + rule;
    if (as_config) throw ConfigError(message);
    throw InputError(message);
  };
  if (!(std::isfinite(latitude_deg) && std::abs(latitude_deg) <= 90.0))
    fail("latitude_deg", latitude_deg, "must be in [-90, 90]");
  if (!(std::isfinite(longitude_deg) && std::abs(longitude_deg) <= 180.0))
    fail("longitude_deg", longitude_deg, "must be in [-180, 180]");
  if (!(std::isfinite(altitude_m) && std::abs(altitude_m) <= 1e5))
    fail("altitude_m", altitude_m, "must be in [-1e5, 1e5]");
}

}  // namespace

GeodeticFrame::GeodeticFrame(const GeodeticOrigin& origin) : origin_(origin) {
  check_wgs84("incident", origin.latitude_deg, origin.longitude_deg, origin.altitude_m, true);
  local_.Reset(origin.latitude_deg, origin.longitude_deg, origin.altitude_m);
}

Vec3 GeodeticFrame::to_enu(const Geodetic& point) const {
  check_wgs84("point", point.latitude_deg, point.longitude_deg, point.altitude_m, false);
  Vec3 enu;
  local_.Forward(point.latitude_deg, point.longitude_deg, point.altitude_m, enu.x(), enu.y(), enu.z());
  return enu;
}

Geodetic GeodeticFrame::to_wgs84(const Vec3& enu) const {
  if (!enu.allFinite()) throw InputError("ENU position not finite");
  Geodetic g;
  local_.Reverse(enu.x(), enu.y(), enu.z(), g.latitude_deg, g.longitude_deg, g.altitude_m);
  return g;
}

std::string format_wgs84(const Geodetic& g) {
  char text[64];
  std::snprintf(text, sizeof text, "%.6f %c, %.6f %c", std::abs(g.latitude_deg), g.latitude_deg < 0.0 ? 'S' : 'N',
                std::abs(g.longitude_deg), g.longitude_deg < 0.0 ? 'W' : 'E');
  return text;
}

}  // namespace sarloc::incident
