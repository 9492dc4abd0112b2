#include "sarloc/core/incident/assignment.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::incident {
namespace {

bool forbidden(double c) { return !(c < kInfeasible); }  // also true for +inf

// Rows <= cols. a is n x m with finite entries. Returns row -> column.
// Shortest augmenting path with potentials u (rows), v (columns); 1-based with a virtual
// column 0, as in the classical O(n^2 m) formulation.
std::vector<int> hungarian(const Eigen::MatrixXd& a) {
  const int n = static_cast<int>(a.rows());
  const int m = static_cast<int>(a.cols());
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0.0), v(m + 1, 0.0);
  std::vector<int> p(m + 1, 0), way(m + 1, 0);  // p[j]: row (1-based) matched to column j
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::vector<double> minv(m + 1, inf);
    std::vector<char> used(m + 1, 0);
    do {
      used[j0] = 1;
      const int i0 = p[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (used[j]) continue;
        const double cur = a(i0 - 1, j - 1) - u[i0] - v[j];
        if (cur < minv[j]) {
          minv[j] = cur;
          way[j] = j0;
        }
        if (minv[j] < delta) {
          delta = minv[j];
          j1 = j;
        }
      }
      for (int j = 0; j <= m; ++j) {
        if (used[j]) {
          u[p[j]] += delta;
          v[j] -= delta;
        } else {
          minv[j] -= delta;
        }
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  std::vector<int> row_to_col(n, -1);
  for (int j = 1; j <= m; ++j)
    if (p[j] != 0) row_to_col[p[j] - 1] = j - 1;
  return row_to_col;
}

}  // namespace

std::vector<int> solve_assignment(const Eigen::MatrixXd& cost) {
  const Eigen::Index n = cost.rows(), m = cost.cols();
  if (n == 0) return {};
  if (m == 0) return std::vector<int>(static_cast<std::size_t>(n), -1);
  double max_abs = 0.0;
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < m; ++j) {
      const double c = cost(i, j);
      if (std::isnan(c) || c == -std::numeric_limits<double>::infinity()) {
        std::ostringstream os;
        os << "assignment.cost(" << i << ", " << j << ") = " << c << ": must not be NaN or -inf";
        throw InputError(os.str());
      }
      if (!forbidden(c)) max_abs = std::max(max_abs, std::fabs(c));
    }
  // Big-M: one more feasible pair always beats any change of feasible total (<= 2 k max|c|).
  const double k = static_cast<double>(std::min(n, m));
  const double big = 2.0 * (k + 1.0) * (max_abs + 1.0);
  Eigen::MatrixXd a(n, m);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < m; ++j) a(i, j) = forbidden(cost(i, j)) ? big : cost(i, j);

  std::vector<int> result(static_cast<std::size_t>(n), -1);
  if (n <= m) {
    result = hungarian(a);
  } else {
    const std::vector<int> col_to_row = hungarian(a.transpose());
    for (std::size_t j = 0; j < col_to_row.size(); ++j)
      if (col_to_row[j] >= 0) result[static_cast<std::size_t>(col_to_row[j])] = static_cast<int>(j);
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    const int j = result[static_cast<std::size_t>(i)];
    if (j >= 0 && forbidden(cost(i, j))) result[static_cast<std::size_t>(i)] = -1;
  }
  return result;
}

}  // namespace sarloc::incident
