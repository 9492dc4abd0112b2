#include "sarloc/core/incident/search_strips.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"
#include "sarloc/core/incident/assignment.hpp"
#include "search_geometry.hpp"

namespace sarloc::incident {
namespace bg = boost::geometry;

void StripPlanConfig::validate() const {
  require(std::isfinite(strip_width_m) && strip_width_m >= 5.0 && strip_width_m <= 100.0, "search.strip_width_m",
          strip_width_m, "must be in [5, 100]");
  if (fall_line_deg)
    require(std::isfinite(*fall_line_deg) && std::abs(*fall_line_deg) <= 360.0, "search.fall_line_deg", *fall_line_deg,
            "must be in [-360, 360]");
}

namespace {

Vec2 rotate(const Vec2& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return Vec2(c * v.x() - s * v.y(), s * v.x() + c * v.y());
}

// The vertices' extent along (u) and across (v) the direction `angle`.
struct Extent {
  double lo_u = 1e300, hi_u = -1e300, lo_v = 1e300, hi_v = -1e300;
};
Extent extent(const std::vector<Vec2>& vertices, double angle) {
  Extent e;
  for (const Vec2& p : vertices) {
    const Vec2 q = rotate(p, -angle);
    e.lo_u = std::min(e.lo_u, q.x());
    e.hi_u = std::max(e.hi_u, q.x());
    e.lo_v = std::min(e.lo_v, q.y());
    e.hi_v = std::max(e.hi_v, q.y());
  }
  return e;
}

// The direction of the long side of the minimum-area bounding rectangle: one of the convex
// hull's edge directions (rotating calipers, by trying each edge).
double long_axis(const std::vector<Vec2>& vertices) {
  geometry::Polygon hull;
  bg::convex_hull(geometry::to_polygon(vertices), hull);
  const auto h = geometry::to_vertices(hull);
  double best_area = std::numeric_limits<double>::infinity(), best = 0.0;
  for (std::size_t k = 0; k < h.size(); ++k) {
    const Vec2 e = h[(k + 1) % h.size()] - h[k];
    if (e.norm() == 0.0) continue;
    const double a = std::atan2(e.y(), e.x());
    const auto [lo_u, hi_u, lo_v, hi_v] = extent(h, a);
    const double area = (hi_u - lo_u) * (hi_v - lo_v);
    if (area < best_area) {
      best_area = area;
      best = hi_u - lo_u >= hi_v - lo_v ? a : a + kPi / 2.0;
    }
  }
  return best;
}

}  // namespace

std::vector<Strip> plan_strips(const Deposit& deposit, const StripPlanConfig& config, const Vec2& entry,
                               std::size_t at_least) {
  config.validate();
  const std::vector<Vec2>& vertices = deposit.vertices();
  // Downhill along +u after turning by -downhill; across is v.
  double downhill = config.fall_line_deg ? *config.fall_line_deg * kDeg : long_axis(vertices);
  if (!config.fall_line_deg) {
    // Enter from the end nearer the rescuers: downhill points away from them.
    Vec2 centre = Vec2::Zero();
    for (const Vec2& p : vertices) centre += p;
    centre /= static_cast<double>(vertices.size());
    const Vec2 axis(std::cos(downhill), std::sin(downhill));
    if ((entry - centre).dot(axis) > 0.0) downhill += kPi;
  }
  const auto [lo_u, hi_u, lo_v, hi_v] = extent(vertices, downhill);
  // 1 cm of slack: an outline that went through WGS-84 comes back micrometres wider, and an 80 m
  // deposit must still be two strips of 40 m, not three of 26.7 m.
  constexpr double kSlack_m = 0.01;
  auto count = static_cast<std::size_t>(std::max(1.0, std::ceil((hi_v - lo_v - kSlack_m) / config.strip_width_m)));
  // One strip per rescuer when there are more rescuers: all search at once, none idle.
  const auto narrowest =
      static_cast<std::size_t>(std::max(1.0, std::floor((hi_v - lo_v + kSlack_m) / kMinStripWidth_m)));
  count = std::max(count, std::min(at_least, narrowest));
  const double width = (hi_v - lo_v) / static_cast<double>(count);
  const geometry::Polygon area = geometry::to_polygon(vertices);
  std::vector<Strip> strips;
  // From the left looking downhill: v from high to low.
  for (std::size_t i = 0; i < count; ++i) {
    const double v1 = hi_v - width * static_cast<double>(i), v0 = v1 - width;
    const double u0 = lo_u - 1.0, u1 = hi_u + 1.0;
    std::vector<Vec2> band{rotate(Vec2(u0, v0), downhill), rotate(Vec2(u1, v0), downhill),
                           rotate(Vec2(u1, v1), downhill), rotate(Vec2(u0, v1), downhill)};
    geometry::MultiPolygon pieces;
    bg::intersection(area, geometry::to_polygon(band), pieces);
    for (const geometry::Polygon& piece : pieces) {
      const double piece_area = bg::area(piece);
      if (piece_area < 1.0) continue;  // a sliver where an edge grazes the band
      Strip s;
      s.index = strips.size();
      s.outline = geometry::to_vertices(piece);
      s.width_m = width;
      s.area_m2 = piece_area;
      // The centreline: the band's middle across the piece, or where the piece is if the middle
      // misses it; its top is its uphill end.
      geometry::Point centroid(0.0, 0.0);
      bg::centroid(piece, centroid);
      double v_mid = 0.5 * (v0 + v1);
      geometry::Line middle{geometry::to_point(rotate(Vec2(u0, v_mid), downhill)),
                            geometry::to_point(rotate(Vec2(u1, v_mid), downhill))};
      geometry::MultiLine inside;
      bg::intersection(middle, piece, inside);
      if (inside.empty()) {
        v_mid = rotate(geometry::to_vec(centroid), -downhill).y();
        middle = {geometry::to_point(rotate(Vec2(u0, v_mid), downhill)),
                  geometry::to_point(rotate(Vec2(u1, v_mid), downhill))};
        bg::intersection(middle, piece, inside);
      }
      double first = 1e300, last = -1e300;
      for (const auto& line : inside)
        for (const auto& p : line) {
          const double u = rotate(geometry::to_vec(p), -downhill).x();
          first = std::min(first, u);
          last = std::max(last, u);
        }
      if (first > last) first = last = rotate(geometry::to_vec(centroid), -downhill).x();
      s.top = rotate(Vec2(first, v_mid), downhill);
      s.bottom = rotate(Vec2(last, v_mid), downhill);
      strips.push_back(std::move(s));
    }
  }
  return strips;
}

std::vector<std::optional<std::size_t>> assign_strips(const std::vector<Strip>& strips,
                                                      const std::vector<Vec2>& rescuers,
                                                      const std::vector<bool>& open) {
  if (!open.empty() && open.size() != strips.size())
    throw InputError("assign_strips: " + std::to_string(open.size()) + " open flags for " +
                     std::to_string(strips.size()) + " strips");
  std::vector<std::optional<std::size_t>> out(rescuers.size());
  if (rescuers.empty() || strips.empty()) return out;
  Eigen::MatrixXd cost(rescuers.size(), strips.size());
  for (std::size_t r = 0; r < rescuers.size(); ++r) {
    if (!rescuers[r].allFinite())
      throw InputError("assign_strips: rescuer " + std::to_string(r) + ": position not finite");
    for (std::size_t s = 0; s < strips.size(); ++s)
      cost(r, s) = open.empty() || open[s] ? (rescuers[r] - strips[s].top).norm() : kInfeasible;
  }
  const std::vector<int> column = solve_assignment(cost);
  for (std::size_t r = 0; r < rescuers.size(); ++r)
    if (column[r] >= 0) out[r] = static_cast<std::size_t>(column[r]);
  return out;
}

}  // namespace sarloc::incident
