// The offline basemap (dashboard.basemap): a tile set made by scripts/make-test-basemap, whose
// red mark GDAL puts at the incident's origin, is placed by Basemap so that the mark is at the
// incident frame's (0, 0); what GDAL reads out of the tile the server sends is the judge. Files
// that are not raster MBTiles are refused naming the key; tiles need the view token.
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

// clang-format off
// Eigen before httplib.h: the resolver header httplib pulls in defines `_res`, a name Eigen uses.
#include "basemap.hpp"
#include "dashboard_server.hpp"
#include "sarloc/core/common/errors.hpp"
#include "support/required_program.hpp"
#include <httplib.h>
// clang-format on

namespace sarloc::dashboard {
namespace {

using app::Basemap;
using app::basemap_json;
using app::kBasemapMargin;
using app::kBasemapTilesMax;
using app::PlacedTile;
using app::tiles_over_incident;

namespace fs = std::filesystem;
const GeodeticOrigin kOrigin{46.5563, 7.9263, 2320.0};  // config/missions/default.yaml's

class BasemapFile : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    path_ = new std::string(::testing::TempDir() + "/sarloc_test_basemap.mbtiles");
    const std::string said =
        test::output_of(std::string(SARLOC_SOURCE_DIR "/scripts/make-test-basemap ") + *path_ + " " +
                        std::to_string(kOrigin.latitude_deg) + " " + std::to_string(kOrigin.longitude_deg) + " 500");
    made_ = new std::string(said);
  }
  static void TearDownTestSuite() {
    fs::remove(*path_);
    delete path_;
    delete made_;
  }
  // The colour GDAL reads at a pixel of a tile's bytes (PNG): "R G B " (and "A " if it has one).
  static std::string pixel(const std::string& png, double x, double y) {
    const std::string file = ::testing::TempDir() + "/sarloc_basemap_tile.png";
    std::ofstream(file, std::ios::binary) << png;
    std::string values =
        test::output_of("gdallocationinfo -valonly " + file + " " + std::to_string(static_cast<int>(x)) + " " +
                        std::to_string(static_cast<int>(y)));
    for (char& c : values)
      if (c == '\n') c = ' ';
    return values;
  }
  static std::string* path_;
  static std::string* made_;
};
std::string* BasemapFile::path_ = nullptr;
std::string* BasemapFile::made_ = nullptr;

TEST_F(BasemapFile, ItsTilesArePlacedSoThatTheMarkGdalPutAtTheOriginIsAtTheIncidentFramesOrigin) {
  ASSERT_TRUE(test::has_program("gdallocationinfo", "gdal-bin"));
  ASSERT_TRUE(fs::exists(*path_)) << *made_;
  // GDAL itself: the red mark is at the origin's latitude and longitude.
  EXPECT_EQ(test::output_of("gdallocationinfo -wgs84 -valonly " + *path_ + " " + std::to_string(kOrigin.longitude_deg) +
                            " " + std::to_string(kOrigin.latitude_deg)),
            "220\n0\n0\n255\n");
  const Basemap basemap(*path_, "dashboard.basemap");
  EXPECT_EQ(basemap.content_type(), "image/png");
  EXPECT_EQ(basemap.max_zoom(), 17);
  const incident::GeodeticFrame frame(kOrigin);
  const std::vector<Eigen::Vector2d> deposit{{-45, 10}, {60, 0}, {70, 70}, {-40, 75}};
  const auto tiles = tiles_over_incident(basemap, frame, deposit);
  ASSERT_FALSE(tiles.empty());
  EXPECT_LE(tiles.size(), kBasemapTilesMax);
  // A tile's side is the parallel's length over 2^zoom (WGS-84's radius of the parallel).
  const double a = 6378137.0, e2 = 6.69437999014e-3, phi = kOrigin.latitude_deg * M_PI / 180.0;
  const double side = 2.0 * M_PI * a * std::cos(phi) / std::sqrt(1.0 - e2 * std::sin(phi) * std::sin(phi)) /
                      std::ldexp(1.0, tiles.front().zoom);
  const PlacedTile* under_origin = nullptr;
  for (const auto& t : tiles) {
    EXPECT_EQ(t.zoom, 17) << "the finest zoom fits: the deposit and 300 m around it in 144 tiles";
    EXPECT_NEAR(t.width, side, 0.01 * side);
    EXPECT_NEAR(t.height, side, 0.01 * side) << "Web Mercator tiles are square on the ground";
    if (t.west <= 0 && t.west + t.width > 0 && t.north >= 0 && t.north - t.height < 0) under_origin = &t;
    // Every placed tile covers part of the box asked for.
    EXPECT_LT(t.west, 70 + kBasemapMargin);
    EXPECT_GT(t.west + t.width, -45 - kBasemapMargin);
  }
  ASSERT_NE(under_origin, nullptr);
  // The tile the server sends for that place, read by GDAL where the incident's (0, 0) falls on it.
  const auto png = basemap.tile(under_origin->zoom, under_origin->column, under_origin->row);
  ASSERT_TRUE(png);
  const double px = -under_origin->west / under_origin->width * 256.0;
  const double py = under_origin->north / under_origin->height * 256.0;
  EXPECT_EQ(pixel(*png, px, py).substr(0, 8), "220 0 0 ") << "pixel " << px << ", " << py;
  EXPECT_NE(pixel(*png, std::fmod(px + 20.0, 256.0), py).substr(0, 8), "220 0 0 ")
      << "the mark is 6 m across, not more";
  EXPECT_FALSE(basemap.tile(under_origin->zoom, under_origin->column, -1));
  EXPECT_FALSE(basemap.tile(under_origin->zoom + 1, under_origin->column, under_origin->row)) << "finer than the file";
  EXPECT_FALSE(basemap.tile(3, 1, 1)) << "a tile the file does not have";
}

TEST_F(BasemapFile, TheServerSendsTilesWithTheViewTokenOnly) {
  ASSERT_TRUE(fs::exists(*path_)) << *made_;
  auto basemap = std::make_shared<const Basemap>(*path_, "dashboard.basemap");
  const auto tiles = tiles_over_incident(*basemap, incident::GeodeticFrame(kOrigin), {});
  ASSERT_FALSE(tiles.empty());
  PictureState state{PictureStateConfig{}, [] { return TimestampNs{0}; }, 0};
  state.set_extra("basemap", basemap_json(tiles));
  DashboardServerConfig config;
  config.port = 0;
  config.token = "correct-horse-battery";
  config.view_token = "look-but-do-not-touch";
  DashboardServer server(config, state, [](std::uint32_t, const std::string&) { return true; });
  server.set_basemap(basemap);
  server.start();
  httplib::Client client("127.0.0.1", server.port());
  const auto& t = tiles.front();
  const std::string url =
      "/api/basemap/" + std::to_string(t.zoom) + "/" + std::to_string(t.column) + "/" + std::to_string(t.row);
  EXPECT_EQ(client.Get(url)->status, 401);
  const httplib::Headers viewer{{"Authorization", "Bearer look-but-do-not-touch"}};
  const auto res = client.Get(url, viewer);
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  EXPECT_EQ(res->get_header_value("Content-Type"), "image/png");
  EXPECT_EQ(res->body.substr(1, 3), "PNG");
  EXPECT_EQ(client.Get("/api/basemap/3/1/1", viewer)->status, 404);
  EXPECT_EQ(client.Get("/api/basemap/99/1/1", viewer)->status, 404);
  // The page finds each tile's place in its snapshot.
  const auto snapshot = nlohmann::json::parse(client.Get("/api/state", viewer)->body);
  ASSERT_EQ(snapshot["basemap"].size(), tiles.size());
  EXPECT_EQ(snapshot["basemap"][0]["x"], t.column);
  EXPECT_NEAR(snapshot["basemap"][0]["west"].get<double>(), t.west, 0.01);
  server.stop();
}

// What is not a raster MBTiles file is refused at start, naming the key and why.
TEST(Basemap, WhatIsNotARasterMbtilesFileIsRefusedNamingTheKey) {
  const std::string dir = ::testing::TempDir();
  auto refused = [](const std::string& path, const std::string& why) {
    try {
      Basemap b(path, "dashboard.basemap");
      ADD_FAILURE() << path << " was taken for a basemap";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("dashboard.basemap = '" + path + "'"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  };
  refused(dir + "/no-such-basemap.mbtiles", "cannot be opened");
  EXPECT_FALSE(fs::exists(dir + "/no-such-basemap.mbtiles")) << "opening creates nothing";
  const std::string text = dir + "/not-sqlite.mbtiles";
  std::ofstream(text) << "zoom_level,tile_column,tile_row\n";
  refused(text, "not an MBTiles file");
  // SQLite, but vector tiles; then raster, but empty.
  const std::string vector_tiles = dir + "/vector.mbtiles";
  fs::remove(vector_tiles);
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(vector_tiles.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(
      sqlite3_exec(db,
                   "CREATE TABLE metadata (name TEXT, value TEXT);"
                   "CREATE TABLE tiles (zoom_level INTEGER, tile_column INTEGER, tile_row INTEGER, tile_data BLOB);"
                   "INSERT INTO metadata VALUES ('format', 'pbf');",
                   nullptr, nullptr, nullptr),
      SQLITE_OK);
  refused(vector_tiles, "its tiles are 'pbf'");
  ASSERT_EQ(sqlite3_exec(db, "UPDATE metadata SET value = 'png' WHERE name = 'format';", nullptr, nullptr, nullptr),
            SQLITE_OK);
  refused(vector_tiles, "it holds no tile");
  sqlite3_close(db);
  fs::remove(text);
  fs::remove(vector_tiles);
}

}  // namespace
}  // namespace sarloc::dashboard
