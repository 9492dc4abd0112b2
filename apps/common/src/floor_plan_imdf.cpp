#include "sarloc/app/floor_plan_imdf.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"
#include "sarloc/core/incident/geodetic_frame.hpp"

namespace sarloc::app {
namespace {

using firefighter::Segment;
using firefighter::Vec2;
using nlohmann::json;
namespace fs = std::filesystem;

constexpr double kOnWallM = 0.05;     // a door this near a wall is on it (FloorPlan::validate's rule)
constexpr double kCollinearM = 0.02;  // unit edges this near one line are one wall
const double kParallel = std::sin(0.5 * kPi / 180.0);
constexpr double kEntryInsideM = 0.5;  // an entry's point, this far inside its door
constexpr double kSideProbeM = 0.3;    // how far either side of an opening a unit is looked for

[[noreturn]] void refuse(const std::string& where, const std::string& what) { throw ConfigError(where + ": " + what); }

struct Collection {
  std::string path;
  json features;
};

std::optional<std::string> string_member(const json& object, const char* key) {
  if (!object.is_object() || !object.contains(key) || !object[key].is_string()) return std::nullopt;
  return object[key].get<std::string>();
}

std::optional<Collection> read_collection(const fs::path& dir, const std::string& name, bool required) {
  const fs::path file = dir / (name + ".geojson");
  if (!fs::exists(file)) {
    if (required) refuse(file.string(), "missing: an IMDF archive for sarloc needs " + name + ".geojson");
    return std::nullopt;
  }
  std::ifstream in(file);
  json doc;
  try {
    doc = json::parse(in);
  } catch (const json::exception& e) {
    refuse(file.string(), std::string("not JSON: ") + e.what());
  }
  if (string_member(doc, "type") != "FeatureCollection" || !doc.contains("features") || !doc["features"].is_array()) {
    refuse(file.string(), "not a GeoJSON FeatureCollection");
  }
  return Collection{file.string(), doc["features"]};
}

/// One feature of a collection, with the file and its id for every message.
struct Feature {
  const json& f;
  std::string where;  // "unit.geojson: unit 'ID'"
  std::string id;
  const json& properties() const { return f["properties"]; }
};

std::vector<Feature> features_of(const Collection& c, const std::string& kind) {
  std::vector<Feature> out;
  for (std::size_t i = 0; i < c.features.size(); ++i) {
    const json& f = c.features[i];
    const auto id = string_member(f, "id");
    const std::string at = c.path + ": features[" + std::to_string(i) + "]";
    if (!id) refuse(at, "no string id");
    if (!f.contains("properties") || !f["properties"].is_object()) refuse(at, kind + " '" + *id + "': no properties");
    if (!f.contains("geometry") || !f["geometry"].is_object()) refuse(at, kind + " '" + *id + "': no geometry");
    out.push_back({f, c.path + ": " + kind + " '" + *id + "'", *id});
  }
  return out;
}

/// IMDF LABELS ({"en": "Hall"}): the first language's text.
std::optional<std::string> label(const json& properties, const char* key) {
  if (!properties.contains(key) || !properties[key].is_object()) return std::nullopt;
  for (const auto& [language, text] : properties[key].items()) {
    if (text.is_string()) return text.get<std::string>();
  }
  return std::nullopt;
}

class PlanFrame {
 public:
  explicit PlanFrame(const GeodeticOrigin& origin) : frame_(origin) {}
  Vec2 point(const json& position, const std::string& where) const {
    if (!position.is_array() || position.size() < 2 || !position[0].is_number() || !position[1].is_number()) {
      refuse(where, "a position must be [longitude, latitude]");
    }
    const double lon = position[0].get<double>(), lat = position[1].get<double>();
    if (!std::isfinite(lon) || !std::isfinite(lat) || std::abs(lon) > 180.0 || std::abs(lat) > 90.0) {
      refuse(where, "position [" + config_value(lon) + ", " + config_value(lat) +
                        "]: longitude must be within [-180, 180] and latitude within [-90, 90]");
    }
    const Vec3 enu = frame_.to_enu({lat, lon, 0.0});
    return {enu.x(), enu.y()};
  }

 private:
  incident::GeodeticFrame frame_;
};

using Ring = std::vector<Vec2>;  // closed: the last point repeats the first
using Polygon = std::vector<Ring>;

std::string geometry_type(const Feature& f) { return string_member(f.f["geometry"], "type").value_or(""); }

// The geometry's coordinates, null when it has none (a const json's operator[] must not be asked
// for a key it lacks).
const json& coordinates_of(const Feature& f) {
  static const json none;
  const json& geometry = f.f["geometry"];
  return geometry.contains("coordinates") ? geometry["coordinates"] : none;
}

Ring read_ring(const json& positions, const PlanFrame& frame, const std::string& where) {
  if (!positions.is_array() || positions.size() < 4) refuse(where, "a ring needs at least 4 positions");
  if (positions.front() != positions.back())
    refuse(where, "the ring does not close (its first and last positions differ)");
  Ring ring;
  for (const json& p : positions) ring.push_back(frame.point(p, where));
  return ring;
}

std::vector<Polygon> read_polygons(const Feature& f, const PlanFrame& frame) {
  const std::string type = geometry_type(f);
  const json& coordinates = coordinates_of(f);
  std::vector<json> polygons;
  if (type == "Polygon") {
    polygons.push_back(coordinates);
  } else if (type == "MultiPolygon" && coordinates.is_array()) {
    for (const json& p : coordinates) polygons.push_back(p);
  } else {
    refuse(f.where, "geometry '" + type + "': must be a Polygon or MultiPolygon");
  }
  std::vector<Polygon> out;
  for (const json& rings : polygons) {
    if (!rings.is_array() || rings.empty()) refuse(f.where, "a polygon without rings");
    Polygon polygon;
    for (std::size_t r = 0; r < rings.size(); ++r) {
      polygon.push_back(read_ring(rings[r], frame, f.where + " ring " + std::to_string(r)));
    }
    out.push_back(polygon);
  }
  return out;
}

std::vector<Vec2> read_line(const Feature& f, const PlanFrame& frame) {
  const json& coordinates = coordinates_of(f);
  if (geometry_type(f) != "LineString" || !coordinates.is_array() || coordinates.size() < 2) {
    refuse(f.where, "geometry must be a LineString of at least 2 positions");
  }
  std::vector<Vec2> line;
  for (const json& p : coordinates) line.push_back(frame.point(p, f.where));
  return line;
}

// Even-odd over every ring: a hole's inside is outside.
bool inside(const Polygon& polygon, const Vec2& p) {
  bool in = false;
  for (const Ring& ring : polygon) {
    for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
      const Vec2& a = ring[i];
      const Vec2& b = ring[j];
      if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
        in = !in;
      }
    }
  }
  return in;
}

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// `p` lies on segment a-b (within kOnWallM of its line), with room for `half_width` either side.
bool on_segment(const Vec2& a, const Vec2& b, const Vec2& p, double half_width) {
  const double length = (b - a).norm();
  if (length < 1e-9) return false;
  const Vec2 u = (b - a) / length;
  const double t = u.dot(p - a);
  return std::abs(cross(u, p - a)) <= kOnWallM && t >= half_width - kOnWallM && t <= length - half_width + kOnWallM;
}

// Every unit edge and detail line as walls: edges on one line (two rooms either side of one wall,
// a corridor's long side and the rooms along it) merged where they overlap or touch.
std::vector<firefighter::Wall> merged_walls(const std::vector<Segment>& edges) {
  struct Line {
    Vec2 origin, direction;
    std::vector<std::pair<double, double>> spans;
  };
  std::vector<Line> lines;
  for (const Segment& e : edges) {
    const double length = e.length();
    if (length < kCollinearM) continue;
    const Vec2 u = (e.b - e.a) / length;
    auto line = std::find_if(lines.begin(), lines.end(), [&](const Line& l) {
      const Vec2 normal(-l.direction.y(), l.direction.x());
      return std::abs(cross(l.direction, u)) < kParallel && std::abs(normal.dot(e.a - l.origin)) < kCollinearM &&
             std::abs(normal.dot(e.b - l.origin)) < kCollinearM;
    });
    if (line == lines.end()) line = lines.insert(lines.end(), Line{e.a, u, {}});
    const double t1 = line->direction.dot(e.a - line->origin), t2 = line->direction.dot(e.b - line->origin);
    line->spans.emplace_back(std::min(t1, t2), std::max(t1, t2));
  }
  std::vector<firefighter::Wall> walls;
  for (Line& l : lines) {
    std::sort(l.spans.begin(), l.spans.end());
    std::vector<std::pair<double, double>> merged;
    for (const auto& s : l.spans) {
      if (!merged.empty() && s.first <= merged.back().second + kCollinearM) {
        merged.back().second = std::max(merged.back().second, s.second);
      } else {
        merged.push_back(s);
      }
    }
    for (const auto& [t1, t2] : merged) {
      walls.push_back(
          {"w" + std::to_string(walls.size() + 1), l.origin + t1 * l.direction, l.origin + t2 * l.direction});
    }
  }
  return walls;
}

struct Level {
  std::string feature_id;
  long ordinal = 0;
  std::size_t floor = 0;  // index into the plan's floors
  std::vector<Polygon> units;
  std::vector<Segment> edges;
  struct StairsUnit {
    std::string where, id, name;
    Ring ring;
  };
  std::vector<StairsUnit> stairs;
  std::vector<std::pair<Vec2, Vec2>> openings;  // ends, for the stairs
};

// The edge of a stairs unit's ring that holds one of its level's openings: the flight's end there.
Segment flight_end(const Level::StairsUnit& s, const Level& level, const char* end) {
  std::optional<Segment> found;
  for (std::size_t i = 0; i + 1 < s.ring.size(); ++i) {
    for (const auto& [a, b] : level.openings) {
      if (!on_segment(s.ring[i], s.ring[i + 1], 0.5 * (a + b), 0.5 * (b - a).norm())) continue;
      if (found)
        refuse(s.where, std::string("more than one edge holds an opening on this level: its ") + end + " is ambiguous");
      found = Segment{s.ring[i], s.ring[i + 1]};
    }
  }
  if (!found)
    refuse(s.where, std::string("no edge holds an opening on this level: the flight's ") + end + " is unknown");
  return *found;
}

}  // namespace

bool is_imdf_directory(const std::string& path) {
  std::error_code ec;
  return fs::is_directory(path, ec) && fs::exists(fs::path(path) / "manifest.json", ec);
}

firefighter::FloorPlan load_floor_plan_imdf(const std::string& directory, const ImdfImport& options) {
  if (!std::isfinite(options.storey_height_m) || options.storey_height_m < 1.0 || options.storey_height_m > 20.0) {
    throw ConfigError("IMDF import: storey_height_m = " + config_value(options.storey_height_m) +
                      ": must be within [1, 20] m");
  }
  const fs::path dir(directory);
  if (!is_imdf_directory(directory)) refuse(directory, "not an IMDF archive (a directory with a manifest.json)");
  const Collection venues = *read_collection(dir, "venue", true);
  const std::vector<Feature> venue = features_of(venues, "venue");
  if (venue.size() != 1) refuse(venues.path, "one venue expected, found " + std::to_string(venue.size()));
  const json& display = venue[0].properties().value("display_point", json());
  if (string_member(display, "type") != "Point" || !display.contains("coordinates")) {
    refuse(venue[0].where, "display_point: a GeoJSON Point is required (the plan's origin)");
  }
  const json& origin_position = display["coordinates"];
  {
    const PlanFrame probe(GeodeticOrigin{});
    probe.point(origin_position, venue[0].where + ": display_point");  // range checks
  }
  const PlanFrame frame(GeodeticOrigin{origin_position[1].get<double>(), origin_position[0].get<double>(), 0.0});

  firefighter::FloorPlan plan;
  plan.name = label(venue[0].properties(), "name").value_or(dir.filename().string());

  const Collection level_file = *read_collection(dir, "level", true);
  std::map<std::string, Level> levels;  // by feature id
  std::map<long, std::string> by_ordinal;
  for (const Feature& f : features_of(level_file, "level")) {
    const json& ordinal = f.properties().value("ordinal", json());
    if (!ordinal.is_number_integer()) refuse(f.where, "ordinal: an integer is required");
    Level level;
    level.feature_id = f.id;
    level.ordinal = ordinal.get<long>();
    if (by_ordinal.count(level.ordinal)) {
      refuse(f.where, "ordinal " + std::to_string(level.ordinal) + " is also level '" + by_ordinal[level.ordinal] +
                          "'s: one building, one level per ordinal");
    }
    if (levels.count(f.id)) refuse(f.where, "a second level with this id");
    by_ordinal[level.ordinal] = f.id;
    firefighter::Floor floor;
    floor.id = label(f.properties(), "short_name").value_or(f.id);
    floor.elevation_m = static_cast<double>(level.ordinal) * options.storey_height_m;
    level.floor = plan.floors.size();
    plan.floors.push_back(floor);
    levels.emplace(f.id, level);
  }
  if (levels.empty()) refuse(level_file.path, "no level");
  auto level_of = [&](const Feature& f) -> Level& {
    const auto id = string_member(f.properties(), "level_id");
    if (!id) refuse(f.where, "level_id: required");
    const auto it = levels.find(*id);
    if (it == levels.end()) refuse(f.where, "level_id '" + *id + "': no such level");
    return it->second;
  };

  const Collection units = *read_collection(dir, "unit", true);
  for (const Feature& f : features_of(units, "unit")) {
    Level& level = level_of(f);
    const std::vector<Polygon> polygons = read_polygons(f, frame);
    for (const Polygon& polygon : polygons) {
      for (const Ring& ring : polygon) {
        for (std::size_t i = 0; i + 1 < ring.size(); ++i) level.edges.push_back({ring[i], ring[i + 1]});
      }
      level.units.push_back(polygon);
    }
    if (string_member(f.properties(), "category") == "stairs") {
      if (polygons.size() != 1) refuse(f.where, "a stairs unit must be one polygon");
      level.stairs.push_back({f.where, f.id, label(f.properties(), "name").value_or(f.id), polygons[0][0]});
    }
  }
  if (const auto details = read_collection(dir, "detail", false)) {
    for (const Feature& f : features_of(*details, "detail")) {
      Level& level = level_of(f);
      const std::vector<Vec2> line = read_line(f, frame);
      for (std::size_t i = 0; i + 1 < line.size(); ++i) level.edges.push_back({line[i], line[i + 1]});
    }
  }
  for (auto& [id, level] : levels) {
    if (level.units.empty()) refuse(level_file.path + ": level '" + id + "'", "no unit lies on it");
    plan.floors[level.floor].walls = merged_walls(level.edges);
  }

  const Collection openings = *read_collection(dir, "opening", true);
  for (const Feature& f : features_of(openings, "opening")) {
    Level& level = level_of(f);
    const std::vector<Vec2> line = read_line(f, frame);
    if (line.size() != 2) refuse(f.where, "an opening must be one straight line (2 positions)");
    firefighter::Floor& floor = plan.floors[level.floor];
    const Vec2 centre = 0.5 * (line[0] + line[1]);
    const double width = (line[1] - line[0]).norm();
    const Vec2 along = (line[1] - line[0]) / std::max(width, 1e-9);
    const auto wall = std::find_if(floor.walls.begin(), floor.walls.end(), [&](const firefighter::Wall& w) {
      return std::abs(cross((w.b - w.a).normalized(), along)) < kParallel && on_segment(w.a, w.b, centre, 0.5 * width);
    });
    if (wall == floor.walls.end()) {
      refuse(f.where, "centre [" + config_value(centre.x()) + ", " + config_value(centre.y()) +
                          "] m lies along no unit's edge on its level: a door must sit in a wall");
    }
    const Vec2 u = (wall->b - wall->a).normalized();
    firefighter::Door door;
    door.id = f.id;
    door.wall = wall->id;
    door.center = wall->a + u.dot(centre - wall->a) * u;
    door.width_m = width;
    door.kind = f.properties().contains("door") && f.properties()["door"].is_object()
                    ? firefighter::OpeningKind::kDoor
                    : firefighter::OpeningKind::kOpening;
    floor.doors.push_back(door);
    level.openings.emplace_back(line[0], line[1]);
    // A door with a unit on one side only leads out: an entry, just inside it.
    const Vec2 normal(-u.y(), u.x());
    auto in_a_unit = [&](const Vec2& p) {
      return std::any_of(level.units.begin(), level.units.end(), [&](const Polygon& unit) { return inside(unit, p); });
    };
    const bool left = in_a_unit(door.center + kSideProbeM * normal),
               right = in_a_unit(door.center - kSideProbeM * normal);
    if (left != right) {
      const Vec2 in = left ? normal : Vec2(-normal);
      plan.entries.push_back({label(f.properties(), "name").value_or(f.id), floor.id, door.id,
                              door.center + kEntryInsideM * in, std::atan2(in.y(), in.x())});
    }
  }

  if (const auto fixtures = read_collection(dir, "fixture", false)) {
    for (const Feature& f : features_of(*fixtures, "fixture")) {
      Level& level = level_of(f);
      firefighter::Furniture item;
      item.id = f.id;
      item.min = Vec2::Constant(1e300);
      item.max = Vec2::Constant(-1e300);
      for (const Polygon& polygon : read_polygons(f, frame)) {
        for (const Vec2& p : polygon[0]) {
          item.min = item.min.cwiseMin(p);
          item.max = item.max.cwiseMax(p);
        }
      }
      plan.floors[level.floor].furniture.push_back(item);
    }
  }

  // Flights: a stairs unit over one on the next level up.
  for (auto it = by_ordinal.begin(); it != by_ordinal.end() && std::next(it) != by_ordinal.end(); ++it) {
    const Level& lower = levels.at(it->second);
    const Level& upper = levels.at(std::next(it)->second);
    bool joined = false;
    for (const Level::StairsUnit& s : lower.stairs) {
      Vec2 centroid = Vec2::Zero();
      for (std::size_t i = 0; i + 1 < s.ring.size(); ++i) centroid += s.ring[i];
      centroid /= static_cast<double>(s.ring.size() - 1);
      const auto above = std::find_if(upper.stairs.begin(), upper.stairs.end(),
                                      [&](const Level::StairsUnit& t) { return inside(Polygon{t.ring}, centroid); });
      if (above == upper.stairs.end()) continue;
      const Segment bottom = flight_end(s, lower, "bottom");
      const Segment top = flight_end(*above, upper, "top");
      firefighter::Stairs flight;
      flight.id = s.name;
      flight.lower_floor = plan.floors[lower.floor].id;
      flight.upper_floor = plan.floors[upper.floor].id;
      flight.bottom = 0.5 * (bottom.a + bottom.b);
      flight.top = 0.5 * (top.a + top.b);
      flight.width_m = std::min(bottom.length(), top.length());
      plan.stairs.push_back(flight);
      joined = true;
    }
    if (!joined) {
      refuse(level_file.path + ": level '" + upper.feature_id + "'",
             "ordinal " + std::to_string(upper.ordinal) + " has no stairs unit over one of level '" + lower.feature_id +
                 "' below it: the levels cannot be told apart or walked between");
    }
  }
  try {
    plan.validate();
  } catch (const ConfigError& e) {
    throw ConfigError(directory + ": " + e.what());
  }
  return plan;
}

}  // namespace sarloc::app
