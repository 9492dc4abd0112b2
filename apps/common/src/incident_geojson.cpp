#include "sarloc/app/incident_geojson.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>

#include "sarloc/core/common/gaussian.hpp"

namespace sarloc::app {
namespace {

using nlohmann::json;

// To `decimals` places; dividing by an exact power of ten gives the shortest decimal when dumped.
double round_to(double value, int decimals) {
  const double scale = std::pow(10.0, decimals);
  return std::round(value * scale) / scale;
}

// 7 decimals of a degree: 1.1 cm of latitude, finer than any estimate here (RFC 7946, 11.2:
// more is noise).
double rounded(double degrees) { return round_to(degrees, 7); }

json lon_lat(const incident::GeodeticFrame& frame, const Eigen::Vector2d& enu) {
  const incident::Geodetic g = frame.to_wgs84(Vec3(enu.x(), enu.y(), 0.0));
  return json::array({rounded(g.longitude_deg), rounded(g.latitude_deg)});
}

// A closed ring, counter-clockwise (a shoelace area below 0 is clockwise: reversed). East and
// north are longitude and latitude's directions, so the turn is the same in both.
json ring(const incident::GeodeticFrame& frame, std::vector<Eigen::Vector2d> outline) {
  double twice_area = 0.0;
  for (std::size_t i = 0; i < outline.size(); ++i) {
    const auto& a = outline[i];
    const auto& b = outline[(i + 1) % outline.size()];
    twice_area += a.x() * b.y() - b.x() * a.y();
  }
  if (twice_area < 0.0) std::reverse(outline.begin(), outline.end());
  json positions = json::array();
  for (const auto& p : outline) positions.push_back(lon_lat(frame, p));
  if (!outline.empty()) positions.push_back(positions.front());
  return positions;
}

json feature(json geometry, json properties) {
  return json{{"type", "Feature"}, {"geometry", std::move(geometry)}, {"properties", std::move(properties)}};
}

std::string utc(TimestampNs ns) {
  const std::time_t seconds = static_cast<std::time_t>(ns / 1000000000);
  std::tm parts{};
  gmtime_r(&seconds, &parts);
  char text[80];  // room for any int the compiler imagines in each field
  std::snprintf(text, sizeof text, "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", parts.tm_year + 1900, parts.tm_mon + 1,
                parts.tm_mday, parts.tm_hour, parts.tm_min, parts.tm_sec, static_cast<int>((ns / 1000000) % 1000));
  return text;
}

json victim_properties(const GeoJsonVictim& v, const std::optional<TimestampNs>& epoch_ns) {
  json p{{"victim_id", v.victim_id},
         {"state", v.state},
         {"radius95_m", round_to(radius95_2d(v.position.covariance), 3)},
         {"depth_m", round_to(-v.position.position.z(), 3)},
         {"sources", v.sources},
         {"evidence_conflict", v.evidence_conflict}};
  const auto time = [&](const char* key, const std::optional<double>& t_s) {
    p[std::string(key) + "_s"] = t_s ? json(*t_s) : json(nullptr);
    if (t_s && epoch_ns) p[std::string(key) + "_utc"] = utc(*epoch_ns + static_cast<TimestampNs>(*t_s * 1e9));
  };
  time("located", v.located_s);
  time("found", v.found_s);
  return p;
}

}  // namespace

json to_geojson(const IncidentGeoJson& picture, const incident::GeodeticFrame& frame) {
  json features = json::array();
  if (picture.deposit) {
    features.push_back(feature(json{{"type", "Polygon"}, {"coordinates", json::array({ring(frame, *picture.deposit)})}},
                               json{{"kind", "deposit"}}));
  }
  for (const auto& s : picture.strips) {
    features.push_back(feature(json{{"type", "Polygon"}, {"coordinates", json::array({ring(frame, s.outline)})}},
                               json{{"kind", "strip"},
                                    {"strip", s.index},
                                    {"width_m", round_to(s.width_m, 3)},
                                    {"searched_fraction", round_to(s.searched_fraction, 4)}}));
  }
  for (const auto& t : picture.tracks) {
    json line = json::array();
    for (const auto& p : t.points)
      if (p.allFinite()) line.push_back(lon_lat(frame, p));
    if (line.size() < 2) continue;
    features.push_back(
        feature(json{{"type", "LineString"}, {"coordinates", std::move(line)}},
                json{{"kind", "track"}, {"responder_id", t.responder_id}, {"team_id", t.team_id}, {"role", t.role}}));
  }
  for (const auto& v : picture.victims) {
    if (!v.position.position.allFinite() || !v.position.covariance.allFinite()) continue;
    const incident::Geodetic g = frame.to_wgs84(v.position.position);
    json point{
        {"type", "Point"},
        {"coordinates", json::array({rounded(g.longitude_deg), rounded(g.latitude_deg), round_to(g.altitude_m, 2)})}};
    json properties = victim_properties(v, picture.epoch_ns);
    properties["kind"] = "victim";
    features.push_back(feature(std::move(point), properties));
    // A point estimate (no spread, 1 cm) has no area to draw: a degenerate ring is invalid GIS.
    if (ellipse95(v.position.covariance.topLeftCorner<2, 2>()).semi_minor_m < 0.01) continue;
    const auto outline = ellipse95_outline(v.position.position.head<2>(), v.position.covariance.topLeftCorner<2, 2>());
    properties["kind"] = "victim_ellipse_95";
    features.push_back(
        feature(json{{"type", "Polygon"}, {"coordinates", json::array({ring(frame, outline)})}}, properties));
  }
  return json{{"type", "FeatureCollection"}, {"features", std::move(features)}};
}

}  // namespace sarloc::app
