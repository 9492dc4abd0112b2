// IMDF -> FloorPlan (floor_plan_imdf.hpp): the shipped house-125.imdf, drawn by hand as rooms,
// openings and inner walls in WGS-84, is the same building as house-125.yaml drawn as walls in
// metres; and what the importer cannot map is refused naming the file and the feature.
#include "sarloc/app/floor_plan_imdf.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "sarloc/app/floor_plan_yaml.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/firefighter/search_pattern.hpp"

namespace sarloc::app {
namespace {

namespace fs = std::filesystem;
using firefighter::FloorPlan;
using firefighter::Segment;
using firefighter::Vec2;
using firefighter::WallSet;

const fs::path kBuildings = fs::path(SARLOC_SOURCE_DIR) / "config" / "buildings";

double distance_to(const Segment& s, const Vec2& p) {
  const Vec2 d = s.b - s.a;
  const double t = std::clamp(d.dot(p - s.a) / d.squaredNorm(), 0.0, 1.0);
  return (s.a + t * d - p).norm();
}

// The largest distance from a point of `from`'s walls (every 5 cm) to the nearest wall of `to`.
double farthest(const std::vector<Segment>& from, const std::vector<Segment>& to) {
  double worst = 0.0;
  for (const Segment& s : from) {
    const int steps = std::max(1, static_cast<int>(s.length() / 0.05));
    for (int k = 0; k <= steps; ++k) {
      const Vec2 p = s.a + (s.b - s.a) * (static_cast<double>(k) / steps);
      double nearest = 1e300;
      for (const Segment& t : to) nearest = std::min(nearest, distance_to(t, p));
      worst = std::max(worst, nearest);
    }
  }
  return worst;
}

// The IMDF archive and the YAML of one shipped building: the same walls (to 5 mm, both ways), the
// YAML's doors, the entries, the flights, the furniture, and the navigable grid the filter and
// the patterns are built on. IMDF needs an opening where a flight meets a floor (the YAML simply
// has no wall there), so the import may hold more doors, each spanning a whole wall piece.
void expect_twins(const std::string& name) {
  SCOPED_TRACE(name);
  const FloorPlan yaml = load_floor_plan((kBuildings / (name + ".yaml")).string());
  const FloorPlan imdf = load_floor_plan((kBuildings / (name + ".imdf")).string());  // found by its manifest
  EXPECT_EQ(imdf.name, yaml.name);
  ASSERT_EQ(imdf.floors.size(), yaml.floors.size());
  for (std::size_t f = 0; f < yaml.floors.size(); ++f) {
    EXPECT_EQ(imdf.floors[f].id, yaml.floors[f].id);
    EXPECT_DOUBLE_EQ(imdf.floors[f].elevation_m, yaml.floors[f].elevation_m);
    for (const WallSet set : {WallSet::kNavigation, WallSet::kWorld}) {
      const auto a = yaml.solid_walls(f, set), b = imdf.solid_walls(f, set);
      EXPECT_LT(farthest(a, b), 0.005) << "floor " << f << ": a wall of the YAML is missing from the import";
      EXPECT_LT(farthest(b, a), 0.005) << "floor " << f << ": the import has a wall the YAML does not";
    }
    for (const auto& door : yaml.floors[f].doors) {
      const auto match = std::find_if(imdf.floors[f].doors.begin(), imdf.floors[f].doors.end(),
                                      [&](const auto& d) { return (d.center - door.center).norm() < 0.005; });
      ASSERT_NE(match, imdf.floors[f].doors.end()) << door.id;
      EXPECT_NEAR(match->width_m, door.width_m, 0.005) << door.id;
      EXPECT_EQ(match->kind, door.kind) << door.id;
    }
    ASSERT_EQ(imdf.floors[f].furniture.size(), yaml.floors[f].furniture.size());
    for (std::size_t i = 0; i < yaml.floors[f].furniture.size(); ++i) {
      EXPECT_LT((imdf.floors[f].furniture[i].min - yaml.floors[f].furniture[i].min).norm(), 0.005);
      EXPECT_LT((imdf.floors[f].furniture[i].max - yaml.floors[f].furniture[i].max).norm(), 0.005);
    }
  }
  ASSERT_EQ(imdf.entries.size(), yaml.entries.size());
  for (std::size_t i = 0; i < yaml.entries.size(); ++i) {
    EXPECT_EQ(imdf.entries[i].id, yaml.entries[i].id);
    EXPECT_EQ(imdf.entries[i].floor, yaml.entries[i].floor);
    EXPECT_LT((imdf.entries[i].position - yaml.entries[i].position).norm(), 0.005);
    EXPECT_NEAR(imdf.entries[i].heading_rad, yaml.entries[i].heading_rad, 1e-6);
  }
  ASSERT_EQ(imdf.stairs.size(), yaml.stairs.size());
  for (std::size_t i = 0; i < yaml.stairs.size(); ++i) {
    EXPECT_EQ(imdf.stairs[i].id, yaml.stairs[i].id);
    EXPECT_EQ(imdf.stairs[i].lower_floor, yaml.stairs[i].lower_floor);
    EXPECT_EQ(imdf.stairs[i].upper_floor, yaml.stairs[i].upper_floor);
    EXPECT_LT((imdf.stairs[i].bottom - yaml.stairs[i].bottom).norm(), 0.005);
    EXPECT_LT((imdf.stairs[i].top - yaml.stairs[i].top).norm(), 0.005);
    EXPECT_NEAR(imdf.stairs[i].width_m, yaml.stairs[i].width_m, 0.005);
  }
  const auto grid_yaml = firefighter::navigable_grid(yaml, firefighter::PatternGridConfig{});
  const auto grid_imdf = firefighter::navigable_grid(imdf, firefighter::PatternGridConfig{});
  ASSERT_EQ(grid_imdf.nodes_per_floor.size(), grid_yaml.nodes_per_floor.size());
  for (std::size_t f = 0; f < grid_yaml.nodes_per_floor.size(); ++f) {
    ASSERT_EQ(grid_imdf.nodes_per_floor[f].size(), grid_yaml.nodes_per_floor[f].size()) << "floor " << f;
    for (std::size_t i = 0; i < grid_yaml.nodes_per_floor[f].size(); ++i) {
      EXPECT_LT((grid_imdf.nodes_per_floor[f][i] - grid_yaml.nodes_per_floor[f][i]).norm(), 1e-3) << f << " " << i;
    }
  }
}

// A recording carries an imported plan as YAML (floor_plan_yaml_text): read back, it is the plan.
TEST(FloorPlanImdf, AnImportedPlanWrittenAsYamlReadsBackExactly) {
  const FloorPlan imdf = load_floor_plan((kBuildings / "office-253.imdf").string());
  const FloorPlan back = load_floor_plan_text(floor_plan_yaml_text(imdf), "written");
  ASSERT_EQ(back.floors.size(), imdf.floors.size());
  for (std::size_t f = 0; f < imdf.floors.size(); ++f) {
    ASSERT_EQ(back.floors[f].walls.size(), imdf.floors[f].walls.size());
    for (std::size_t i = 0; i < imdf.floors[f].walls.size(); ++i) {
      EXPECT_EQ(back.floors[f].walls[i].a, imdf.floors[f].walls[i].a);
      EXPECT_EQ(back.floors[f].walls[i].b, imdf.floors[f].walls[i].b);
    }
    ASSERT_EQ(back.floors[f].doors.size(), imdf.floors[f].doors.size());
    for (std::size_t i = 0; i < imdf.floors[f].doors.size(); ++i) {
      EXPECT_EQ(back.floors[f].doors[i].id, imdf.floors[f].doors[i].id);
      EXPECT_EQ(back.floors[f].doors[i].center, imdf.floors[f].doors[i].center);
      EXPECT_EQ(back.floors[f].doors[i].kind, imdf.floors[f].doors[i].kind);
    }
  }
  ASSERT_EQ(back.entries.size(), 1U);
  EXPECT_NEAR(back.entries[0].heading_rad, imdf.entries[0].heading_rad, 1e-12);
  ASSERT_EQ(back.stairs.size(), 1U);
  EXPECT_EQ(back.stairs[0].top, imdf.stairs[0].top);
}

TEST(FloorPlanImdf, TheShippedHouseAndOfficeAreTheirYamlTwins) {
  expect_twins("house-125");
  expect_twins("office-253");  // two levels and a flight between them
}

// A copy of the shipped archive with one collection's features edited.
class BrokenArchive : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("sarloc_imdf_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::copy(kBuildings / "house-125.imdf", dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  nlohmann::json read(const std::string& name) { return nlohmann::json::parse(std::ifstream(dir_ / name)); }
  void write(const std::string& name, const nlohmann::json& j) { std::ofstream(dir_ / name) << j.dump(); }
  std::string refusal() {
    try {
      load_floor_plan_imdf(dir_.string());
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "(accepted)";
  }
  fs::path dir_;
};

TEST_F(BrokenArchive, AUnitWhoseRingDoesNotCloseIsRefusedByItsId) {
  auto units = read("unit.geojson");
  units["features"][1]["geometry"]["coordinates"][0].back()[0] = 9.8300001;
  write("unit.geojson", units);
  const std::string id = units["features"][1]["id"];
  std::string message = refusal();
  EXPECT_NE(message.find("unit '" + id + "'"), std::string::npos) << message;
  EXPECT_NE(message.find("does not close"), std::string::npos) << message;
  units["features"][1]["geometry"].erase("coordinates");  // a geometry with no coordinates at all
  write("unit.geojson", units);
  message = refusal();
  EXPECT_NE(message.find("unit '" + id + "'"), std::string::npos) << message;
}

TEST_F(BrokenArchive, AnOpeningOnNoWallIsRefusedByItsId) {
  auto openings = read("opening.geojson");
  for (auto& p : openings["features"][2]["geometry"]["coordinates"]) p[1] = p[1].get<double>() + 1e-5;  // 1.1 m north
  write("opening.geojson", openings);
  const std::string id = openings["features"][2]["id"];
  const std::string message = refusal();
  EXPECT_NE(message.find("opening '" + id + "'"), std::string::npos) << message;
  EXPECT_NE(message.find("no unit's edge"), std::string::npos) << message;
}

TEST_F(BrokenArchive, ALevelOverAnotherWithoutStairsIsRefused) {
  auto levels = read("level.geojson");
  auto upper = levels["features"][0];
  upper["id"] = "11111111-2222-3333-4444-555555555555";
  upper["properties"]["ordinal"] = 1;
  upper["properties"]["short_name"]["en"] = "upper";
  levels["features"].push_back(upper);
  write("level.geojson", levels);
  auto units = read("unit.geojson");
  auto room = units["features"][0];
  room["id"] = "11111111-2222-3333-4444-666666666666";
  room["properties"]["level_id"] = upper["id"];
  units["features"].push_back(room);
  write("unit.geojson", units);
  const std::string message = refusal();
  EXPECT_NE(message.find("level '11111111-2222-3333-4444-555555555555'"), std::string::npos) << message;
  EXPECT_NE(message.find("no stairs unit"), std::string::npos) << message;
}

TEST_F(BrokenArchive, ACoordinateOutOfRangeOrAnUnknownLevelIsRefusedByItsId) {
  auto details = read("detail.geojson");
  details["features"][0]["geometry"]["coordinates"][0][1] = 95.0;
  write("detail.geojson", details);
  std::string message = refusal();
  EXPECT_NE(message.find("detail '" + details["features"][0]["id"].get<std::string>() + "'"), std::string::npos)
      << message;
  EXPECT_NE(message.find("latitude"), std::string::npos) << message;

  details["features"][0]["geometry"]["coordinates"][0][1] = 46.8;
  details["features"][0]["properties"]["level_id"] = "no-such-level";
  write("detail.geojson", details);
  message = refusal();
  EXPECT_NE(message.find("level_id 'no-such-level': no such level"), std::string::npos) << message;

  details["features"][0]["properties"]["level_id"] = read("level.geojson")["features"][0]["id"];
  write("detail.geojson", details);
  std::ofstream(dir_ / "opening.geojson") << "{\"type\": \"FeatureCollection\", \"features\": [";  // cut short
  message = refusal();
  EXPECT_NE(message.find("opening.geojson: not JSON"), std::string::npos) << message;
}

}  // namespace
}  // namespace sarloc::app
