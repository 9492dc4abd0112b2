#pragma once
// Wall segments of one floor in a Boost.Geometry R-tree: does a move cross a wall, how far a
// ray travels before hitting one, how far the nearest wall is. Used by the particle filter
// (a particle that crosses a wall is removed, seed 004 section IV-E), the pattern grid and the
// simulated walker.
#include <memory>
#include <vector>

#include "sarloc/core/firefighter/floor_plan.hpp"

namespace sarloc::firefighter {

class WallIndex {
 public:
  explicit WallIndex(std::vector<Segment> walls);
  ~WallIndex();
  WallIndex(WallIndex&&) noexcept;
  WallIndex& operator=(WallIndex&&) noexcept;

  /// True when the segment a->b touches a wall.
  bool crosses(const Vec2& a, const Vec2& b) const;
  /// Indices (into walls()) of every wall the segment a->b touches.
  std::vector<std::size_t> touching(const Vec2& a, const Vec2& b) const;
  /// Distance from `origin` along the unit direction of `heading_rad` to the first wall, or
  /// `max_range` when none is closer.
  double ray(const Vec2& origin, double heading_rad, double max_range) const;
  /// Distance from p to the nearest wall (infinity without walls).
  double clearance(const Vec2& p) const;

  const std::vector<Segment>& walls() const { return walls_; }

 private:
  struct Tree;
  std::vector<Segment> walls_;
  std::unique_ptr<Tree> tree_;
};

}  // namespace sarloc::firefighter
