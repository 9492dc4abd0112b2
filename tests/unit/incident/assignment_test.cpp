#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <set>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/incident/assignment.hpp"

namespace sarloc::incident {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Score {
  int pairs = 0;
  double cost = 0.0;
};

Score score(const Eigen::MatrixXd& c, const std::vector<int>& a) {
  Score s;
  std::set<int> used;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i] < 0) continue;
    EXPECT_TRUE(used.insert(a[i]).second) << "column used twice";
    EXPECT_LT(c(static_cast<Eigen::Index>(i), a[i]), kInfeasible) << "forbidden pair assigned";
    ++s.pairs;
    s.cost += c(static_cast<Eigen::Index>(i), a[i]);
  }
  return s;
}

// Every partial injective assignment: most feasible pairs, then least cost.
void brute(const Eigen::MatrixXd& c, std::size_t row, std::vector<int>& cur, std::vector<bool>& used,
           Score& best) {
  if (row == static_cast<std::size_t>(c.rows())) {
    Score s;
    for (std::size_t i = 0; i < cur.size(); ++i)
      if (cur[i] >= 0) {
        ++s.pairs;
        s.cost += c(static_cast<Eigen::Index>(i), cur[i]);
      }
    if (s.pairs > best.pairs || (s.pairs == best.pairs && s.cost < best.cost)) best = s;
    return;
  }
  cur[row] = -1;
  brute(c, row + 1, cur, used, best);
  for (int j = 0; j < c.cols(); ++j) {
    if (used[static_cast<std::size_t>(j)] || !(c(static_cast<Eigen::Index>(row), j) < kInfeasible)) continue;
    used[static_cast<std::size_t>(j)] = true;
    cur[row] = j;
    brute(c, row + 1, cur, used, best);
    used[static_cast<std::size_t>(j)] = false;
  }
  cur[row] = -1;
}

TEST(Assignment, SquareClassic) {
  Eigen::MatrixXd c(3, 3);
  c << 4, 1, 3,  //
      2, 0, 5,   //
      3, 2, 2;
  const std::vector<int> a = solve_assignment(c);
  EXPECT_EQ(a, (std::vector<int>{1, 0, 2}));
  EXPECT_DOUBLE_EQ(score(c, a).cost, 5.0);
}

TEST(Assignment, RectangularBothWays) {
  Eigen::MatrixXd wide(2, 4);
  wide << 9, 2, 7, 8,  //
      6, 4, 3, 7;
  EXPECT_EQ(solve_assignment(wide), (std::vector<int>{1, 2}));
  const std::vector<int> tall = solve_assignment(wide.transpose());
  EXPECT_EQ(tall, (std::vector<int>{-1, 0, 1, -1}));
}

TEST(Assignment, ForbiddenPairsNeverAssigned) {
  Eigen::MatrixXd c(3, 2);
  c << 1, kInf,  //
      kInfeasible, kInf,  //
      0.5, 2;
  const std::vector<int> a = solve_assignment(c);
  EXPECT_EQ(a[1], -1);
  EXPECT_EQ(a[0], 0);
  EXPECT_EQ(a[2], 1);  // more feasible pairs beats the cheaper 0.5
}

TEST(Assignment, EmptyAndAllForbidden) {
  EXPECT_TRUE(solve_assignment(Eigen::MatrixXd(0, 3)).empty());
  EXPECT_EQ(solve_assignment(Eigen::MatrixXd(2, 0)), (std::vector<int>{-1, -1}));
  EXPECT_EQ(solve_assignment(Eigen::MatrixXd::Constant(2, 2, kInf)), (std::vector<int>{-1, -1}));
}

TEST(Assignment, RejectsNan) {
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(2, 2);
  c(1, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(solve_assignment(c), InputError);
}

TEST(Assignment, MatchesBruteForceOnRandomMatrices) {
  std::mt19937 rng(1);
  std::uniform_int_distribution<int> dim(1, 5);
  std::uniform_real_distribution<double> val(-5.0, 20.0);
  std::bernoulli_distribution forbid(0.25);
  for (int trial = 0; trial < 400; ++trial) {
    const int n = dim(rng), m = dim(rng);
    Eigen::MatrixXd c(n, m);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < m; ++j) c(i, j) = forbid(rng) ? kInf : val(rng);
    Score best{-1, 0.0};
    std::vector<int> cur(static_cast<std::size_t>(n), -1);
    std::vector<bool> used(static_cast<std::size_t>(m), false);
    brute(c, 0, cur, used, best);
    const Score got = score(c, solve_assignment(c));
    ASSERT_EQ(got.pairs, best.pairs) << "trial " << trial << "\n" << c;
    ASSERT_NEAR(got.cost, best.cost, 1e-9) << "trial " << trial << "\n" << c;
  }
}

}  // namespace
}  // namespace sarloc::incident
