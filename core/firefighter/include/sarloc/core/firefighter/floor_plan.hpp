#pragma once
// A building's floor plan (docs/configuration.md, "Floor plans"): walls as segments in metres,
// doors and openings cut into them, entry points, floors at their elevations and the stairs
// between floors. Furniture is part of the simulated world only: the navigation map (the
// filter, the search patterns) never sees it, as a fire department's plan would not show it.
//
// The map of seed 004 section IV-B makes no distinction between doors and openings of the same
// size; sarloc keeps the kind for the reader. An entry names the exterior door it uses; that
// door is closed in the navigation map (a search stays inside the building).
//
//   FloorPlan plan = ...;          // apps/common: load_floor_plan(path)
//   plan.validate();               // ConfigError naming the element
//   auto walls = plan.solid_walls(0, WallSet::kNavigation);
#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <string>
#include <cmath>
#include <vector>

namespace sarloc::firefighter {

using Vec2 = Eigen::Vector2d;

/// `v` turned by `a` rad counter-clockwise.
inline Vec2 rotate(const Vec2& v, double a) {
  return {std::cos(a) * v.x() - std::sin(a) * v.y(), std::sin(a) * v.x() + std::cos(a) * v.y()};
}

struct Segment {
  Vec2 a = Vec2::Zero();
  Vec2 b = Vec2::Zero();
  double length() const { return (b - a).norm(); }
};

struct Wall {
  std::string id;
  Vec2 a = Vec2::Zero();
  Vec2 b = Vec2::Zero();
};

enum class OpeningKind { kDoor, kOpening };

/// A door or opening of `width_m` centred at `center` on the wall `wall`.
struct Door {
  std::string id;
  std::string wall;
  Vec2 center = Vec2::Zero();
  double width_m = 0.9;
  OpeningKind kind = OpeningKind::kDoor;
};

/// An axis-aligned box (bed, table, shelf) the walker goes around; not in the navigation map.
struct Furniture {
  std::string id;
  Vec2 min = Vec2::Zero();
  Vec2 max = Vec2::Zero();
};

struct Floor {
  std::string id;
  double elevation_m = 0.0;
  std::vector<Wall> walls;
  std::vector<Door> doors;
  std::vector<Furniture> furniture;
};

/// Where a team goes in: a point just inside the exterior door `door` of floor `floor`, and the
/// direction (rad, from +x counter-clockwise) of walking in.
struct Entry {
  std::string id;
  std::string floor;
  std::string door;
  Vec2 position = Vec2::Zero();
  double heading_rad = 0.0;
};

/// A straight flight: a rectangle `width_m` wide from the centre of its bottom edge (on
/// `lower_floor`) to the centre of its top edge (on `upper_floor`). Its side walls are walls of
/// both floors; the height changes linearly along it.
struct Stairs {
  std::string id;
  std::string lower_floor;
  std::string upper_floor;
  Vec2 bottom = Vec2::Zero();
  Vec2 top = Vec2::Zero();
  double width_m = 1.2;

  /// 0 at the bottom edge, 1 at the top edge, nullopt outside the rectangle.
  std::optional<double> progress(const Vec2& p) const;
};

/// Which walls: the navigation map (doors cut, entry doors closed, no furniture) or the
/// simulated world (the same plus furniture).
enum class WallSet { kNavigation, kWorld };

class FloorPlan {
 public:
  std::string name;
  std::vector<Floor> floors;
  std::vector<Entry> entries;
  std::vector<Stairs> stairs;

  /// Throws ConfigError naming the element and the rule ("floors[0].walls[w3]: zero length"):
  /// NaN/Inf or absurd coordinates, zero-length walls, duplicate ids, a door not on its wall
  /// or wider than it, an entry on an unknown floor or door, stairs between unknown floors.
  void validate() const;

  std::size_t floor_index(const std::string& id) const;  ///< throws ConfigError when unknown
  /// The solid pieces of floor `floor`'s walls (doors and openings cut out).
  std::vector<Segment> solid_walls(std::size_t floor, WallSet set) const;
  /// Stairs touching floor `floor`.
  std::vector<const Stairs*> stairs_of(std::size_t floor) const;
  /// Bounding box of every wall of every floor.
  void bounds(Vec2& min, Vec2& max) const;
};

/// Moves door `door` of floor `floor` by `shift_m` along its wall, as far as the wall allows (a
/// map error: the plan says the door is elsewhere). Returns the shift applied. Throws
/// ConfigError naming the door when the floor has no such door.
double move_door(FloorPlan& plan, std::size_t floor, const std::string& door, double shift_m);

}  // namespace sarloc::firefighter
