// Pattern comparison (seed 004 section IV-D, Algorithm 1): eq. (1), resampling, and ICP finding
// a walked stretch of a search pattern wherever it was rotated and moved to.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <random>
#include <tuple>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/firefighter/pattern_matcher.hpp"
#include "test_buildings.hpp"

namespace sarloc::firefighter {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(PatternMatcher, PrincipalRotationUndoesARotatedRectilinearWalk) {
  const std::vector<Vec2> walk = {{0, 0}, {4, 0}, {4, 3}, {1, 3}, {1, 5}};
  for (double angle : {0.0, 0.3, -0.6, 1.2}) {
    std::vector<Vec2> rotated;
    for (const Vec2& p : walk) rotated.push_back(Eigen::Rotation2Dd(angle) * p);
    const double phi = PatternMatcher::principal_rotation(rotated);
    // Any multiple of 90 deg is as good: compare modulo pi/2.
    const double residual = std::remainder(angle + phi, 0.5 * kPi);
    EXPECT_NEAR(residual, 0.0, 0.01) << "angle " << angle;
  }
}

TEST(PatternMatcher, ResampleKeepsTheEndsAndTheSpacing) {
  const auto r = PatternMatcher::resample({{0, 0}, {1.2, 0}, {1.2, 1.3}}, 0.5);
  EXPECT_EQ(r.front(), Vec2(0, 0));
  EXPECT_EQ(r.back(), Vec2(1.2, 1.3));
  for (std::size_t k = 1; k + 1 < r.size(); ++k) EXPECT_LE((r[k] - r[k - 1]).norm(), 0.5 + 1e-9);
  EXPECT_EQ(r.size(), 6U);  // 2.5 m: 0, 0.5, ..., 2.5
}

TEST(PatternMatcher, FindsAWalkedStretchOfThePatternWhereverItWasMoved) {
  const FloorPlan plan = test::building("house-125");
  const PatternGridConfig grid;
  const auto sequences = extract_node_sequences(plan, grid);
  const PatternMatcher matcher(sequences, grid, PatternMatchConfig{});
  const auto& nodes = sequences.front().nodes;
  std::mt19937_64 rng(4);
  std::normal_distribution<double> noise(0.0, 0.05);
  for (std::size_t start : {0UL, 17UL, 40UL, 71UL}) {
    // 20 m of the right-hand search, in an odometry frame rotated and moved, with noise.
    const Eigen::Rotation2Dd R(0.9);
    std::vector<Vec2> trajectory;
    for (std::size_t k = 0; k <= 20; ++k) {
      const Vec2 p = nodes[(start + k) % nodes.size()];
      trajectory.push_back(R * p + Vec2(30, -12) + Vec2(noise(rng), noise(rng)));
    }
    const auto obs = matcher.compare(trajectory);
    ASSERT_EQ(obs.size(), 2 * matcher.window_count());
    const auto best = std::min_element(obs.begin(), obs.end(),
                                       [](const auto& a, const auto& b) { return a.rmse < b.rmse; });
    const Vec2 now = nodes[(start + 20) % nodes.size()];
    EXPECT_LT(best->rmse, 0.15) << "start " << start;
    EXPECT_LT((best->position - now).norm(), 1e-9) << "start " << start;
    EXPECT_LT((best->fitted_position - now).norm(), 0.2) << "start " << start;
    EXPECT_NEAR(std::remainder(best->frame_heading + 0.9, 2 * kPi), 0.0, 0.05) << "the odometry frame's heading";
  }
}

// A crew that passed a room by walked the pattern without that room: with the room skips the
// comparison finds where it is now as well as for a crew that searched every room; without
// them, the best fit there is poor.
TEST(PatternMatcher, AWalkThatPassedARoomByStillFitsThePattern) {
  const FloorPlan plan = test::building("house-125");
  PatternGridConfig grid;
  const auto sequences = extract_node_sequences(plan, grid);
  const auto& nodes = sequences.front().nodes;
  ASSERT_FALSE(sequences.front().room_skips.empty());
  grid.room_skips = false;
  const PatternMatcher with(sequences, grid, PatternMatchConfig{});
  const PatternMatcher without(extract_node_sequences(plan, grid), grid, PatternMatchConfig{});
  ASSERT_GT(with.window_count(), without.window_count());
  std::mt19937_64 rng(6);
  std::normal_distribution<double> noise(0.0, 0.05);
  for (const RoomSkip& skip : sequences.front().room_skips) {
    // 10 m up to the room, 10 m on after it, in a rotated and moved odometry frame.
    const Eigen::Rotation2Dd R(-0.4);
    std::vector<Vec2> trajectory;
    for (std::size_t k = 0; k < 10; ++k) trajectory.push_back(nodes[(skip.from + nodes.size() - 9 + k) % nodes.size()]);
    for (std::size_t k = 0; k <= 10; ++k) trajectory.push_back(nodes[(skip.to + k) % nodes.size()]);
    const Vec2 now = trajectory.back();
    for (Vec2& p : trajectory) p = R * p + Vec2(-7, 3) + Vec2(noise(rng), noise(rng));
    auto best_at_now = [&](const PatternMatcher& m) {
      double best = 1e9;
      for (const auto& o : m.compare(trajectory)) {
        if ((o.position - now).norm() < 1e-9) best = std::min(best, o.rmse);
      }
      return best;
    };
    EXPECT_LT(best_at_now(with), 0.15) << "room left at node " << skip.from;
    EXPECT_GT(best_at_now(without), 0.4) << "room left at node " << skip.from;
  }
}

// mark_ends_near marks the nearest end of every point within the radius (brute force here).
TEST(PatternMatcher, MarksTheNearestEndOfEveryPointNearTheCentre) {
  const FloorPlan plan = test::building("office-253");
  const PatternGridConfig grid;
  const PatternMatcher matcher(extract_node_sequences(plan, grid), grid, PatternMatchConfig{});
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> x(-1.0, 12.5), y(-1.0, 12.0), offset(-0.35, 0.35);
  for (int trial = 0; trial < 200; ++trial) {
    const std::size_t floor = static_cast<std::size_t>(trial % 2);
    const auto& ends = matcher.ends(floor);
    ASSERT_FALSE(ends.empty());
    const Vec2 centre(x(rng), y(rng));
    EndMask mask = matcher.empty_end_mask();
    matcher.mark_ends_near(floor, centre, 0.5, mask);
    for (int k = 0; k < 20; ++k) {
      const Vec2 p = centre + Vec2(offset(rng), offset(rng));  // within 0.5 m
      std::size_t nearest = 0;
      for (std::size_t i = 1; i < ends.size(); ++i) {
        if ((ends[i] - p).squaredNorm() < (ends[nearest] - p).squaredNorm()) nearest = i;
      }
      ASSERT_TRUE(mask[floor][nearest]) << "centre " << centre.transpose() << ", point " << p.transpose();
    }
  }
}

// A comparison restricted to some ends gives exactly the full comparison's observations there
// (with pruning off: a pruned ICP stops at a value that depends on the best fit found so far).
TEST(PatternMatcher, ARestrictedComparisonGivesTheFullOnesObservationsAtTheWantedEnds) {
  const FloorPlan plan = test::building("house-125");
  const PatternGridConfig grid;
  const auto sequences = extract_node_sequences(plan, grid);
  PatternMatchConfig config;
  config.prune_margin_m = 100.0;
  const PatternMatcher matcher(sequences, grid, config);
  const auto& nodes = sequences.front().nodes;
  std::vector<Vec2> trajectory;
  for (std::size_t k = 0; k <= 20; ++k) trajectory.push_back(nodes[(30 + k) % nodes.size()]);
  EndMask wanted = matcher.empty_end_mask();
  matcher.mark_ends_near(0, nodes[50 % nodes.size()], 1.0, wanted);
  const std::size_t touching = matcher.windows_touching(wanted);
  ASSERT_GT(touching, 0U);
  ASSERT_LT(touching, matcher.window_count() / 2) << "the restriction leaves most windows out";

  auto key = [](const PseudoObservation& o) { return std::make_tuple(o.position.x(), o.position.y(), o.heading, o.rmse); };
  auto sorted = [&](std::vector<PseudoObservation> v) {
    std::sort(v.begin(), v.end(), [&](const auto& a, const auto& b) { return key(a) < key(b); });
    return v;
  };
  std::vector<PseudoObservation> expected;
  for (const auto& o : matcher.compare(trajectory)) {
    const auto& ends = matcher.ends(0);
    const auto at = std::find(ends.begin(), ends.end(), o.position);
    ASSERT_NE(at, ends.end()) << "every observation is at a window end";
    if (wanted[0][static_cast<std::size_t>(at - ends.begin())]) expected.push_back(o);
  }
  const auto restricted = sorted(matcher.compare(trajectory, &wanted));
  expected = sorted(expected);
  ASSERT_FALSE(expected.empty());
  ASSERT_EQ(restricted.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(key(restricted[i]), key(expected[i])) << i;
    EXPECT_EQ(restricted[i].fitted_position, expected[i].fitted_position) << i;
    EXPECT_EQ(restricted[i].frame_heading, expected[i].frame_heading) << i;
  }
  EXPECT_THROW(matcher.compare(trajectory, &(wanted = EndMask(3))), InputError) << "another matcher's mask";
  EXPECT_THROW(matcher.windows_touching(wanted), InputError);
  EXPECT_THROW(matcher.mark_ends_near(0, nodes.front(), 1.0, wanted), InputError);
}

}  // namespace
}  // namespace sarloc::firefighter
