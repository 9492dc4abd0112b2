// WGS-84 <-> ENU about the incident's origin, against the ellipsoid's own radii of curvature.
#include "sarloc/core/incident/geodetic_frame.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/incident/gnss_fix.hpp"

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

// A receiver's fix, as it gives it, into the incident frame: the simulated receiver reports what
// a real one would, and the device's conversion gets back where it was and what it claimed.
TEST(GnssFix, AReceiversFixComesBackIntoTheIncidentFrameWithItsAccuracy) {
  const GeodeticFrame frame(kBern);
  GaussianPosition at;
  at.position = Vec3(1200.0, -850.0, 35.0);
  at.covariance = Vec3(0.09, 0.16, 0.36).asDiagonal();
  const GnssFix fix = as_receiver_fix(frame, 7, at);
  EXPECT_EQ(fix.stamp, 7);
  EXPECT_DOUBLE_EQ(fix.horizontal_sigma_m, 0.4);  // the larger of east and north
  EXPECT_DOUBLE_EQ(fix.vertical_sigma_m, 0.6);
  EXPECT_LT(fix.position.latitude_deg, kBern.latitude_deg);    // south
  EXPECT_GT(fix.position.longitude_deg, kBern.longitude_deg);  // east
  const GaussianPosition back = in_incident_frame(frame, fix);
  EXPECT_LT((back.position - at.position).norm(), 1e-3);
  EXPECT_DOUBLE_EQ(back.covariance(0, 0), 0.16);
  EXPECT_DOUBLE_EQ(back.covariance(1, 1), 0.16);
  EXPECT_DOUBLE_EQ(back.covariance(2, 2), 0.36);
  EXPECT_DOUBLE_EQ(back.covariance(0, 1), 0.0);
}

TEST(GnssFix, RefusesAFixOutOfRangeFarAwayOrWithoutAnAccuracyNamingTheField) {
  const GeodeticFrame frame(kBern);
  const auto message = [&](GnssFix fix) {
    try {
      in_incident_frame(frame, fix);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const GnssFix good{1, {kBern.latitude_deg, kBern.longitude_deg, 540.0}, 2.0, 4.0};
  EXPECT_EQ(message(good), "accepted");
  GnssFix f = good;
  f.position.latitude_deg = 91.0;
  EXPECT_NE(message(f).find("latitude_deg = 91"), std::string::npos) << message(f);
  f = good;
  f.position.longitude_deg = std::nan("");
  EXPECT_NE(message(f).find("longitude_deg"), std::string::npos) << message(f);
  f = good;
  f.position.latitude_deg += 1.0;  // 111 km north
  EXPECT_NE(message(f).find("from the incident's origin"), std::string::npos) << message(f);
  f = good;
  f.horizontal_sigma_m = 0.0;
  EXPECT_NE(message(f).find("horizontal_sigma_m = 0"), std::string::npos) << message(f);
  f = good;
  f.vertical_sigma_m = 5000.0;
  EXPECT_NE(message(f).find("vertical_sigma_m = 5000"), std::string::npos) << message(f);
}

}  // namespace
}  // namespace sarloc::incident
