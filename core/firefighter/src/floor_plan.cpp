#include "sarloc/core/firefighter/floor_plan.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::firefighter {
namespace {

// Coordinates beyond this (m) are a unit error (mm for m), not a building.
constexpr double kMaxCoordinateM = 10000.0;
// A door centre farther than this from its wall's line is not on the wall.
constexpr double kOnWallToleranceM = 0.05;

[[noreturn]] void fail(const std::string& where, const std::string& rule) {
  throw ConfigError(where + ": " + rule);
}

std::string num(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

std::string fmt(const Vec2& v) {
  std::ostringstream out;
  out << "[" << v.x() << ", " << v.y() << "]";
  return out.str();
}

void check_point(const std::string& where, const Vec2& p) {
  if (!p.allFinite()) fail(where, fmt(p) + ": must be finite");
  if (p.cwiseAbs().maxCoeff() > kMaxCoordinateM) fail(where, fmt(p) + ": beyond +-10000 m");
}

void check_id(const std::string& where, const std::string& id, std::set<std::string>& seen) {
  if (id.empty()) fail(where, "id must not be empty");
  if (!seen.insert(id).second) fail(where, "duplicate id '" + id + "'");
}

// Parameter of p's projection on a->b, and its distance from the line.
double project(const Vec2& a, const Vec2& b, const Vec2& p, double& distance) {
  const Vec2 d = b - a;
  const double t = (p - a).dot(d) / d.squaredNorm();
  distance = (a + t * d - p).norm();
  return t;
}

}  // namespace

std::optional<double> Stairs::progress(const Vec2& p) const {
  const Vec2 axis = top - bottom;
  const double length = axis.norm();
  const Vec2 u = axis / length;
  const double along = (p - bottom).dot(u);
  const double across = std::abs(u.x() * (p - bottom).y() - u.y() * (p - bottom).x());
  if (along < 0.0 || along > length || across > 0.5 * width_m) return std::nullopt;
  return along / length;
}

void FloorPlan::validate() const {
  if (name.empty()) fail("name", "must not be empty");
  if (floors.empty()) fail("floors", "at least one floor is required");
  std::set<std::string> floor_ids;
  for (std::size_t f = 0; f < floors.size(); ++f) {
    const Floor& floor = floors[f];
    const std::string fw = "floors[" + (floor.id.empty() ? std::to_string(f) : floor.id) + "]";
    check_id(fw, floor.id, floor_ids);
    if (!std::isfinite(floor.elevation_m) || std::abs(floor.elevation_m) > 1000.0) {
      fail(fw + ".elevation_m", num(floor.elevation_m) + ": must be finite, within +-1000 m");
    }
    if (floor.walls.empty()) fail(fw + ".walls", "a floor needs walls");
    std::set<std::string> ids;
    for (const Wall& w : floor.walls) {
      const std::string where = fw + ".walls[" + w.id + "]";
      check_id(where, w.id, ids);
      check_point(where + ".a", w.a);
      check_point(where + ".b", w.b);
      if ((w.b - w.a).norm() < 0.05) fail(where, "zero length (a and b within 5 cm)");
    }
    for (const Door& d : floor.doors) {
      const std::string where = fw + ".doors[" + d.id + "]";
      check_id(where, d.id, ids);
      check_point(where + ".center", d.center);
      if (!std::isfinite(d.width_m) || d.width_m < 0.5 || d.width_m > 20.0) {
        fail(where + ".width_m", num(d.width_m) + ": must be within [0.5, 20] m");
      }
      const auto wall = std::find_if(floor.walls.begin(), floor.walls.end(),
                                     [&](const Wall& w) { return w.id == d.wall; });
      if (wall == floor.walls.end()) fail(where + ".wall", "'" + d.wall + "': no such wall on this floor");
      double off = 0.0;
      const double t = project(wall->a, wall->b, d.center, off);
      const double length = (wall->b - wall->a).norm();
      const double half = 0.5 * d.width_m / length;
      if (off > kOnWallToleranceM || t - half < -1e-9 || t + half > 1.0 + 1e-9) {
        fail(where, "centre " + fmt(d.center) + " width " + num(d.width_m) + " m is not on wall '" +
                        d.wall + "' (" + fmt(wall->a) + " to " + fmt(wall->b) + ")");
      }
    }
    for (const Furniture& item : floor.furniture) {
      const std::string where = fw + ".furniture[" + item.id + "]";
      check_id(where, item.id, ids);
      check_point(where + ".min", item.min);
      check_point(where + ".max", item.max);
      if ((item.max - item.min).minCoeff() <= 0.0) fail(where, "max must exceed min on both axes");
    }
  }
  std::set<std::string> other_ids;
  for (const Entry& e : entries) {
    const std::string where = "entries[" + e.id + "]";
    check_id(where, e.id, other_ids);
    check_point(where + ".position", e.position);
    if (!std::isfinite(e.heading_rad)) fail(where + ".heading_deg", "must be finite");
    if (!floor_ids.count(e.floor)) fail(where + ".floor", "'" + e.floor + "': no such floor");
    const Floor& floor = floors[floor_index(e.floor)];
    if (std::none_of(floor.doors.begin(), floor.doors.end(), [&](const Door& d) { return d.id == e.door; })) {
      fail(where + ".door", "'" + e.door + "': no such door on floor '" + e.floor + "'");
    }
  }
  if (entries.empty()) fail("entries", "at least one entry is required");
  for (const Stairs& s : stairs) {
    const std::string where = "stairs[" + s.id + "]";
    check_id(where, s.id, other_ids);
    check_point(where + ".bottom", s.bottom);
    check_point(where + ".top", s.top);
    if ((s.top - s.bottom).norm() < 0.5) fail(where, "bottom and top less than 0.5 m apart");
    if (!std::isfinite(s.width_m) || s.width_m < 0.5 || s.width_m > 10.0) {
      fail(where + ".width_m", num(s.width_m) + ": must be within [0.5, 10] m");
    }
    if (!floor_ids.count(s.lower_floor)) fail(where + ".lower_floor", "'" + s.lower_floor + "': no such floor");
    if (!floor_ids.count(s.upper_floor)) fail(where + ".upper_floor", "'" + s.upper_floor + "': no such floor");
    if (floors[floor_index(s.upper_floor)].elevation_m <= floors[floor_index(s.lower_floor)].elevation_m) {
      fail(where, "upper_floor '" + s.upper_floor + "' must be above lower_floor '" + s.lower_floor + "'");
    }
  }
}

std::size_t FloorPlan::floor_index(const std::string& id) const {
  for (std::size_t f = 0; f < floors.size(); ++f) {
    if (floors[f].id == id) return f;
  }
  throw ConfigError("floor '" + id + "': no such floor");
}

std::vector<Segment> FloorPlan::solid_walls(std::size_t floor_idx, WallSet set) const {
  const Floor& floor = floors.at(floor_idx);
  std::set<std::string> closed;  // entry doors: the search stays inside
  for (const Entry& e : entries) {
    if (e.floor == floor.id) closed.insert(e.door);
  }
  std::vector<Segment> out;
  for (const Wall& w : floor.walls) {
    const double length = (w.b - w.a).norm();
    std::vector<std::pair<double, double>> gaps;
    for (const Door& d : floor.doors) {
      if (d.wall != w.id || closed.count(d.id)) continue;
      double off = 0.0;
      const double t = project(w.a, w.b, d.center, off);
      const double half = 0.5 * d.width_m / length;
      gaps.emplace_back(t - half, t + half);
    }
    std::sort(gaps.begin(), gaps.end());
    double t0 = 0.0;
    for (const auto& [g0, g1] : gaps) {
      if (g0 > t0 + 1e-9) out.push_back({w.a + t0 * (w.b - w.a), w.a + g0 * (w.b - w.a)});
      t0 = std::max(t0, g1);
    }
    if (t0 < 1.0 - 1e-9) out.push_back({w.a + t0 * (w.b - w.a), w.b});
  }
  if (set == WallSet::kWorld) {
    for (const Furniture& item : floor.furniture) {
      const Vec2 c1(item.max.x(), item.min.y()), c3(item.min.x(), item.max.y());
      out.push_back({item.min, c1});
      out.push_back({c1, item.max});
      out.push_back({item.max, c3});
      out.push_back({c3, item.min});
    }
  }
  return out;
}

std::vector<const Stairs*> FloorPlan::stairs_of(std::size_t floor_idx) const {
  std::vector<const Stairs*> out;
  for (const Stairs& s : stairs) {
    if (s.lower_floor == floors.at(floor_idx).id || s.upper_floor == floors.at(floor_idx).id) out.push_back(&s);
  }
  return out;
}

void FloorPlan::bounds(Vec2& min, Vec2& max) const {
  min = Vec2::Constant(1e300);
  max = Vec2::Constant(-1e300);
  for (const Floor& f : floors) {
    for (const Wall& w : f.walls) {
      min = min.cwiseMin(w.a).cwiseMin(w.b);
      max = max.cwiseMax(w.a).cwiseMax(w.b);
    }
  }
}

double move_door(FloorPlan& plan, std::size_t floor, const std::string& door, double shift_m) {
  if (floor >= plan.floors.size()) throw ConfigError("move_door: floor " + config_value(floor) + " not in the plan");
  Floor& f = plan.floors[floor];
  auto it = std::find_if(f.doors.begin(), f.doors.end(), [&](const Door& d) { return d.id == door; });
  if (it == f.doors.end()) throw ConfigError("map_error.door = '" + door + "': no such door on floor '" + f.id + "'");
  const Wall& wall = *std::find_if(f.walls.begin(), f.walls.end(), [&](const Wall& w) { return w.id == it->wall; });
  const Vec2 u = (wall.b - wall.a).normalized();
  const double length = (wall.b - wall.a).norm();
  const double along = (it->center - wall.a).dot(u);
  const double t = std::clamp(along + shift_m, 0.5 * it->width_m, length - 0.5 * it->width_m);
  it->center = wall.a + t * u;
  plan.validate();
  return t - along;
}

}  // namespace sarloc::firefighter
