#pragma once
// The incident picture as GeoJSON (RFC 7946) in WGS-84, for GIS tools, another agency's map or a
// helicopter crew (issue 63, item 7): the avalanche deposit, its primary-search strips with their
// coverage, responders' tracks as LineStrings, victims as Points with their 95 % ellipse as a
// Polygon. sarloc-report --geojson and the dashboard's GET /api/geojson both write it here.
//
// Every feature has a "kind" property: "deposit", "strip", "track", "victim",
// "victim_ellipse_95" (the last two share the victim's properties). Positions are [longitude,
// latitude] (victims: and altitude above the ellipsoid), 7 decimals (1 cm); polygons' rings are
// closed and counter-clockwise (RFC 7946, 3.1.6). Docs: docs/operations/recording.md.
//
//   IncidentGeoJson picture;  picture.deposit = ...;  picture.victims.push_back(...);
//   const nlohmann::json collection = to_geojson(picture, GeodeticFrame(origin));
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "sarloc/core/common/types.hpp"
#include "sarloc/core/incident/geodetic_frame.hpp"

namespace sarloc::app {

struct GeoJsonStrip {
  std::size_t index = 0;
  std::vector<Eigen::Vector2d> outline;  ///< incident frame
  double width_m = 0.0;
  double searched_fraction = 0.0;  ///< of the strip's area, in [0, 1]
};

struct GeoJsonTrack {
  std::string responder_id;
  std::string team_id;
  std::string role;                     ///< "avalanche rescuer" or "firefighter"
  std::vector<Eigen::Vector2d> points;  ///< incident frame, in time order; non-finite ones are left out
};

struct GeoJsonVictim {
  std::uint32_t victim_id = 0;
  std::string state;                         ///< "unconfirmed", "LOCATED", "FOUND", "recovered"
  GaussianPosition position;                 ///< incident frame
  std::optional<double> located_s, found_s;  ///< mission seconds
  std::vector<std::string> sources;          ///< "rescuer/signal"
  bool evidence_conflict = false;
};

struct IncidentGeoJson {
  std::optional<std::vector<Eigen::Vector2d>> deposit;  ///< incident frame
  std::vector<GeoJsonStrip> strips;
  std::vector<GeoJsonTrack> tracks;
  std::vector<GeoJsonVictim> victims;
  /// Mission time 0 (ns since the Unix epoch): features' times also as UTC when it is known.
  std::optional<TimestampNs> epoch_ns;
};

/// A FeatureCollection. Tracks with fewer than 2 finite points and victims whose position is
/// not finite are left out (a GeoJSON LineString needs 2 positions; a NaN is no coordinate).
nlohmann::json to_geojson(const IncidentGeoJson& picture, const incident::GeodeticFrame& frame);

}  // namespace sarloc::app
