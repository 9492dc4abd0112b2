#include "basemap.hpp"

#include <openssl/evp.h>
#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/errors.hpp"

namespace sarloc::app {

namespace {

constexpr int kZoomMax = 24;  ///< finer than any raster basemap (a centimetre a pixel)

struct StatementCloser {
  void operator()(sqlite3_stmt* s) const { sqlite3_finalize(s); }
};
using Statement = std::unique_ptr<sqlite3_stmt, StatementCloser>;

Statement prepare(sqlite3* db, const char* sql) {
  sqlite3_stmt* s = nullptr;
  if (sqlite3_prepare_v2(db, sql, -1, &s, nullptr) != SQLITE_OK) return nullptr;
  return Statement(s);
}

std::string text_of(sqlite3_stmt* s, int column) {
  const auto* text = sqlite3_column_text(s, column);
  return text ? reinterpret_cast<const char*>(text) : "";
}

}  // namespace

std::vector<PlacedTile> tiles_over_incident(const Basemap& basemap, const incident::GeodeticFrame& frame,
                                            const std::vector<Eigen::Vector2d>& deposit) {
  Eigen::Vector2d low = Eigen::Vector2d::Zero(), high = Eigen::Vector2d::Zero();
  if (!deposit.empty()) low = high = deposit.front();
  for (const auto& p : deposit) {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  const Eigen::Vector2d margin = Eigen::Vector2d::Constant(kBasemapMargin);
  return basemap.tiles_over(frame, low - margin, high + margin, kBasemapTilesMax);
}

std::optional<std::string> tile_data_uri(const Basemap& basemap, const PlacedTile& tile) {
  const auto bytes = basemap.tile(tile.zoom, tile.column, tile.row);
  if (!bytes) return std::nullopt;
  std::string base64(4 * ((bytes->size() + 2) / 3) + 1, '\0');
  const int written =
      EVP_EncodeBlock(reinterpret_cast<unsigned char*>(base64.data()),
                      reinterpret_cast<const unsigned char*>(bytes->data()), static_cast<int>(bytes->size()));
  base64.resize(static_cast<std::size_t>(written));
  return "data:" + basemap.content_type() + ";base64," + base64;
}

nlohmann::json basemap_json(const std::vector<PlacedTile>& tiles) {
  auto cm = [](double m) { return std::round(m * 100.0) / 100.0; };
  nlohmann::json out = nlohmann::json::array();
  for (const auto& t : tiles)
    out.push_back({{"z", t.zoom},
                   {"x", t.column},
                   {"y", t.row},
                   {"west", cm(t.west)},
                   {"north", cm(t.north)},
                   {"width", cm(t.width)},
                   {"height", cm(t.height)}});
  return out;
}

Eigen::Vector2d tile_of(double latitude_deg, double longitude_deg, int zoom) {
  const double n = std::ldexp(1.0, zoom);
  const double lat = latitude_deg * kPi / 180.0;
  return {(longitude_deg + 180.0) / 360.0 * n, (1.0 - std::asinh(std::tan(lat)) / kPi) / 2.0 * n};
}

incident::Geodetic tile_corner(int zoom, double column, double row) {
  const double n = std::ldexp(1.0, zoom);
  incident::Geodetic g;
  g.longitude_deg = column / n * 360.0 - 180.0;
  g.latitude_deg = std::atan(std::sinh(kPi * (1.0 - 2.0 * row / n))) * 180.0 / kPi;
  return g;
}

Basemap::Basemap(const std::string& path, const std::string& key) {
  auto refuse = [&](const std::string& why) {
    if (db_) sqlite3_close(db_);
    db_ = nullptr;
    throw ConfigError(key + " = '" + path + "': " + why);
  };
  // Read-only, and never created: a wrong path is an error, not an empty database.
  if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READONLY | SQLITE_OPEN_FULLMUTEX, nullptr) != SQLITE_OK)
    refuse(std::string("cannot be opened: ") + (db_ ? sqlite3_errmsg(db_) : "out of memory"));
  std::string format;
  {
    auto s = prepare(db_, "SELECT name, value FROM metadata");
    if (!s) refuse(std::string("not an MBTiles file (no metadata table: ") + sqlite3_errmsg(db_) + ")");
    while (sqlite3_step(s.get()) == SQLITE_ROW)
      if (text_of(s.get(), 0) == "format") format = text_of(s.get(), 1);
  }
  if (format == "png")
    content_type_ = "image/png";
  else if (format == "jpg" || format == "jpeg")
    content_type_ = "image/jpeg";
  else
    refuse("its tiles are '" + format + "': a raster basemap needs png or jpg (metadata 'format')");
  auto s = prepare(db_, "SELECT MIN(zoom_level), MAX(zoom_level), COUNT(*) FROM tiles");
  if (!s) refuse(std::string("not an MBTiles file (no tiles table: ") + sqlite3_errmsg(db_) + ")");
  if (sqlite3_step(s.get()) != SQLITE_ROW || sqlite3_column_int64(s.get(), 2) == 0) refuse("it holds no tile");
  min_zoom_ = sqlite3_column_int(s.get(), 0);
  max_zoom_ = sqlite3_column_int(s.get(), 1);
  if (min_zoom_ < 0 || max_zoom_ > kZoomMax)
    refuse("zoom levels " + std::to_string(min_zoom_) + "-" + std::to_string(max_zoom_) + ": must be in 0-" +
           std::to_string(kZoomMax));
}

Basemap::~Basemap() { sqlite3_close(db_); }

std::optional<std::string> Basemap::tile(int zoom, long column, long row) const {
  if (zoom < min_zoom_ || zoom > max_zoom_) return std::nullopt;
  const long n = 1L << zoom;
  if (column < 0 || column >= n || row < 0 || row >= n) return std::nullopt;
  std::lock_guard<std::mutex> lock(mutex_);
  auto s = prepare(db_, "SELECT tile_data FROM tiles WHERE zoom_level = ? AND tile_column = ? AND tile_row = ?");
  if (!s) return std::nullopt;
  sqlite3_bind_int(s.get(), 1, zoom);
  sqlite3_bind_int64(s.get(), 2, column);
  sqlite3_bind_int64(s.get(), 3, n - 1 - row);  // MBTiles counts rows from the south
  if (sqlite3_step(s.get()) != SQLITE_ROW) return std::nullopt;
  const auto* data = static_cast<const char*>(sqlite3_column_blob(s.get(), 0));
  return std::string(data ? data : "", static_cast<std::size_t>(sqlite3_column_bytes(s.get(), 0)));
}

std::vector<PlacedTile> Basemap::tiles_over(const incident::GeodeticFrame& frame, const Eigen::Vector2d& south_west,
                                            const Eigen::Vector2d& north_east, std::size_t max_tiles) const {
  const double altitude = frame.origin().altitude_m;
  const auto sw = frame.to_wgs84(Eigen::Vector3d(south_west.x(), south_west.y(), 0.0));
  const auto ne = frame.to_wgs84(Eigen::Vector3d(north_east.x(), north_east.y(), 0.0));
  auto place = [&](int zoom, long column, long row) {
    auto nw = tile_corner(zoom, static_cast<double>(column), static_cast<double>(row));
    auto se = tile_corner(zoom, static_cast<double>(column + 1), static_cast<double>(row + 1));
    nw.altitude_m = se.altitude_m = altitude;
    const Eigen::Vector3d a = frame.to_enu(nw), b = frame.to_enu(se);
    return PlacedTile{zoom, column, row, a.x(), a.y(), b.x() - a.x(), a.y() - b.y()};
  };
  std::lock_guard<std::mutex> lock(mutex_);
  for (int zoom = max_zoom_; zoom >= min_zoom_; --zoom) {
    const Eigen::Vector2d first = tile_of(ne.latitude_deg, sw.longitude_deg, zoom).array().floor();
    const Eigen::Vector2d last = tile_of(sw.latitude_deg, ne.longitude_deg, zoom).array().floor();
    const double count = (last.x() - first.x() + 1) * (last.y() - first.y() + 1);
    if (count > static_cast<double>(max_tiles)) continue;
    const long n = 1L << zoom;
    auto s = prepare(db_,
                     "SELECT tile_column, tile_row FROM tiles WHERE zoom_level = ? AND tile_column BETWEEN ? AND ? "
                     "AND tile_row BETWEEN ? AND ?");
    if (!s) return {};
    sqlite3_bind_int(s.get(), 1, zoom);
    sqlite3_bind_int64(s.get(), 2, static_cast<long>(first.x()));
    sqlite3_bind_int64(s.get(), 3, static_cast<long>(last.x()));
    sqlite3_bind_int64(s.get(), 4, n - 1 - static_cast<long>(last.y()));
    sqlite3_bind_int64(s.get(), 5, n - 1 - static_cast<long>(first.y()));
    std::vector<PlacedTile> placed;
    while (sqlite3_step(s.get()) == SQLITE_ROW) {
      const long column = static_cast<long>(sqlite3_column_int64(s.get(), 0));
      placed.push_back(place(zoom, column, n - 1 - static_cast<long>(sqlite3_column_int64(s.get(), 1))));
    }
    if (!placed.empty()) return placed;
  }
  return {};
}

}  // namespace sarloc::app
