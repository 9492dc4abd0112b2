#pragma once
// WGS-84 <-> the incident's ENU frame (x east, y north, z up; metres about the IncidentFrame's
// origin): the one place sarloc converts, with GeographicLib's LocalCartesian (exact on the
// ellipsoid: no flat-earth approximation, which is 0.1 m off at 1 km here).
//
//   const GeodeticFrame frame(origin);                 // ConfigError for an origin out of range
//   Vec3 enu = frame.to_enu({46.95, 7.45, 540.0});
//   Geodetic g = frame.to_wgs84(enu);
#include <GeographicLib/LocalCartesian.hpp>
#include <string>

#include "sarloc/core/common/types.hpp"

namespace sarloc::incident {

struct Geodetic {
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  double altitude_m = 0.0;  ///< above the WGS-84 ellipsoid
};

class GeodeticFrame {
 public:
  explicit GeodeticFrame(const GeodeticOrigin& origin);
  /// InputError naming the field for a latitude outside [-90, 90], a longitude outside
  /// [-180, 180] or anything not finite.
  Vec3 to_enu(const Geodetic& point) const;
  Geodetic to_wgs84(const Vec3& enu) const;
  const GeodeticOrigin& origin() const { return origin_; }

 private:
  GeodeticOrigin origin_;
  GeographicLib::LocalCartesian local_;
};

/// "46.948000 N, 7.447400 E" (6 decimals: 0.1 m).
std::string format_wgs84(const Geodetic& g);

}  // namespace sarloc::incident
