// The picture as GeoJSON (RFC 7946): positions [longitude, latitude] that convert back to where
// they were, rings closed and counter-clockwise whichever way they came, the 95 % ellipse on its
// chi2_2(0.95) contour, and what GeoJSON cannot hold (a NaN, a one-point line) left out.
#include "sarloc/app/incident_geojson.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "sarloc/core/common/gaussian.hpp"

namespace sarloc::app {
namespace {

using nlohmann::json;
using Vec2 = Eigen::Vector2d;

const GeodeticOrigin kOrigin{46.5563, 7.9263, 2320.0};

Vec3 back(const incident::GeodeticFrame& frame, const json& position) {
  return frame.to_enu({position[1].get<double>(), position[0].get<double>(),
                       position.size() > 2 ? position[2].get<double>() : kOrigin.altitude_m});
}

double signed_area(const json& ring) {  // shoelace on [lon, lat]: > 0 counter-clockwise
  double twice = 0.0;
  for (std::size_t k = 0; k + 1 < ring.size(); ++k)
    twice += ring[k][0].get<double>() * ring[k + 1][1].get<double>() -
             ring[k + 1][0].get<double>() * ring[k][1].get<double>();
  return twice / 2.0;
}

TEST(IncidentGeoJson, PositionsConvertBackAndRingsAreClosedAndCounterClockwise) {
  const incident::GeodeticFrame frame(kOrigin);
  IncidentGeoJson picture;
  picture.epoch_ns = 1'800'000'000'000'000'000LL;
  picture.deposit = std::vector<Vec2>{{0.0, 0.0}, {0.0, 200.0}, {150.0, 200.0}, {150.0, 0.0}};  // clockwise
  picture.strips.push_back({0, {{0.0, 0.0}, {75.0, 0.0}, {75.0, 200.0}, {0.0, 200.0}}, 37.5, 0.25});
  picture.tracks.push_back(
      {"r1", "north", "avalanche rescuer", {{10.0, 0.0}, {10.0, NAN}, {10.0, 50.0}, {12.0, 90.0}}});
  picture.tracks.push_back({"r2", "north", "avalanche rescuer", {{20.0, 0.0}}});  // one point: no line
  GeoJsonVictim victim;
  victim.victim_id = 3;
  victim.state = "LOCATED";
  victim.position.position = Vec3(30.0, 40.0, -1.5);
  victim.position.covariance = Vec3(0.25, 0.09, 0.04).asDiagonal();
  victim.position.covariance(0, 1) = victim.position.covariance(1, 0) = 0.05;
  victim.located_s = 61.5;
  victim.sources = {"r1/2"};
  picture.victims.push_back(victim);
  GeoJsonVictim lost = victim;
  lost.victim_id = 4;
  lost.position.position.x() = NAN;
  picture.victims.push_back(lost);

  const json collection = to_geojson(picture, frame);
  ASSERT_EQ(collection["type"], "FeatureCollection");
  std::map<std::string, std::vector<json>> by_kind;
  for (const auto& f : collection["features"]) {
    EXPECT_EQ(f["type"], "Feature");
    by_kind[f["properties"]["kind"]].push_back(f);
  }
  EXPECT_EQ(by_kind.size(), 5u) << collection.dump();

  const json& deposit = by_kind["deposit"].at(0)["geometry"];
  ASSERT_EQ(deposit["type"], "Polygon");
  const json& ring = deposit["coordinates"][0];
  ASSERT_EQ(ring.size(), 5u);
  EXPECT_EQ(ring.front(), ring.back());
  EXPECT_GT(signed_area(ring), 0.0) << "given clockwise, written counter-clockwise";
  for (std::size_t k = 0; k + 1 < ring.size(); ++k) {
    const Vec3 p = back(frame, ring[k]);
    EXPECT_LT(std::min({p.head<2>().norm(), (p.head<2>() - Vec2(0, 200)).norm(), (p.head<2>() - Vec2(150, 200)).norm(),
                        (p.head<2>() - Vec2(150, 0)).norm()}),
              0.015)
        << "7 decimals of a degree: about 1 cm";
  }
  EXPECT_DOUBLE_EQ(by_kind["strip"].at(0)["properties"]["searched_fraction"].get<double>(), 0.25);

  ASSERT_EQ(by_kind["track"].size(), 1u) << "r2's one point makes no line";
  const json& line = by_kind["track"][0]["geometry"];
  ASSERT_EQ(line["type"], "LineString");
  ASSERT_EQ(line["coordinates"].size(), 3u) << "the NaN point left out";
  EXPECT_LT((back(frame, line["coordinates"][2]).head<2>() - Vec2(12.0, 90.0)).norm(), 0.015);

  ASSERT_EQ(by_kind["victim"].size(), 1u) << "victim 4's NaN position left out";
  const json& point = by_kind["victim"][0];
  EXPECT_LT((back(frame, point["geometry"]["coordinates"]) - victim.position.position).norm(), 0.015)
      << "longitude, latitude and altitude above the ellipsoid";
  EXPECT_EQ(point["properties"]["victim_id"], 3);
  EXPECT_EQ(point["properties"]["state"], "LOCATED");
  EXPECT_DOUBLE_EQ(point["properties"]["located_s"].get<double>(), 61.5);
  EXPECT_EQ(point["properties"]["located_utc"], "2027-01-15T08:01:01.500Z");
  EXPECT_TRUE(point["properties"]["found_s"].is_null());
  EXPECT_DOUBLE_EQ(point["properties"]["depth_m"].get<double>(), 1.5);
  EXPECT_NEAR(point["properties"]["radius95_m"].get<double>(), radius95_2d(victim.position.covariance), 1e-3);

  // The ellipse: every vertex on the 95 % contour (Mahalanobis^2 = chi2_2(0.95)) of the
  // horizontal covariance, counter-clockwise, closed.
  const json& ellipse = by_kind["victim_ellipse_95"].at(0);
  EXPECT_EQ(ellipse["properties"]["victim_id"], 3);
  const json& outline = ellipse["geometry"]["coordinates"][0];
  ASSERT_EQ(outline.size(), 37u);
  EXPECT_EQ(outline.front(), outline.back());
  EXPECT_GT(signed_area(outline), 0.0);
  const Eigen::Matrix2d information = victim.position.covariance.topLeftCorner<2, 2>().inverse();
  for (std::size_t k = 0; k + 1 < outline.size(); ++k) {
    const Vec2 d = back(frame, outline[k]).head<2>() - victim.position.position.head<2>();
    EXPECT_NEAR(d.dot(information * d), kChi2_2_95, 0.15) << k;  // 1 cm rounding on a 0.5-1.3 m ellipse
  }
}

TEST(IncidentGeoJson, AnEmptyPictureIsAnEmptyCollection) {
  const json collection = to_geojson(IncidentGeoJson{}, incident::GeodeticFrame(kOrigin));
  EXPECT_EQ(collection["type"], "FeatureCollection");
  EXPECT_TRUE(collection["features"].empty());
}

}  // namespace
}  // namespace sarloc::app
