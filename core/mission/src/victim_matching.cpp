#include "sarloc/core/mission/victim_matching.hpp"

#include <algorithm>
#include <limits>

#include "sarloc/core/incident/assignment.hpp"

namespace sarloc::mission {

std::vector<int> match_to_truth(const std::vector<VictimSpec>& truth, const std::vector<incident::FusedVictim>& fused,
                                double radius_m) {
  if (fused.empty()) return std::vector<int>(truth.size(), -1);
  Eigen::MatrixXd cost(static_cast<Eigen::Index>(truth.size()), static_cast<Eigen::Index>(fused.size()));
  for (std::size_t j = 0; j < fused.size(); ++j) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& t : truth) nearest = std::min(nearest, (fused[j].position.position - t.position).norm());
    for (std::size_t i = 0; i < truth.size(); ++i) {
      const double d = (fused[j].position.position - truth[i].position).norm();
      // Only its nearest buried victim: a second copy of one victim never stands in for
      // another one nearby (seen: a duplicate of A, 3 m from B, ended a mission as "B found").
      const bool feasible = d <= radius_m && d <= nearest;
      // Confirmed victims first: an unconfirmed twin that says it may be a confirmed one
      // (possibly_same_as) must not take the buried victim from it and leave it a "ghost".
      const double doubt = fused[j].state == incident::VictimState::kUnconfirmed ? 2.0 * radius_m : 0.0;
      cost(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = feasible ? d + doubt : incident::kInfeasible;
    }
  }
  return incident::solve_assignment(cost);
}

bool every_victim_found(const std::vector<VictimSpec>& truth, const std::vector<incident::FusedVictim>& fused) {
  const auto matched = match_to_truth(truth, fused);
  return std::all_of(matched.begin(), matched.end(), [&](int j) {
    return j >= 0 && incident::is_found(fused[static_cast<std::size_t>(j)].state);
  });
}

}  // namespace sarloc::mission
