#include "sarloc/core/incident/search_coverage.hpp"

#include <algorithm>
#include <cmath>

#include "sarloc/core/common/errors.hpp"
#include "search_geometry.hpp"

namespace sarloc::incident {
namespace {

// A cell on the line between two strips lies exactly half a strip from both centrelines; the
// strips' rotated corners leave it a rounding error further.
constexpr double kRoundingM = 1e-6;

}  // namespace

SearchCoverage::SearchCoverage(const Deposit& deposit, const std::vector<Strip>& strips, double cell_m)
    : cell_m_(cell_m) {
  if (!(cell_m >= 0.5 && cell_m <= 5.0))
    throw InputError("coverage cell of " + std::to_string(cell_m) + " m: must be in [0.5, 5]");
  Vec2 lo = deposit.vertices().front(), hi = lo;
  for (const Vec2& p : deposit.vertices()) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  origin_ = lo;
  columns_ = static_cast<std::size_t>(std::ceil((hi.x() - lo.x()) / cell_m)) + 1;
  rows_ = static_cast<std::size_t>(std::ceil((hi.y() - lo.y()) / cell_m)) + 1;
  index_.assign(columns_ * rows_, -1);
  std::vector<geometry::Polygon> strip_polygons;
  for (const Strip& s : strips) strip_polygons.push_back(geometry::to_polygon(s.outline));
  strip_cells_.assign(strips.size(), 0);
  strip_searched_.assign(strips.size(), 0);
  for (std::size_t r = 0; r < rows_; ++r)
    for (std::size_t c = 0; c < columns_; ++c) {
      const Vec2 centre = origin_ + cell_m * Vec2(static_cast<double>(c) + 0.5, static_cast<double>(r) + 0.5);
      if (!deposit.contains(centre)) continue;
      index_[r * columns_ + c] = static_cast<std::int32_t>(centres_.size());
      centres_.push_back(centre);
      std::int32_t strip = -1;
      for (std::size_t s = 0; s < strip_polygons.size() && strip < 0; ++s)
        if (boost::geometry::covered_by(geometry::to_point(centre), strip_polygons[s]))
          strip = static_cast<std::int32_t>(s);
      strip_of_.push_back(strip);
      if (strip >= 0) ++strip_cells_[static_cast<std::size_t>(strip)];
    }
  searched_.assign(centres_.size(), 0);
}

void SearchCoverage::add_walk(const Vec2& a, const Vec2& b, double reach_m) {
  if (!a.allFinite() || !b.allFinite() || !std::isfinite(reach_m) || reach_m < 0.0)
    throw InputError("coverage walk: a point or the reach is not finite (or the reach is negative)");
  const Vec2 lo = a.cwiseMin(b).array() - reach_m, hi = a.cwiseMax(b).array() + reach_m;
  const auto clamp_index = [](double x, std::size_t n) {
    return static_cast<std::size_t>(std::clamp(std::floor(x), 0.0, static_cast<double>(n) - 1.0));
  };
  const std::size_t c0 = clamp_index((lo.x() - origin_.x()) / cell_m_, columns_),
                    c1 = clamp_index((hi.x() - origin_.x()) / cell_m_, columns_);
  const std::size_t r0 = clamp_index((lo.y() - origin_.y()) / cell_m_, rows_),
                    r1 = clamp_index((hi.y() - origin_.y()) / cell_m_, rows_);
  const Vec2 d = b - a;
  const double length2 = d.squaredNorm();
  for (std::size_t r = r0; r <= r1; ++r)
    for (std::size_t c = c0; c <= c1; ++c) {
      const std::int32_t k = index_[r * columns_ + c];
      if (k < 0 || searched_[static_cast<std::size_t>(k)]) continue;
      const Vec2& p = centres_[static_cast<std::size_t>(k)];
      const double t = length2 > 0.0 ? std::clamp((p - a).dot(d) / length2, 0.0, 1.0) : 0.0;
      if ((a + t * d - p).norm() > reach_m + kRoundingM) continue;
      searched_[static_cast<std::size_t>(k)] = 1;
      ++searched_count_;
      if (strip_of_[static_cast<std::size_t>(k)] >= 0)
        ++strip_searched_[static_cast<std::size_t>(strip_of_[static_cast<std::size_t>(k)])];
    }
}

void SearchCoverage::carry_over(const SearchCoverage& before) {
  for (std::size_t k = 0; k < centres_.size(); ++k) {
    if (searched_[k]) continue;
    const std::int32_t old = before.cell_at(centres_[k]);
    if (old < 0 || !before.searched_[static_cast<std::size_t>(old)]) continue;
    searched_[k] = 1;
    ++searched_count_;
    if (strip_of_[k] >= 0) ++strip_searched_[static_cast<std::size_t>(strip_of_[k])];
  }
}

std::int32_t SearchCoverage::cell_at(const Vec2& p) const {
  if (!p.allFinite()) return -1;
  const double c = std::floor((p.x() - origin_.x()) / cell_m_), r = std::floor((p.y() - origin_.y()) / cell_m_);
  if (c < 0.0 || r < 0.0 || c >= static_cast<double>(columns_) || r >= static_cast<double>(rows_)) return -1;
  return index_[static_cast<std::size_t>(r) * columns_ + static_cast<std::size_t>(c)];
}

bool SearchCoverage::searched_at(const Vec2& p) const {
  const std::int32_t k = cell_at(p);
  return k < 0 || searched_[static_cast<std::size_t>(k)] != 0;
}

bool SearchCoverage::searched_at(const Vec2& p, std::size_t strip) const {
  const std::int32_t k = cell_at(p);
  if (k < 0 || searched_[static_cast<std::size_t>(k)] != 0) return true;
  const std::int32_t owner = strip_of_[static_cast<std::size_t>(k)];
  return owner >= 0 && static_cast<std::size_t>(owner) != strip;  // a sliver in no strip: this one's
}

double SearchCoverage::searched() const {
  return centres_.empty() ? 1.0 : static_cast<double>(searched_count_) / static_cast<double>(centres_.size());
}

double SearchCoverage::searched(std::size_t strip) const {
  if (strip >= strip_cells_.size()) throw InputError("coverage: no strip " + std::to_string(strip));
  return strip_cells_[strip] == 0
             ? 1.0
             : static_cast<double>(strip_searched_[strip]) / static_cast<double>(strip_cells_[strip]);
}

}  // namespace sarloc::incident
