#pragma once
// An offline raster basemap under the dashboard's map and the report's: an MBTiles file
// (SQLite; tiles in Web Mercator, rows numbered from the south as TMS does) prepared before the
// season, for example OpenStreetMap or orthophoto tiles (docs/operations/dashboard.md,
// "Basemap"). Read-only.
#include <Eigen/Core>
#include <cstddef>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "sarloc/core/incident/geodetic_frame.hpp"

struct sqlite3;

namespace sarloc::app {

/// One tile of the file, placed in the incident frame: its north-west corner and its size (m).
/// zoom/column/row number it as web maps do (XYZ: row 0 at the north), as the page asks for it.
struct PlacedTile {
  int zoom = 0;
  long column = 0;
  long row = 0;
  double west = 0.0;   ///< east of the incident origin (m)
  double north = 0.0;  ///< north of the incident origin (m)
  double width = 0.0;
  double height = 0.0;
};

class Basemap {
 public:
  /// Opens `path` read-only. ConfigError naming `key` when it is not an MBTiles file of PNG or
  /// JPEG tiles (not SQLite, no tiles table, another format, or no tile at all).
  Basemap(const std::string& path, const std::string& key);
  ~Basemap();
  Basemap(const Basemap&) = delete;
  Basemap& operator=(const Basemap&) = delete;

  /// image/png or image/jpeg, from the file's metadata.
  const std::string& content_type() const { return content_type_; }
  int min_zoom() const { return min_zoom_; }
  int max_zoom() const { return max_zoom_; }

  /// The tile's bytes (XYZ numbering), or nothing when the file has none there.
  std::optional<std::string> tile(int zoom, long column, long row) const;

  /// The file's tiles over the box [south_west, north_east] of the incident frame (m), at the
  /// finest zoom at which the box takes at most `max_tiles` tiles and the file has some there.
  std::vector<PlacedTile> tiles_over(const incident::GeodeticFrame& frame, const Eigen::Vector2d& south_west,
                                     const Eigen::Vector2d& north_east, std::size_t max_tiles) const;

 private:
  sqlite3* db_ = nullptr;
  mutable std::mutex mutex_;  ///< one statement at a time on the one connection
  std::string content_type_;
  int min_zoom_ = 0;
  int max_zoom_ = 0;
};

/// The tiles under the incident: the deposit's bounding box and kBasemapMargin around it, or
/// kBasemapMargin around the origin without one; at most kBasemapTilesMax.
inline constexpr double kBasemapMargin = 300.0;
inline constexpr std::size_t kBasemapTilesMax = 144;
std::vector<PlacedTile> tiles_over_incident(const Basemap& basemap, const incident::GeodeticFrame& frame,
                                            const std::vector<Eigen::Vector2d>& deposit);

/// The page's list: [{"z", "x", "y", "west", "north", "width", "height"}, ...] (m, to the cm).
nlohmann::json basemap_json(const std::vector<PlacedTile>& tiles);

/// The tile's bytes as a data: URI (base64), to draw it inside a self-contained file; nothing
/// when the file has no tile there.
std::optional<std::string> tile_data_uri(const Basemap& basemap, const PlacedTile& tile);

/// Web Mercator: the tile (XYZ) holding a WGS-84 point at `zoom`, and a tile corner's latitude
/// and longitude (its north-west corner; column + 1, row + 1 for the south-east).
Eigen::Vector2d tile_of(double latitude_deg, double longitude_deg, int zoom);
incident::Geodetic tile_corner(int zoom, double column, double row);

}  // namespace sarloc::app
