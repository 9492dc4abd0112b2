#include "sarloc/core/firefighter/pattern_matcher.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <tuple>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::firefighter {
namespace {


Eigen::Matrix2d rotation(double a) {
  return Eigen::Rotation2Dd(a).toRotationMatrix();
}

double heading_of(const Vec2& v) { return std::atan2(v.y(), v.x()); }

// Angular distance of `a` from the nearest multiple of 90 deg.
double off_principal(double a) {
  const double r = std::fmod(std::fmod(a, 0.5 * kPi) + 0.5 * kPi, 0.5 * kPi);
  return std::min(r, 0.5 * kPi - r);
}

}  // namespace

void PatternMatchConfig::validate() const {
  auto check = [](const char* key, double v, double lo, double hi) { check_range("pattern", key, v, lo, hi); };
  check("pattern_length_m", pattern_length_m, 4.0, 200.0);
  check("compare_every_m", compare_every_m, 0.5, 50.0);
  check("trajectory_spacing_m", trajectory_spacing_m, 0.1, 2.0);
  check("pattern_point_spacing_m", pattern_point_spacing_m, 0.05, 2.0);
  check("icp_iterations", icp_iterations, 1.0, 200.0);
  check("icp_tolerance_m", icp_tolerance_m, 1e-6, 1.0);
  check("prune_margin_m", prune_margin_m, 0.05, 100.0);
}

PatternMatcher::PatternMatcher(const std::vector<NodeSequence>& sequences, const PatternGridConfig& grid,
                               PatternMatchConfig config)
    : config_((config.validate(), config)) {
  // Distinct window ends per floor: the positions of the observations.
  std::size_t floors = 0;
  for (const NodeSequence& seq : sequences) floors = std::max(floors, seq.floor + 1);
  std::vector<std::vector<Vec2>> end_points(floors);
  std::vector<std::map<std::tuple<double, double>, std::uint32_t>> end_id(floors);
  auto end_of = [&](std::size_t floor, const Vec2& p) {
    const auto [it, added] = end_id[floor].try_emplace({p.x(), p.y()}, static_cast<std::uint32_t>(end_points[floor].size()));
    if (added) end_points[floor].push_back(p);
    return it->second;
  };
  const auto span = static_cast<std::size_t>(std::lround(config_.pattern_length_m / grid.spacing_m));
  // The window of span + 1 nodes starting at node(0) of a walk.
  auto add_window = [&](std::size_t floor, const std::function<Vec2(std::size_t)>& node) {
    std::vector<Vec2> points;
    for (std::size_t k = 0; k < span; ++k) {
      const Vec2 a = node(k), b = node(k + 1);
      const int pieces = std::max(1, static_cast<int>(std::lround((b - a).norm() / config_.pattern_point_spacing_m)));
      for (int s = 0; s < pieces; ++s) points.push_back(a + (b - a) * (static_cast<double>(s) / pieces));
    }
    points.push_back(node(span));
    Vec2 centroid = Vec2::Zero();
    for (const Vec2& p : points) centroid += p;
    centroid /= static_cast<double>(points.size());
    Window w{floor, end_of(floor, node(0)), end_of(floor, node(span)), node(0), node(span), centroid,
             heading_of(node(0) - node(1)), heading_of(node(span) - node(span - 1)), PointIndex(std::move(points))};
    windows_.push_back(std::move(w));
  };
  for (const NodeSequence& seq : sequences) {
    const std::size_t n = seq.nodes.size();
    if (n <= span) continue;  // a loop shorter than a pattern cannot hold d metres of walking
    for (std::size_t eta = 0; eta < n; ++eta) add_window(seq.floor, [&](std::size_t k) { return seq.nodes[(eta + k) % n]; });
    // A room passed by: the windows that span the step from `from` to `to` (the others are the
    // loop's own). The loop without the room must still hold two patterns.
    for (const RoomSkip& skip : seq.room_skips) {
      if (n - (skip.to - skip.from - 1) < 2 * span) continue;
      std::vector<Vec2> walk;  // span nodes up to `from`, then span nodes from `to`
      for (std::size_t k = 0; k < span; ++k) walk.push_back(seq.nodes[(skip.from + n - span + 1 + k) % n]);
      for (std::size_t k = 0; k < span; ++k) walk.push_back(seq.nodes[(skip.to + k) % n]);
      for (std::size_t eta = 0; eta < span; ++eta) add_window(seq.floor, [&](std::size_t k) { return walk[eta + k]; });
    }
  }
  for (auto& points : end_points) {
    ends_.push_back(points.empty() ? nullptr : std::make_unique<PointIndex>(std::move(points)));
  }
}

const std::vector<Vec2>& PatternMatcher::ends(std::size_t floor) const {
  static const std::vector<Vec2> none;
  return floor < ends_.size() && ends_[floor] ? ends_[floor]->points() : none;
}

EndMask PatternMatcher::empty_end_mask() const {
  EndMask mask(ends_.size());
  for (std::size_t f = 0; f < ends_.size(); ++f) mask[f].assign(ends(f).size(), 0);
  return mask;
}

void PatternMatcher::check_mask(const EndMask& mask) const {
  bool fits = mask.size() == ends_.size();
  for (std::size_t f = 0; fits && f < ends_.size(); ++f) fits = mask[f].size() == ends(f).size();
  if (!fits) throw InputError("pattern comparison: the end mask is not this matcher's (use empty_end_mask)");
}

void PatternMatcher::mark_ends_near(std::size_t floor, const Vec2& centre, double radius_m, EndMask& mask) const {
  check_mask(mask);
  if (floor >= ends_.size() || !ends_[floor]) return;
  // A point p within r of the centre has its nearest end within d + r of p (d: the centre's
  // nearest), so within d + 2r of the centre.
  double d2 = 0.0;
  ends_[floor]->nearest(centre, d2);
  std::vector<std::uint32_t> found;
  ends_[floor]->within(centre, std::sqrt(d2) + 2.0 * radius_m + 1e-9, found);
  for (std::uint32_t i : found) mask[floor][i] = 1;
}

std::size_t PatternMatcher::windows_touching(const EndMask& mask) const {
  check_mask(mask);
  std::size_t n = 0;
  for (const Window& w : windows_) n += (mask[w.floor][w.first_end] || mask[w.floor][w.last_end]) ? 1 : 0;
  return n;
}

std::vector<Vec2> PatternMatcher::resample(const std::vector<Vec2>& trajectory, double spacing) {
  std::vector<Vec2> out;
  if (trajectory.empty()) return out;
  out.push_back(trajectory.front());
  double carried = 0.0;  // distance walked since the last output point
  for (std::size_t k = 1; k < trajectory.size(); ++k) {
    const Vec2 a = trajectory[k - 1], b = trajectory[k];
    const double len = (b - a).norm();
    double at = spacing - carried;
    while (at <= len) {
      out.push_back(a + (b - a) * (at / len));
      at += spacing;
    }
    carried = len - (at - spacing);
  }
  if ((out.back() - trajectory.back()).norm() > 1e-9) out.push_back(trajectory.back());
  return out;
}

double PatternMatcher::principal_rotation(const std::vector<Vec2>& trajectory) {
  std::vector<double> angles;
  for (std::size_t k = 1; k < trajectory.size(); ++k) {
    const Vec2 d = trajectory[k] - trajectory[k - 1];
    if (d.norm() > 1e-6) angles.push_back(heading_of(d));
  }
  double best = 0.0, best_cost = 1e300;
  for (int step = -90; step < 90; ++step) {  // 0.5 deg
    const double phi = step * 0.5 * kPi / 180.0;
    double cost = 0.0;
    for (double a : angles) cost += off_principal(a + phi);
    if (cost < best_cost) {
      best_cost = cost;
      best = phi;
    }
  }
  return best;
}

PatternMatcher::Fit PatternMatcher::icp(const std::vector<Vec2>& source, const Window& window,
                                        double abandon_above) const {
  // Source centred at the origin; start with its centroid on the window's.
  Eigen::Matrix2d R = Eigen::Matrix2d::Identity();
  Vec2 t = window.centroid;
  const auto& target = window.points.points();
  std::vector<Vec2> matched(source.size());
  auto fit = [&](double rmse) { return Fit{rmse, R * source.back() + t, std::atan2(R(1, 0), R(0, 0))}; };
  double previous = 1e300;
  for (std::uint32_t it = 0; it < config_.icp_iterations; ++it) {
    double sum = 0.0;
    for (std::size_t k = 0; k < source.size(); ++k) {
      double d2 = 0.0;
      matched[k] = target[window.points.nearest(R * source[k] + t, d2)];
      sum += d2;
    }
    const double current = std::sqrt(sum / static_cast<double>(source.size()));
    if (it >= 3 && current > abandon_above) return fit(current);
    // Converged: `current` is already the fit of this R and t (no second pass of queries).
    if (std::abs(previous - current) < config_.icp_tolerance_m) return fit(current);
    previous = current;
    // Closed-form 2-D rigid fit of source -> matched (least squares).
    Vec2 cs = Vec2::Zero(), cm = Vec2::Zero();
    for (std::size_t k = 0; k < source.size(); ++k) {
      cs += source[k];
      cm += matched[k];
    }
    cs /= static_cast<double>(source.size());
    cm /= static_cast<double>(source.size());
    double dot = 0.0, cross = 0.0;
    for (std::size_t k = 0; k < source.size(); ++k) {
      const Vec2 a = source[k] - cs, b = matched[k] - cm;
      dot += a.dot(b);
      cross += a.x() * b.y() - a.y() * b.x();
    }
    R = rotation(std::atan2(cross, dot));
    t = cm - R * cs;
  }
  // Out of iterations: R and t moved after the last RMSE was taken.
  double sum = 0.0;
  for (const Vec2& s : source) {
    double d2 = 0.0;
    window.points.nearest(R * s + t, d2);
    sum += d2;
  }
  return fit(std::sqrt(sum / static_cast<double>(source.size())));
}

std::vector<PseudoObservation> PatternMatcher::compare(const std::vector<Vec2>& trajectory, const EndMask* wanted) const {
  std::vector<PseudoObservation> out;
  double length = 0.0;
  for (std::size_t k = 1; k < trajectory.size(); ++k) length += (trajectory[k] - trajectory[k - 1]).norm();
  if (length < 0.5 * config_.pattern_length_m || windows_.empty()) return out;
  if (wanted) check_mask(*wanted);
  std::vector<Vec2> source = resample(trajectory, config_.trajectory_spacing_m);
  // Algorithm 1, line 1: rotate by eq. (1), then centre.
  const Eigen::Matrix2d R0 = rotation(principal_rotation(source));
  auto principal_rotation_of = [](const Eigen::Matrix2d& R) { return std::atan2(R(1, 0), R(0, 0)); };
  Vec2 c = Vec2::Zero();
  for (Vec2& p : source) {
    p = R0 * p;
    c += p;
  }
  c /= static_cast<double>(source.size());
  for (Vec2& p : source) p -= c;
  std::vector<std::vector<Vec2>> rotated(4, source);
  for (int i = 1; i < 4; ++i) {
    const Eigen::Matrix2d Ri = rotation(i * 0.5 * kPi);
    for (Vec2& p : rotated[static_cast<std::size_t>(i)]) p = Ri * p;
  }
  out.reserve(2 * windows_.size());
  const double phi = principal_rotation_of(R0);
  double best = 1e300;
  for (const Window& w : windows_) {
    const bool first_wanted = !wanted || (*wanted)[w.floor][w.first_end];
    const bool last_wanted = !wanted || (*wanted)[w.floor][w.last_end];
    if (!first_wanted && !last_wanted) continue;
    PseudoObservation first{w.floor, w.first, w.heading_first}, last{w.floor, w.last, w.heading_last};
    for (int i = 0; i < 4; ++i) {
      const Fit fit = icp(rotated[static_cast<std::size_t>(i)], w, best + config_.prune_margin_m);
      best = std::min(best, fit.rmse);
      // Algorithm 1, lines 8-12: which end of the pattern is "now".
      PseudoObservation& o = (fit.last - w.first).norm() < (fit.last - w.last).norm() ? first : last;
      if (fit.rmse < o.rmse) {
        o.rmse = fit.rmse;
        o.fitted_position = fit.last;
        o.frame_heading = std::remainder(fit.angle + i * 0.5 * kPi + phi, 2.0 * kPi);
      }
    }
    if (first_wanted) out.push_back(first);
    if (last_wanted) out.push_back(last);
  }
  return out;
}

}  // namespace sarloc::firefighter
