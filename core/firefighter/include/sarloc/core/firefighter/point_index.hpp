#pragma once
// A k-d tree over 2-D points (Debian's nanoflann): the nearest-neighbour queries of the ICP and
// of the particles' pseudo-observation lookup.
#include <cstdint>
#include <memory>
#include <vector>

#include "sarloc/core/firefighter/floor_plan.hpp"

namespace sarloc::firefighter {

class PointIndex {
 public:
  explicit PointIndex(std::vector<Vec2> points);
  ~PointIndex();
  PointIndex(PointIndex&&) noexcept;
  PointIndex& operator=(PointIndex&&) noexcept;

  /// Index of the nearest point and its squared distance. The index must not be empty.
  std::uint32_t nearest(const Vec2& query, double& distance_sq) const;
  /// Appends the indices of the points within `radius` of `query` to `out`.
  void within(const Vec2& query, double radius, std::vector<std::uint32_t>& out) const;
  const std::vector<Vec2>& points() const;
  std::size_t size() const { return points().size(); }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sarloc::firefighter
