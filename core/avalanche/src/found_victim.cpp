#include "sarloc/core/avalanche/found_victim.hpp"

#include <algorithm>
#include <functional>

#include "sarloc/core/common/gaussian.hpp"

namespace sarloc::avalanche {

double found_reach(const Mat3& covariance) { return radius95_3d(covariance) + kFalseFoundMarginM; }

std::optional<std::size_t> victim_of_found(const Vec3& found, double reach, const std::vector<Vec3>& victims,
                                           std::optional<std::size_t> own) {
  if (own && *own < victims.size() && (victims[*own] - found).norm() <= reach) return own;
  std::optional<std::size_t> nearest;
  double best = reach;
  for (std::size_t v = 0; v < victims.size(); ++v) {
    const double d = (victims[v] - found).norm();
    if (d <= best) {
      best = d;
      nearest = v;
    }
  }
  return nearest;
}

FoundMatching match_founds(const std::vector<FoundClaim>& founds, const std::vector<Vec3>& victims) {
  // Candidates per FOUND, the preferred one first.
  std::vector<std::vector<std::size_t>> candidates(founds.size());
  for (std::size_t f = 0; f < founds.size(); ++f) {
    const FoundClaim& c = founds[f];
    if (const auto named = victim_of_found(c.position, found_reach(c.covariance), victims, c.own))
      candidates[f].push_back(*named);
    const double stated = radius95_3d(c.covariance);
    for (std::size_t v = 0; v < victims.size(); ++v)
      if ((victims[v] - c.position).norm() <= stated &&
          std::find(candidates[f].begin(), candidates[f].end(), v) == candidates[f].end())
        candidates[f].push_back(v);
  }
  // Kuhn's augmenting paths: a handful of FOUNDs and victims.
  std::vector<std::optional<std::size_t>> holder(victims.size());  // victim -> FOUND
  std::function<bool(std::size_t, std::vector<char>&)> augment = [&](std::size_t f, std::vector<char>& seen) {
    for (std::size_t v : candidates[f]) {
      if (seen[v]) continue;
      seen[v] = 1;
      if (!holder[v] || augment(*holder[v], seen)) {
        holder[v] = f;
        return true;
      }
    }
    return false;
  };
  for (std::size_t f = 0; f < founds.size(); ++f) {
    std::vector<char> seen(victims.size(), 0);
    augment(f, seen);
  }
  FoundMatching m;
  m.victim.assign(founds.size(), std::nullopt);
  for (std::size_t v = 0; v < victims.size(); ++v)
    if (holder[v]) {
      m.victim[*holder[v]] = v;
      ++m.found;
    }
  for (std::size_t f = 0; f < founds.size(); ++f) {
    if (candidates[f].empty()) ++m.ghosts;
    else if (!m.victim[f]) ++m.duplicates;
  }
  return m;
}

}  // namespace sarloc::avalanche
