#include "sarloc/core/avalanche/probe_pattern.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <tuple>

#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"

namespace sarloc::avalanche {
namespace {

using Vec2 = Eigen::Vector2d;

/// Distance from the origin to the segment [a, b].
double distance_to_segment(const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp(-a.dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab).norm();
}

/// Does the convex polygon `v` (counter-clockwise) meet the disc of radius k at the origin?
bool polygon_meets_disc(const std::array<Vec2, 6>& v, double k) {
  bool origin_inside = true;
  for (std::size_t m = 0; m < v.size(); ++m) {
    const Vec2& a = v[m];
    const Vec2& b = v[(m + 1) % v.size()];
    if (distance_to_segment(a, b) <= k) return true;
    const Vec2 e = b - a;
    if (e.x() * (-a.y()) - e.y() * (-a.x()) < 0.0) origin_inside = false;
  }
  return origin_inside;
}

}  // namespace

std::vector<Vec2> probe_pattern(const Mat3& position_covariance, double cover_radius_m) {
  if (!position_covariance.allFinite() || !(cover_radius_m > 0.0) || !std::isfinite(cover_radius_m)) {
    std::ostringstream os;
    os << "probe_pattern: cover_radius_m = " << cover_radius_m << ": must be finite and > 0, with a finite covariance";
    throw InputError(os.str());
  }
  std::vector<Vec2> out{Vec2::Zero()};
  const double semi_major = radius95_2d(position_covariance);
  if (semi_major <= cover_radius_m) return out;  // the disc around the estimate covers E

  // Whitening: E = {x : |L^-1 x| <= k}, C = L L^T. A 1 mm^2 floor keeps L invertible for a
  // degenerate (line-like) ellipse; it only enlarges E, so coverage is kept.
  Eigen::Matrix2d c = position_covariance.topLeftCorner<2, 2>();
  c = 0.5 * (c + c.transpose()) + 1e-6 * Eigen::Matrix2d::Identity();
  const Eigen::Matrix2d l = Eigen::LLT<Eigen::Matrix2d>(c).matrixL();
  const Eigen::Matrix2d l_inv = l.inverse();  // lower triangular, positive diagonal: det > 0
  const double k = std::sqrt(kChi2_2_95);

  // Hexagonal lattice a1 = (s, 0), a2 = (s/2, s sqrt(3)/2), s = sqrt(3) cover: its Voronoi cells
  // are hexagons with vertices at cover (cos(30 + 60 m deg), sin(...)) around each point.
  const double s = std::sqrt(3.0) * cover_radius_m;
  const Vec2 a1(s, 0.0), a2(0.5 * s, 0.5 * std::sqrt(3.0) * s);
  std::array<Vec2, 6> cell;
  for (int m = 0; m < 6; ++m) {
    const double ang = (30.0 + 60.0 * m) * kPi / 180.0;
    cell[static_cast<std::size_t>(m)] = l_inv * (cover_radius_m * Vec2(std::cos(ang), std::sin(ang)));
  }
  // A kept cell meets E, which lies within semi_major of the centre; its centre lies within
  // semi_major + cover_radius_m.
  const double reach = semi_major + cover_radius_m;
  const int n = static_cast<int>(std::ceil(2.0 * reach / s)) + 2;
  std::vector<std::tuple<int, double, Vec2>> kept;  // ring, angle, offset
  for (int i = -n; i <= n; ++i) {
    for (int j = -n; j <= n; ++j) {
      if (i == 0 && j == 0) continue;
      const Vec2 p = i * a1 + j * a2;
      if (p.norm() > reach) continue;
      const Vec2 q = l_inv * p;
      std::array<Vec2, 6> v;
      for (std::size_t m = 0; m < v.size(); ++m) v[m] = q + cell[m];
      if (!polygon_meets_disc(v, k)) continue;
      const int ring = std::max({std::abs(i), std::abs(j), std::abs(i + j)});
      kept.emplace_back(ring, std::atan2(p.y(), p.x()), p);
    }
  }
  std::sort(kept.begin(), kept.end(), [](const auto& x, const auto& y) {
    return std::tie(std::get<0>(x), std::get<1>(x)) < std::tie(std::get<0>(y), std::get<1>(y));
  });
  for (const auto& entry : kept) out.push_back(std::get<2>(entry));
  return out;
}

}  // namespace sarloc::avalanche
