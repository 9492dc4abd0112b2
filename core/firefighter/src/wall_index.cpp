#include "sarloc/core/firefighter/wall_index.hpp"

#include <boost/geometry.hpp>
#include <boost/geometry/index/rtree.hpp>
#include <boost/iterator/function_output_iterator.hpp>
#include <cmath>
#include <limits>

namespace sarloc::firefighter {
namespace {

namespace bg = boost::geometry;
namespace bgi = boost::geometry::index;
using BPoint = bg::model::point<double, 2, bg::cs::cartesian>;
using BSegment = bg::model::segment<BPoint>;
using BBox = bg::model::box<BPoint>;
using Value = std::pair<BSegment, std::size_t>;

BPoint to_point(const Vec2& v) { return BPoint(v.x(), v.y()); }
BSegment to_segment(const Vec2& a, const Vec2& b) { return BSegment(to_point(a), to_point(b)); }

}  // namespace

// Moves shorter than the clearance at their start cannot touch a wall. A grid of clearances,
// exact within kClearanceCapM of each cell and lowered by half the cell's diagonal so that it
// bounds every point of the cell, answers most particle moves without a tree query (the query was
// a third of the firefighter filter's time).
constexpr double kClearanceCellM = 0.25;
constexpr double kClearanceCapM = 2.0;

struct WallIndex::Tree {
  bgi::rtree<Value, bgi::rstar<4>> rtree;
  Vec2 grid_origin = Vec2::Zero();
  long grid_nx = 0, grid_ny = 0;
  std::vector<float> clearance_lower_bound;  ///< per cell, row-major; 0 where unknown

  double lower_bound_at(const Vec2& p) const {
    const double fx = (p.x() - grid_origin.x()) / kClearanceCellM, fy = (p.y() - grid_origin.y()) / kClearanceCellM;
    if (!(fx >= 0.0 && fy >= 0.0 && fx < static_cast<double>(grid_nx) && fy < static_cast<double>(grid_ny))) return 0.0;
    return clearance_lower_bound[static_cast<std::size_t>(static_cast<long>(fy) * grid_nx + static_cast<long>(fx))];
  }
};

WallIndex::WallIndex(std::vector<Segment> walls) : walls_(std::move(walls)), tree_(std::make_unique<Tree>()) {
  std::vector<Value> values;
  values.reserve(walls_.size());
  for (std::size_t i = 0; i < walls_.size(); ++i) values.emplace_back(to_segment(walls_[i].a, walls_[i].b), i);
  tree_->rtree = bgi::rtree<Value, bgi::rstar<4>>(values.begin(), values.end());
  if (walls_.empty()) return;
  Vec2 lo = walls_.front().a, hi = lo;
  for (const Segment& w : walls_) {
    lo = lo.cwiseMin(w.a).cwiseMin(w.b);
    hi = hi.cwiseMax(w.a).cwiseMax(w.b);
  }
  tree_->grid_origin = lo - Vec2::Constant(kClearanceCapM);
  const Vec2 extent = hi - lo + Vec2::Constant(2.0 * kClearanceCapM);
  tree_->grid_nx = static_cast<long>(std::ceil(extent.x() / kClearanceCellM));
  tree_->grid_ny = static_cast<long>(std::ceil(extent.y() / kClearanceCellM));
  constexpr long kMaxCells = 16L << 20;  // 1 km x 1 km at 0.25 m; larger plans query the tree
  if (tree_->grid_nx * tree_->grid_ny > kMaxCells) {
    tree_->grid_nx = tree_->grid_ny = 0;
    return;
  }
  const double half_diagonal = kClearanceCellM * std::sqrt(0.5);
  tree_->clearance_lower_bound.resize(static_cast<std::size_t>(tree_->grid_nx * tree_->grid_ny));
  for (long j = 0; j < tree_->grid_ny; ++j) {
    for (long i = 0; i < tree_->grid_nx; ++i) {
      const Vec2 centre = tree_->grid_origin + kClearanceCellM * Vec2(i + 0.5, j + 0.5);
      const BBox near(to_point(centre - Vec2::Constant(kClearanceCapM)), to_point(centre + Vec2::Constant(kClearanceCapM)));
      double nearest = kClearanceCapM;
      tree_->rtree.query(bgi::intersects(near), boost::make_function_output_iterator([&](const Value& v) {
                           nearest = std::min(nearest, static_cast<double>(bg::distance(to_point(centre), v.first)));
                         }));
      tree_->clearance_lower_bound[static_cast<std::size_t>(j * tree_->grid_nx + i)] =
          static_cast<float>(std::max(0.0, nearest - half_diagonal) * (1.0 - 1e-6));
    }
  }
}

WallIndex::~WallIndex() = default;
WallIndex::WallIndex(WallIndex&&) noexcept = default;
WallIndex& WallIndex::operator=(WallIndex&&) noexcept = default;

bool WallIndex::crosses(const Vec2& a, const Vec2& b) const {
  // The one-shot query by bounding box, with the exact test in its output: several times
  // cheaper than the incremental iterator (and than the segment as predicate, whose box test is
  // costly). Crossings are rare, so stopping at the first would gain little.
  if ((b - a).norm() < tree_->lower_bound_at(a)) return false;
  const BSegment move = to_segment(a, b);
  BBox box;
  bg::envelope(move, box);
  bool hit = false;
  tree_->rtree.query(bgi::intersects(box), boost::make_function_output_iterator([&](const Value& v) {
                       hit = hit || bg::intersects(move, v.first);
                     }));
  return hit;
}

std::vector<std::size_t> WallIndex::touching(const Vec2& a, const Vec2& b) const {
  const BSegment query = to_segment(a, b);
  BBox box;
  bg::envelope(query, box);
  std::vector<std::size_t> out;
  tree_->rtree.query(bgi::intersects(box), boost::make_function_output_iterator([&](const Value& v) {
                       if (bg::intersects(query, v.first)) out.push_back(v.second);
                     }));
  return out;
}

double WallIndex::ray(const Vec2& origin, double heading_rad, double max_range) const {
  const Vec2 d(std::cos(heading_rad), std::sin(heading_rad));
  const Vec2 end = origin + max_range * d;
  BBox box;
  bg::envelope(to_segment(origin, end), box);
  double best = max_range;
  for (auto it = tree_->rtree.qbegin(bgi::intersects(box)); it != tree_->rtree.qend(); ++it) {
    const Segment& w = walls_[it->second];
    // origin + s d = w.a + u (w.b - w.a): solve the 2x2 system by cross products.
    const Vec2 e = w.b - w.a;
    const double denom = d.x() * e.y() - d.y() * e.x();
    if (std::abs(denom) < 1e-12) continue;  // parallel: a grazing wall does not stop the ray
    const Vec2 q = w.a - origin;
    const double s = (q.x() * e.y() - q.y() * e.x()) / denom;
    const double u = (q.x() * d.y() - q.y() * d.x()) / denom;
    if (s >= 0.0 && u >= 0.0 && u <= 1.0) best = std::min(best, s);
  }
  return best;
}

double WallIndex::clearance(const Vec2& p) const {
  if (walls_.empty()) return std::numeric_limits<double>::infinity();
  double best = std::numeric_limits<double>::infinity();
  // The nearest few boxes hold the nearest segment (a box is never farther than its segment).
  for (auto it = tree_->rtree.qbegin(bgi::nearest(to_point(p), 4)); it != tree_->rtree.qend(); ++it) {
    best = std::min(best, bg::distance(to_point(p), it->first));
  }
  return best;
}

}  // namespace sarloc::firefighter
