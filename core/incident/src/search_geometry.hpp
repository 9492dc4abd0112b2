#pragma once
// Boost.Geometry types for the search plan's polygons (deposit, strips), and the conversions
// from and to Eigen. Private to core/incident.
// Boost.Geometry's intersection warns of its own rescale factor as maybe uninitialised (GCC 12,
// -O3); the warning is about the library's code, at its lines.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/geometry.hpp>
#include <boost/geometry/geometries/point_xy.hpp>
#include <boost/geometry/geometries/polygon.hpp>
#pragma GCC diagnostic pop
#include <Eigen/Core>
#include <vector>

namespace sarloc::incident::geometry {

using Point = boost::geometry::model::d2::point_xy<double>;
using Polygon = boost::geometry::model::polygon<Point, false>;  // counter-clockwise, closed
using MultiPolygon = boost::geometry::model::multi_polygon<Polygon>;
using Line = boost::geometry::model::linestring<Point>;
using MultiLine = boost::geometry::model::multi_linestring<Line>;

inline Point to_point(const Eigen::Vector2d& v) { return Point(v.x(), v.y()); }
inline Eigen::Vector2d to_vec(const Point& p) { return Eigen::Vector2d(p.x(), p.y()); }

/// Any orientation in, counter-clockwise and closed out.
inline Polygon to_polygon(const std::vector<Eigen::Vector2d>& vertices) {
  Polygon p;
  for (const auto& v : vertices) p.outer().push_back(to_point(v));
  boost::geometry::correct(p);
  return p;
}

/// The outer ring without its closing vertex.
inline std::vector<Eigen::Vector2d> to_vertices(const Polygon& p) {
  std::vector<Eigen::Vector2d> out;
  for (const Point& q : p.outer()) out.push_back(to_vec(q));
  if (out.size() > 1 && out.front() == out.back()) out.pop_back();
  return out;
}

}  // namespace sarloc::incident::geometry
