// The report's basemap (sarloc-report --basemap): a tile set made by scripts/make-test-basemap
// lies under the avalanche field's map, embedded as data: URIs whose bytes (decoded by coreutils'
// base64, not by sarloc) are the file's tiles, cut to the map's frame and drawn before the
// deposit; without the incident's WGS-84 origin, or a tile there, nothing is drawn and the
// legend says why.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "basemap.hpp"
#include "report_html.hpp"
#include "support/required_program.hpp"

namespace sarloc::report {
namespace {

namespace fs = std::filesystem;
const GeodeticOrigin kOrigin{46.5563, 7.9263, 2320.0};

std::string unique_temp(const std::string& name) {
  return ::testing::TempDir() + "/sarloc_report_" + std::to_string(::getpid()) + "_" + name;
}

// An avalanche field of 120 x 80 m around the origin: a deposit, one rescuer's track, one victim.
MissionRecord field(bool with_origin) {
  MissionRecord r;
  if (with_origin) r.incident_origin = kOrigin;
  r.deposit.emplace(std::vector<Eigen::Vector2d>{{-60.0, -40.0}, {60.0, -40.0}, {60.0, 40.0}, {-60.0, 40.0}}, "test");
  auto& track = r.responders["r1"];
  track.id = "r1";
  for (int k = 0; k <= 50; ++k) {
    PositionSample s;
    s.t_s = k;
    s.position.position = Vec3(-50.0 + 2.0 * k, -30.0 + k, 0.0);
    track.samples.push_back(s);
  }
  auto& victim = r.victims[1];
  victim.id = 1;
  VictimSample v;
  v.t_s = 50.0;
  v.position.position = Vec3(45.0, 18.0, -1.5);
  v.position.covariance = Mat3::Identity() * 0.04;
  v.state = incident::VictimState::kFound;
  victim.samples.push_back(v);
  victim.found_s = 50.0;
  return r;
}

class ReportBasemap : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // Per process: ctest runs each test of the suite in its own, at the same time.
    path_ = new std::string(unique_temp("basemap.mbtiles"));
    made_ = new std::string(test::output_of(std::string(SARLOC_SOURCE_DIR "/scripts/make-test-basemap ") + *path_ +
                                            " " + std::to_string(kOrigin.latitude_deg) + " " +
                                            std::to_string(kOrigin.longitude_deg) + " 500"));
  }
  static void TearDownTestSuite() {
    fs::remove(*path_);
    delete path_;
    delete made_;
  }
  static std::string* path_;
  static std::string* made_;
};
std::string* ReportBasemap::path_ = nullptr;
std::string* ReportBasemap::made_ = nullptr;

TEST_F(ReportBasemap, ItsTilesAreEmbeddedUnderTheFieldMapAndAreTheFilesOwnBytes) {
  ASSERT_TRUE(test::has_program("gdal_translate", "gdal-bin"));
  ASSERT_TRUE(test::has_program("base64", "coreutils"));
  ASSERT_TRUE(fs::exists(*path_)) << *made_;
  const app::Basemap basemap(*path_, "--basemap");
  const std::string html = render_report(field(true), nullptr, &basemap);

  // Every tile inside the map's clipped inner <svg>, which comes before the deposit's polygon.
  const auto inner = html.find("class=\"basemap\"");
  const auto inner_end = html.find("</svg>", inner);
  const auto deposit = html.find("<polygon");
  ASSERT_NE(inner, std::string::npos);
  ASSERT_NE(deposit, std::string::npos);
  EXPECT_LT(inner_end, deposit) << "the basemap must lie under the deposit";
  // (std::regex over a page of base64 is too slow: plain searches.)
  const std::string prefix = "preserveAspectRatio=\"none\" href=\"data:image/png;base64,";
  std::size_t images = 0;
  std::string first;
  for (auto at = html.find("<image ", inner); at != std::string::npos && at < inner_end;
       at = html.find("<image ", at + 1)) {
    const auto href = html.find(prefix, at);
    ASSERT_NE(href, std::string::npos);
    const auto start = href + prefix.size(), stop = html.find('"', start);
    ASSERT_EQ(html.find('>', at), stop + 2) << "every image is a data: URI and nothing else";
    const std::string data = html.substr(start, stop - start);
    EXPECT_EQ(data.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/="),
              std::string::npos);
    if (images++ == 0) first = data;
  }
  EXPECT_EQ(html.find("<image "), html.find("<image ", inner)) << "no image outside the basemap's frame";
  EXPECT_GE(images, 2u) << "a 130 x 90 m map over a 1 km tile set: more than one tile";
  EXPECT_LE(images, 24u);
  for (const std::string outside : {"href=\"http", "src=\"http", "url(http", "href=\"//", "href=\"file:"})
    EXPECT_EQ(html.find(outside), std::string::npos) << outside << ": nothing loaded from elsewhere";

  // The first image, decoded by coreutils, is a tile of the file: GDAL reads it as a PNG.
  const std::string encoded = unique_temp("tile.b64");
  const std::string decoded = unique_temp("tile.png");
  std::ofstream(encoded) << first;
  test::output_of("base64 -d " + encoded + " > " + decoded);
  EXPECT_NE(test::output_of("gdalinfo " + decoded).find("Driver: PNG/Portable Network Graphics"), std::string::npos);
  std::ifstream in(decoded, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  bool a_tile_of_the_file = false;
  for (const auto& tile : basemap.tiles_over(incident::GeodeticFrame(kOrigin), {-70.0, -50.0}, {70.0, 50.0}, 24)) {
    a_tile_of_the_file = a_tile_of_the_file || basemap.tile(tile.zoom, tile.column, tile.row) == bytes;
  }
  EXPECT_TRUE(a_tile_of_the_file);
  EXPECT_NE(html.find("Under it: the offline basemap"), std::string::npos);
  fs::remove(encoded);
  fs::remove(decoded);
}

TEST_F(ReportBasemap, WithoutTheIncidentsOriginOrATileThereNothingIsDrawnAndTheLegendSaysWhy) {
  ASSERT_TRUE(fs::exists(*path_)) << *made_;
  const app::Basemap basemap(*path_, "--basemap");
  const std::string html = render_report(field(false), nullptr, &basemap);
  EXPECT_EQ(html.find("<image"), std::string::npos);
  EXPECT_NE(html.find("No basemap: the recording holds no WGS-84 origin"), std::string::npos);
  // An origin 50 km away from the file's tiles: none over the field, and the legend says so.
  MissionRecord elsewhere = field(true);
  elsewhere.incident_origin->latitude_deg += 0.5;
  const std::string far = render_report(elsewhere, nullptr, &basemap);
  EXPECT_EQ(far.find("<image"), std::string::npos);
  EXPECT_NE(far.find("has no tile over this field"), std::string::npos);
  const std::string plain = render_report(field(true));
  EXPECT_EQ(plain.find("<image"), std::string::npos);
  EXPECT_EQ(plain.find("basemap"), std::string::npos) << "no --basemap: the report does not mention one";
}

}  // namespace
}  // namespace sarloc::report
