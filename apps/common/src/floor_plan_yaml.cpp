#include "sarloc/app/floor_plan_yaml.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>

#include "sarloc/app/floor_plan_imdf.hpp"
#include "sarloc/app/yaml_reader.hpp"
#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::app {
namespace {

using firefighter::Vec2;

Vec2 read_point(YamlReader& y, const std::string& key) {
  std::vector<double> v;
  y.require(key, v);
  if (v.size() != 2) {
    throw ConfigError(y.source() + ": " + y.path() + "." + key + ": expected [x, y] in metres, got " +
                      config_value(v.size()) + " numbers");
  }
  return {v[0], v[1]};
}

firefighter::FloorPlan read_plan(YamlReader& yaml) {
  firefighter::FloorPlan plan;
  yaml.require("name", plan.name);
  for (YamlReader& fy : yaml.child_list("floors")) {
    firefighter::Floor floor;
    fy.require("id", floor.id);
    fy.read("elevation_m", floor.elevation_m);
    for (YamlReader& wy : fy.child_list("walls")) {
      firefighter::Wall w;
      wy.require("id", w.id);
      w.a = read_point(wy, "a");
      w.b = read_point(wy, "b");
      wy.expect_done();
      floor.walls.push_back(w);
    }
    for (YamlReader& dy : fy.child_list("doors")) {
      firefighter::Door d;
      dy.require("id", d.id);
      dy.require("wall", d.wall);
      d.center = read_point(dy, "center");
      dy.read("width_m", d.width_m);
      std::string kind = "door";
      dy.read("kind", kind);
      if (kind == "door") {
        d.kind = firefighter::OpeningKind::kDoor;
      } else if (kind == "opening") {
        d.kind = firefighter::OpeningKind::kOpening;
      } else {
        throw ConfigError(dy.source() + ": " + dy.path() + ".kind = '" + kind + "': must be door or opening");
      }
      dy.expect_done();
      floor.doors.push_back(d);
    }
    for (YamlReader& iy : fy.child_list("furniture")) {
      firefighter::Furniture item;
      iy.require("id", item.id);
      item.min = read_point(iy, "min");
      item.max = read_point(iy, "max");
      iy.expect_done();
      floor.furniture.push_back(item);
    }
    fy.expect_done();
    plan.floors.push_back(floor);
  }
  for (YamlReader& ey : yaml.child_list("entries")) {
    firefighter::Entry e;
    ey.require("id", e.id);
    ey.require("floor", e.floor);
    ey.require("door", e.door);
    e.position = read_point(ey, "position");
    double heading_deg = 0.0;
    ey.require("heading_deg", heading_deg);
    e.heading_rad = heading_deg * kPi / 180.0;
    ey.expect_done();
    plan.entries.push_back(e);
  }
  for (YamlReader& sy : yaml.child_list("stairs")) {
    firefighter::Stairs s;
    sy.require("id", s.id);
    sy.require("lower_floor", s.lower_floor);
    sy.require("upper_floor", s.upper_floor);
    s.bottom = read_point(sy, "bottom");
    s.top = read_point(sy, "top");
    sy.read("width_m", s.width_m);
    sy.expect_done();
    plan.stairs.push_back(s);
  }
  yaml.expect_done();
  return plan;
}

firefighter::FloorPlan validated(firefighter::FloorPlan plan, const std::string& source) {
  try {
    plan.validate();
  } catch (const ConfigError& e) {
    throw ConfigError(source + ": " + e.what());
  }
  return plan;
}

}  // namespace

firefighter::FloorPlan load_floor_plan(const std::string& path) {
  if (is_imdf_directory(path)) return load_floor_plan_imdf(path);
  YamlReader yaml = YamlReader::from_file(path);
  return validated(read_plan(yaml), path);
}

namespace {

// Shortest exact text of a double (round trip), for points in flow sequences.
std::string exact(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  return buffer;
}

std::string point(const Vec2& p) { return "[" + exact(p.x()) + ", " + exact(p.y()) + "]"; }

// A YAML double-quoted string: ids from IMDF are the writer's, not ours.
std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace

std::string floor_plan_yaml_text(const firefighter::FloorPlan& plan) {
  std::string y =
      "# written by sarloc from an imported plan (docs/configuration.md, \"Floor plans\")\nname: " + quoted(plan.name) +
      "\nfloors:\n";
  for (const auto& f : plan.floors) {
    y += "  - id: " + quoted(f.id) + "\n    elevation_m: " + exact(f.elevation_m) + "\n    walls:\n";
    for (const auto& w : f.walls)
      y += "      - {id: " + quoted(w.id) + ", a: " + point(w.a) + ", b: " + point(w.b) + "}\n";
    y += "    doors:\n";
    for (const auto& d : f.doors) {
      y += "      - {id: " + quoted(d.id) + ", wall: " + quoted(d.wall) + ", center: " + point(d.center) +
           ", width_m: " + exact(d.width_m) +
           ", kind: " + (d.kind == firefighter::OpeningKind::kDoor ? "door" : "opening") + "}\n";
    }
    y += "    furniture:\n";
    for (const auto& i : f.furniture)
      y += "      - {id: " + quoted(i.id) + ", min: " + point(i.min) + ", max: " + point(i.max) + "}\n";
  }
  y += "entries:\n";
  for (const auto& e : plan.entries) {
    y += "  - {id: " + quoted(e.id) + ", floor: " + quoted(e.floor) + ", door: " + quoted(e.door) +
         ", position: " + point(e.position) + ", heading_deg: " + exact(e.heading_rad * 180.0 / kPi) + "}\n";
  }
  y += "stairs:\n";
  for (const auto& s : plan.stairs) {
    y += "  - {id: " + quoted(s.id) + ", lower_floor: " + quoted(s.lower_floor) +
         ", upper_floor: " + quoted(s.upper_floor) + ", bottom: " + point(s.bottom) + ", top: " + point(s.top) +
         ", width_m: " + exact(s.width_m) + "}\n";
  }
  return y;
}

firefighter::FloorPlan load_floor_plan_text(const std::string& text, const std::string& name) {
  YamlReader yaml = YamlReader::from_string(text, name);
  return validated(read_plan(yaml), name);
}

}  // namespace sarloc::app
