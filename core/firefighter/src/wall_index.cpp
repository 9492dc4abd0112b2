#include "sarloc/core/firefighter/wall_index.hpp"

#include <boost/geometry.hpp>
#include <boost/geometry/index/rtree.hpp>
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

struct WallIndex::Tree {
  bgi::rtree<Value, bgi::quadratic<16>> rtree;
};

WallIndex::WallIndex(std::vector<Segment> walls) : walls_(std::move(walls)), tree_(std::make_unique<Tree>()) {
  std::vector<Value> values;
  values.reserve(walls_.size());
  for (std::size_t i = 0; i < walls_.size(); ++i) values.emplace_back(to_segment(walls_[i].a, walls_[i].b), i);
  tree_->rtree = bgi::rtree<Value, bgi::quadratic<16>>(values.begin(), values.end());
}

WallIndex::~WallIndex() = default;
WallIndex::WallIndex(WallIndex&&) noexcept = default;
WallIndex& WallIndex::operator=(WallIndex&&) noexcept = default;

bool WallIndex::crosses(const Vec2& a, const Vec2& b) const {
  const BSegment move = to_segment(a, b);
  BBox box;
  bg::envelope(move, box);
  for (auto it = tree_->rtree.qbegin(bgi::intersects(box)); it != tree_->rtree.qend(); ++it) {
    if (bg::intersects(move, it->first)) return true;
  }
  return false;
}

std::vector<std::size_t> WallIndex::touching(const Vec2& a, const Vec2& b) const {
  const BSegment query = to_segment(a, b);
  BBox box;
  bg::envelope(query, box);
  std::vector<std::size_t> out;
  for (auto it = tree_->rtree.qbegin(bgi::intersects(box)); it != tree_->rtree.qend(); ++it) {
    if (bg::intersects(query, it->first)) out.push_back(it->second);
  }
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
