// WGS-84 <-> ENU about the incident's origin, against the ellipsoid's own radii of curvature.
#include "sarloc/core/incident/geodetic_frame.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::incident {
namespace {

const GeodeticOrigin kBern{46.9480, 7.4474, 540.0};

// A short step north or east of the origin moves latitude by dn / M and longitude by
// de / (N cos(lat)), M and N the WGS-84 meridian and prime-vertical radii there.
TEST(GeodeticFrame, StepsNorthAndEastMatchTheEllipsoidsRadiiOfCurvature) {
  const GeodeticFrame frame(kBern);
  const double a = 6378137.0, f = 1.0 / 298.257223563, e2 = f * (2.0 - f);
  const double phi = kBern.latitude_deg * M_PI / 180.0, w = 1.0 - e2 * std::sin(phi) * std::sin(phi);
  const double n = a / std::sqrt(w), m = a * (1.0 - e2) / (w * std::sqrt(w));
  const Geodetic north = frame.to_wgs84(Vec3(0.0, 10.0, 0.0));
  EXPECT_NEAR((north.latitude_deg - kBern.latitude_deg) * M_PI / 180.0, 10.0 / (m + kBern.altitude_m), 1e-11);
  EXPECT_NEAR(north.longitude_deg, kBern.longitude_deg, 1e-12);
  const Geodetic east = frame.to_wgs84(Vec3(10.0, 0.0, 0.0));
  EXPECT_NEAR((east.longitude_deg - kBern.longitude_deg) * M_PI / 180.0,
              10.0 / ((n + kBern.altitude_m) * std::cos(phi)), 1e-11);
  const Geodetic up = frame.to_wgs84(Vec3(0.0, 0.0, 12.0));
  EXPECT_NEAR(up.altitude_m, 552.0, 1e-6);
}

TEST(GeodeticFrame, RoundTripsWithinAMillimetreOverTenKilometres) {
  const GeodeticFrame frame(kBern);
  for (const Vec3& p : {Vec3(0, 0, 0), Vec3(150, -220, -3.5), Vec3(-7000, 6500, 80)}) {
    const Vec3 back = frame.to_enu(frame.to_wgs84(p));
    EXPECT_LT((back - p).norm(), 1e-3) << p.transpose();
  }
  EXPECT_EQ(format_wgs84({46.9480, -7.4474, 0.0}), "46.948000 N, 7.447400 W");
}

TEST(GeodeticFrame, RefusesCoordinatesOutOfRangeNamingTheField) {
  EXPECT_THROW(GeodeticFrame({91.0, 7.0, 0.0}), ConfigError);
  EXPECT_THROW(GeodeticFrame({46.0, std::nan(""), 0.0}), ConfigError);
  const GeodeticFrame frame(kBern);
  try {
    (void)frame.to_enu({46.9, 181.0, 0.0});
    FAIL() << "a longitude of 181 was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("point.longitude_deg = 181"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)frame.to_wgs84(Vec3(std::nan(""), 0, 0)), InputError);
}

}  // namespace
}  // namespace sarloc::incident
