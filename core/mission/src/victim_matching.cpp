#include "sarloc/core/mission/victim_matching.hpp"

#include <algorithm>

#include "sarloc/core/incident/assignment.hpp"

namespace sarloc::mission {

std::vector<int> match_to_truth(const std::vector<VictimSpec>& truth, const std::vector<incident::FusedVictim>& fused,
                                double radius_m) {
  if (fused.empty()) return std::vector<int>(truth.size(), -1);
  Eigen::MatrixXd cost(static_cast<Eigen::Index>(truth.size()), static_cast<Eigen::Index>(fused.size()));
  for (std::size_t i = 0; i < truth.size(); ++i) {
    for (std::size_t j = 0; j < fused.size(); ++j) {
      const double d = (fused[j].position.position - truth[i].position).norm();
      cost(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = d <= radius_m ? d : incident::kInfeasible;
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
