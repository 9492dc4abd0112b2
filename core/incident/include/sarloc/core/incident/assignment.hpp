#pragma once
// Minimum-cost rectangular assignment (linear sum assignment).
//
// Shortest augmenting path with dual potentials (Hungarian method in the Jonker-Volgenant
// form: Kuhn 1955, Munkres 1957, Jonker & Volgenant 1987), O(n^2 m) for an n x m matrix with
// n <= m (the matrix is transposed internally when n > m).
//
// Forbidden pairs: any entry >= kInfeasible (including +inf) is never assigned. Forbidden
// entries are replaced by a big-M cost larger than any difference of feasible totals, so the
// result is: among the assignments with the MOST feasible pairs, one of minimum total cost.
// Rows left without a feasible column get -1. NaN or -inf entries throw InputError.
//
//   Eigen::MatrixXd cost(2, 3);  cost << 1, 5, kInfeasible,  2, kInfeasible, 1;
//   std::vector<int> col = solve_assignment(cost);   // {0, 2}
#include <Eigen/Core>
#include <vector>

namespace sarloc::incident {

/// Entries at or above this value (or +inf) are forbidden.
inline constexpr double kInfeasible = 1e15;

/// For each row, the assigned column or -1. Each column is used at most once.
std::vector<int> solve_assignment(const Eigen::MatrixXd& cost);

}  // namespace sarloc::incident
