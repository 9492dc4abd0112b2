#include "sarloc/core/firefighter/point_index.hpp"

#include <nanoflann.hpp>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::firefighter {

// The dataset adaptor nanoflann asks for; it lives on the heap with the tree that refers to it.
struct PointIndex::Impl {
  std::vector<Vec2> points;
  std::size_t kdtree_get_point_count() const { return points.size(); }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const { return points[i][static_cast<int>(dim)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Impl>, Impl, 2, std::uint32_t>;
  std::unique_ptr<Tree> tree;
};

PointIndex::PointIndex(std::vector<Vec2> points) : impl_(std::make_unique<Impl>()) {
  impl_->points = std::move(points);
  impl_->tree = std::make_unique<Impl::Tree>(2, *impl_, nanoflann::KDTreeSingleIndexAdaptorParams(8));
}

PointIndex::~PointIndex() = default;
PointIndex::PointIndex(PointIndex&&) noexcept = default;
PointIndex& PointIndex::operator=(PointIndex&&) noexcept = default;

std::uint32_t PointIndex::nearest(const Vec2& query, double& distance_sq) const {
  if (impl_->points.empty()) throw InputError("PointIndex::nearest: no points");
  std::uint32_t index = 0;
  const double q[2] = {query.x(), query.y()};
  impl_->tree->knnSearch(q, 1, &index, &distance_sq);
  return index;
}

void PointIndex::within(const Vec2& query, double radius, std::vector<std::uint32_t>& out) const {
  if (impl_->points.empty()) return;
  const double q[2] = {query.x(), query.y()};
  std::vector<std::pair<std::uint32_t, double>> found;
  impl_->tree->radiusSearch(q, radius * radius, found, nanoflann::SearchParams(32, 0.0F, false));  // squared (L2_Simple)
  for (const auto& f : found) out.push_back(f.first);
}

const std::vector<Vec2>& PointIndex::points() const { return impl_->points; }

}  // namespace sarloc::firefighter
