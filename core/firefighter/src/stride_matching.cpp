#include "sarloc/core/firefighter/stride_matching.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sarloc/core/common/angle.hpp"

namespace sarloc::firefighter {
namespace {

// The scales of a stride's length and turn that one pairing may miss by (a footfall placed
// differently, the turn split over the next stride), and what a split or missed stance costs:
// a plain pairing is preferred unless the grouped one fits clearly better.
constexpr double kLengthSigmaM = 0.15;
constexpr double kTurnSigmaRad = 10.0 * kPi / 180.0;
constexpr double kGroupPenalty = 4.0;

double heading(const Eigen::Vector2d& v) { return std::atan2(v.y(), v.x()); }

}  // namespace

std::vector<StridePair> match_strides(const std::vector<Eigen::Vector2d>& track,
                                      const std::vector<Eigen::Vector2d>& truth) {
  const std::size_t n = track.size(), m = truth.size();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // cost[i][j]: the best alignment of the first i track and first j truth strides.
  std::vector<std::vector<double>> cost(n + 1, std::vector<double>(m + 1, kInf));
  std::vector<std::vector<std::pair<int, int>>> step(n + 1, std::vector<std::pair<int, int>>(m + 1, {0, 0}));
  cost[0][0] = 0.0;
  auto group_cost = [&](std::size_t i0, std::size_t i1, std::size_t j0, std::size_t j1) {
    Eigen::Vector2d a = Eigen::Vector2d::Zero(), b = Eigen::Vector2d::Zero();
    for (std::size_t i = i0; i < i1; ++i) a += track[i];
    for (std::size_t j = j0; j < j1; ++j) b += truth[j];
    double c = std::pow((a.norm() - b.norm()) / kLengthSigmaM, 2);
    if (i0 > 0 && j0 > 0) {
      const double turn_a = std::remainder(heading(a) - heading(track[i0 - 1]), 2.0 * kPi);
      const double turn_b = std::remainder(heading(b) - heading(truth[j0 - 1]), 2.0 * kPi);
      c += std::pow(std::remainder(turn_a - turn_b, 2.0 * kPi) / kTurnSigmaRad, 2);
    }
    return c + ((i1 - i0) + (j1 - j0) > 2 ? kGroupPenalty : 0.0);
  };
  for (std::size_t i = 0; i <= n; ++i)
    for (std::size_t j = 0; j <= m; ++j) {
      if (cost[i][j] == kInf) continue;
      for (const auto& [a, b] : {std::pair<int, int>{1, 1}, {2, 1}, {1, 2}}) {
        const std::size_t i1 = i + static_cast<std::size_t>(a), j1 = j + static_cast<std::size_t>(b);
        if (i1 > n || j1 > m) continue;
        const double c = cost[i][j] + group_cost(i, i1, j, j1);
        if (c < cost[i1][j1]) {
          cost[i1][j1] = c;
          step[i1][j1] = {a, b};
        }
      }
    }
  // Either sequence may run on past the other's end: each stride left over costs as much as a
  // grouping does.
  std::size_t best_i = 0, best_j = 0;
  double best = kInf;
  auto consider = [&](std::size_t i, std::size_t j) {
    const double c = cost[i][j] + kGroupPenalty * static_cast<double>((n - i) + (m - j));
    if (c < best) {
      best = c;
      best_i = i;
      best_j = j;
    }
  };
  for (std::size_t j = 0; j <= m; ++j) consider(n, j);
  for (std::size_t i = 0; i <= n; ++i) consider(i, m);
  std::vector<StridePair> pairs;
  for (std::size_t i = best_i, j = best_j; i > 0 && j > 0;) {
    const auto [a, b] = step[i][j];
    pairs.push_back({i - static_cast<std::size_t>(a), i, j - static_cast<std::size_t>(b), j});
    i -= static_cast<std::size_t>(a);
    j -= static_cast<std::size_t>(b);
  }
  std::reverse(pairs.begin(), pairs.end());
  return pairs;
}

}  // namespace sarloc::firefighter
