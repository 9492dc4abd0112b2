#include "sarloc/core/firefighter/search_pattern.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <numeric>
#include <string>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"
#include "sarloc/core/firefighter/wall_index.hpp"

namespace sarloc::firefighter {
namespace {

// Grid directions, counter-clockwise: east, north, west, south.
constexpr int kDx[4] = {1, 0, -1, 0};
constexpr int kDy[4] = {0, 1, 0, -1};

int direction_of(double heading) {
  const double q = std::round(heading / (0.5 * kPi));
  return static_cast<int>(((static_cast<long>(q) % 4) + 4) % 4);
}

class FloorGrid {
 public:
  FloorGrid(const FloorPlan& plan, std::size_t floor, const PatternGridConfig& config)
      : walls_(plan.solid_walls(floor, WallSet::kNavigation)), spacing_(config.spacing_m) {
    plan.bounds(origin_, max_);
    origin_ += Vec2::Constant(0.5 * spacing_);
    nx_ = static_cast<int>(std::floor((max_.x() - origin_.x()) / spacing_)) + 1;
    ny_ = static_cast<int>(std::floor((max_.y() - origin_.y()) / spacing_)) + 1;
    valid_.assign(static_cast<std::size_t>(nx_ * ny_), 0);
    for (int j = 0; j < ny_; ++j) {
      for (int i = 0; i < nx_; ++i) {
        valid_[index(i, j)] = walls_.clearance(position(i, j)) >= config.min_clearance_m ? 1 : 0;
      }
    }
  }

  Vec2 position(int i, int j) const { return origin_ + spacing_ * Vec2(i, j); }
  std::size_t index(int i, int j) const { return static_cast<std::size_t>(j * nx_ + i); }
  bool inside(int i, int j) const { return i >= 0 && j >= 0 && i < nx_ && j < ny_; }

  bool edge(int i, int j, int d) const {
    const int i2 = i + kDx[d], j2 = j + kDy[d];
    if (!inside(i2, j2) || !valid_[index(i2, j2)] || !valid_[index(i, j)]) return false;
    return !walls_.crosses(position(i, j), position(i2, j2));
  }

  // The valid node nearest p (within 3 spacings) from which p is visible.
  bool nearest(const Vec2& p, int& i, int& j) const {
    double best = 1e300;
    const int ci = static_cast<int>(std::round((p.x() - origin_.x()) / spacing_));
    const int cj = static_cast<int>(std::round((p.y() - origin_.y()) / spacing_));
    for (int dj = -3; dj <= 3; ++dj) {
      for (int di = -3; di <= 3; ++di) {
        const int a = ci + di, b = cj + dj;
        if (!inside(a, b) || !valid_[index(a, b)]) continue;
        const double d = (position(a, b) - p).norm();
        if (d < best && !walls_.crosses(p, position(a, b))) {
          best = d;
          i = a;
          j = b;
        }
      }
    }
    return best < 1e299;
  }

  void mark_reachable(int i0, int j0) {
    if (reachable_.empty()) reachable_.assign(valid_.size(), 0);
    std::deque<std::pair<int, int>> queue{{i0, j0}};
    reachable_[index(i0, j0)] = 1;
    while (!queue.empty()) {
      const auto [i, j] = queue.front();
      queue.pop_front();
      for (int d = 0; d < 4; ++d) {
        const int a = i + kDx[d], b = j + kDy[d];
        if (edge(i, j, d) && !reachable_[index(a, b)]) {
          reachable_[index(a, b)] = 1;
          queue.emplace_back(a, b);
        }
      }
    }
  }

  bool reachable(int i, int j) const { return !reachable_.empty() && reachable_[index(i, j)]; }

  std::vector<Vec2> reachable_nodes() const {
    std::vector<Vec2> out;
    for (int j = 0; j < ny_; ++j) {
      for (int i = 0; i < nx_; ++i) {
        if (reachable(i, j)) out.push_back(position(i, j));
      }
    }
    return out;
  }

  // Right-hand rule from (i, j) heading d: right, straight, left, back; until the first move
  // out of the first node repeats.
  std::vector<std::pair<int, int>> right_hand(int i, int j, int d) const {
    std::vector<std::pair<int, int>> out{{i, j}};
    const int i0 = i, j0 = j;
    int first_move = -1;
    const std::size_t cap = 4 * valid_.size() + 16;
    for (std::size_t step = 0; step < cap; ++step) {
      int move = -1;
      for (int turn : {3, 0, 1, 2}) {
        const int candidate = (d + turn) % 4;
        if (edge(i, j, candidate)) {
          move = candidate;
          break;
        }
      }
      if (move < 0) break;  // an isolated node
      if (i == i0 && j == j0) {
        if (first_move < 0) {
          first_move = move;
        } else if (move == first_move) {
          break;
        }
      }
      i += kDx[move];
      j += kDy[move];
      d = move;
      out.emplace_back(i, j);
    }
    if (out.size() > 1 && out.back() == out.front()) out.pop_back();  // p_N is adjacent to p_1
    return out;
  }

  // A heading at (i, j) with a wall on the right (the right-hand edge blocked by a wall).
  int heading_with_wall_on_right(int i, int j) const {
    for (int d = 0; d < 4; ++d) {
      const int right = (d + 3) % 4;
      if (edge(i, j, d) && !edge(i, j, right)) return d;
    }
    return 0;
  }

  const WallIndex& walls() const { return walls_; }

 private:
  WallIndex walls_;
  double spacing_;
  Vec2 origin_, max_;
  int nx_ = 0, ny_ = 0;
  std::vector<char> valid_;
  std::vector<char> reachable_;
};

// Where each floor's searches start: its entries, and the top of stairs arriving on it.
std::vector<std::pair<Vec2, double>> starts_of(const FloorPlan& plan, std::size_t floor) {
  std::vector<std::pair<Vec2, double>> out;
  for (const Entry& e : plan.entries) {
    if (plan.floor_index(e.floor) == floor) out.emplace_back(e.position, e.heading_rad);
  }
  for (const Stairs& s : plan.stairs) {
    const Vec2 u = (s.top - s.bottom).normalized();
    if (plan.floor_index(s.upper_floor) == floor) out.emplace_back(s.top + 0.5 * u, std::atan2(u.y(), u.x()));
    if (plan.floor_index(s.lower_floor) == floor) out.emplace_back(s.bottom - 0.5 * u, std::atan2(-u.y(), -u.x()));
  }
  return out;
}

// Groups of walls that touch one another (union-find over segment intersections).
std::vector<std::vector<std::size_t>> wall_groups(const std::vector<Segment>& walls) {
  std::vector<std::size_t> parent(walls.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](std::size_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  const WallIndex index(walls);
  for (std::size_t a = 0; a < walls.size(); ++a) {
    // Extend a hair so that walls meeting end to end count as touching.
    const Vec2 u = (walls[a].b - walls[a].a).normalized() * 1e-3;
    for (std::size_t b : index.touching(walls[a].a - u, walls[a].b + u)) parent[find(a)] = find(b);
  }
  std::map<std::size_t, std::vector<std::size_t>> groups;
  for (std::size_t a = 0; a < walls.size(); ++a) groups[find(a)].push_back(a);
  std::vector<std::vector<std::size_t>> out;
  for (auto& [root, members] : groups) out.push_back(std::move(members));
  return out;
}

// p lies beside the segment (its projection falls on it) within `distance`.
bool beside(const Vec2& p, const Segment& s, double distance) {
  const Vec2 d = s.b - s.a;
  const double t = (p - s.a).dot(d) / d.squaredNorm();
  return t > 0.0 && t < 1.0 && (s.a + t * d - p).norm() < distance;
}

// True when `b` walks the same closed loop as `a` from another start: a second entry on the
// same loop, whose windows would all be the first one's again.
bool same_loop(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  if (a.size() != b.size() || a.empty()) return false;
  const std::size_t n = a.size();
  for (std::size_t shift = 0; shift < n; ++shift) {
    if (a[shift] != b[0]) continue;
    std::size_t k = 1;
    while (k < n && a[(shift + k) % n] == b[k]) ++k;
    if (k == n) return true;
  }
  return false;
}

// The outermost excursions of a closed walk: it leaves cell `from` and comes back to it
// `min_nodes` or more nodes later (within half the loop: a room entered and left by one door).
// Passing such a room by, the walk goes from `from` straight on to where it left the room.
std::vector<RoomSkip> room_skips(const std::vector<std::pair<int, int>>& cells, std::size_t min_nodes) {
  const std::size_t n = cells.size();
  std::vector<RoomSkip> found;
  for (std::size_t i = 0; i < n; ++i) {
    // The latest return to cell i within half the loop: the whole room.
    for (std::size_t j = std::min(n - 1, i + n / 2); j >= i + min_nodes; --j) {
      if (cells[j] != cells[i]) continue;
      if (j + 1 < n) found.push_back({i, j + 1});
      break;
    }
  }
  // Keep the outermost: an excursion inside another is part of the same room.
  std::sort(found.begin(), found.end(), [](const RoomSkip& x, const RoomSkip& y) {
    return x.to - x.from > y.to - y.from || (x.to - x.from == y.to - y.from && x.from < y.from);
  });
  std::vector<RoomSkip> kept;
  for (const RoomSkip& s : found) {
    const bool inside = std::any_of(kept.begin(), kept.end(), [&](const RoomSkip& k) { return k.from <= s.from && s.to <= k.to; });
    if (!inside) kept.push_back(s);
  }
  std::sort(kept.begin(), kept.end(), [](const RoomSkip& x, const RoomSkip& y) { return x.from < y.from; });
  return kept;
}

}  // namespace

void PatternGridConfig::validate() const {
  if (!std::isfinite(spacing_m) || spacing_m < 0.25 || spacing_m > 5.0) {
    throw ConfigError("pattern.grid_spacing_m = " + config_value(spacing_m) + ": must be within [0.25, 5]");
  }
  if (!std::isfinite(min_clearance_m) || min_clearance_m < 0.0 || min_clearance_m >= 0.5 * spacing_m) {
    throw ConfigError("pattern.min_clearance_m = " + config_value(min_clearance_m) +
                      ": must be within [0, grid_spacing_m / 2)");
  }
  if (room_skip_min_nodes < 2 || room_skip_min_nodes > 1000) {
    throw ConfigError("pattern.room_skip_min_nodes = " + config_value(room_skip_min_nodes) + ": must be within [2, 1000]");
  }
}

double NavigableGrid::area_m2(std::size_t floor) const {
  return static_cast<double>(nodes_per_floor.at(floor).size()) * spacing_m * spacing_m;
}

NavigableGrid navigable_grid(const FloorPlan& plan, const PatternGridConfig& config) {
  config.validate();
  NavigableGrid out;
  out.spacing_m = config.spacing_m;
  for (std::size_t f = 0; f < plan.floors.size(); ++f) {
    FloorGrid grid(plan, f, config);
    for (const auto& [p, heading] : starts_of(plan, f)) {
      int i = 0, j = 0;
      if (grid.nearest(p, i, j)) grid.mark_reachable(i, j);
    }
    out.nodes_per_floor.push_back(grid.reachable_nodes());
  }
  return out;
}

std::vector<NodeSequence> extract_node_sequences(const FloorPlan& plan, const PatternGridConfig& config) {
  config.validate();
  std::vector<NodeSequence> out;
  for (std::size_t f = 0; f < plan.floors.size(); ++f) {
    FloorGrid grid(plan, f, config);
    const auto starts = starts_of(plan, f);
    for (const auto& [p, heading] : starts) {
      int i = 0, j = 0;
      if (grid.nearest(p, i, j)) grid.mark_reachable(i, j);
    }
    const std::size_t first_of_floor = out.size();
    auto emit = [&](const std::vector<std::pair<int, int>>& cells, bool inner) {
      NodeSequence seq;
      seq.floor = f;
      seq.around_inner_walls = inner;
      for (const auto& [a, b] : cells) seq.nodes.push_back(grid.position(a, b));
      if (config.room_skips) seq.room_skips = room_skips(cells, config.room_skip_min_nodes);
      if (seq.nodes.size() < 4) return;
      for (std::size_t m = first_of_floor; m < out.size(); ++m) {
        if (same_loop(out[m].nodes, seq.nodes)) return;
      }
      out.push_back(std::move(seq));
    };
    for (const auto& [p, heading] : starts) {
      int i = 0, j = 0;
      if (!grid.nearest(p, i, j)) continue;
      // Walking in, the first right turn follows the entry's wall (seed 004 section II).
      emit(grid.right_hand(i, j, direction_of(heading)), false);
    }
    // Inner walls: every wall group that no sequence of this floor passes next to.
    const auto& walls = grid.walls().walls();
    for (const auto& group : wall_groups(walls)) {
      // Covered when some sequence runs beside at least half of the group's length.
      double group_length = 0.0;
      for (std::size_t w : group) group_length += walls[w].length();
      auto near_group = [&](const Vec2& n) {
        for (std::size_t w : group) {
          if (beside(n, walls[w], 0.75 * config.spacing_m)) return true;
        }
        return false;
      };
      bool covered = false;
      for (std::size_t m = first_of_floor; m < out.size() && !covered; ++m) {
        const auto along = std::count_if(out[m].nodes.begin(), out[m].nodes.end(), near_group);
        covered = static_cast<double>(along) * config.spacing_m >= 0.5 * group_length;
      }
      if (covered) continue;
      // Start at the reachable node nearest the group's first wall, with the wall on the right.
      const Segment& w = walls[group.front()];
      const Vec2 mid = 0.5 * (w.a + w.b);
      const Vec2 normal = Vec2(-(w.b - w.a).y(), (w.b - w.a).x()).normalized();
      for (double side : {1.0, -1.0}) {
        int i = 0, j = 0;
        if (!grid.nearest(mid + side * 0.5 * config.spacing_m * normal, i, j) || !grid.reachable(i, j)) continue;
        emit(grid.right_hand(i, j, grid.heading_with_wall_on_right(i, j)), true);
        break;
      }
    }
  }
  return out;
}

}  // namespace sarloc::firefighter
