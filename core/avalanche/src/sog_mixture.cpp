// The SOG filter's mixture reduction and output: normalisation and pruning, merging, moments,
// the victim estimate.
#include "sarloc/core/avalanche/sog_filter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "sog_filter_detail.hpp"

namespace sarloc::avalanche {
using namespace sog_detail;  // the shared private helpers (sog_filter_detail.hpp)


void SogFilter::normalise_and_prune() {
  if (components_.empty()) return;
  double mx = -std::numeric_limits<double>::infinity();
  for (const auto& c : components_) mx = std::max(mx, c.log_weight);
  double sum = 0.0;
  for (const auto& c : components_) sum += std::exp(c.log_weight - mx);
  const double lse = mx + std::log(sum);
  const double cut = mx - lse - config_.prune_log_weight;
  std::size_t out = 0;
  for (auto& c : components_) {
    c.log_weight -= lse;
    if (c.log_weight >= cut) components_[out++] = c;
  }
  components_.resize(out);
  // A mixture pruned from its opening ~1700 components to tens would otherwise keep the
  // opening's 1.4 MB for the rest of the search, per signal and rescuer (issue 64: 3-6 MB a
  // rescuer in the daemon); give it back once it holds four times what it needs.
  if (components_.capacity() > 4 * components_.size() + 64) components_.shrink_to_fit();
  // Renormalise after pruning.
  sum = 0.0;
  for (const auto& c : components_) sum += std::exp(c.log_weight);
  const double ls = std::log(sum);
  for (auto& c : components_) c.log_weight -= ls;
}

std::size_t SogFilter::merge() {
  if (components_.size() < 2) return 0;
  // Spatial hash on the position mean: only components sharing a cell are compared. The cells
  // are found by sorting (key, index) pairs: O(n log n), no per-bucket allocation.
  const double inv_cell = 1.0 / config_.merge_cell_m;
  std::vector<std::pair<std::int64_t, std::uint32_t>> keyed(components_.size());
  for (std::uint32_t i = 0; i < components_.size(); ++i) {
    const Vec3 p = components_[i].x.segment<3>(idx::kPos) * inv_cell;
    const auto ix = static_cast<std::int64_t>(std::floor(p.x())) & 0x1FFFFF;
    const auto iy = static_cast<std::int64_t>(std::floor(p.y())) & 0x1FFFFF;
    const auto iz = static_cast<std::int64_t>(std::floor(p.z())) & 0x1FFFFF;
    keyed[i] = {(ix << 42) | (iy << 21) | iz, i};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<char> gone(components_.size(), 0);
  std::size_t merged = 0;
  std::vector<std::uint32_t> members;
  for (std::size_t begin = 0; begin < keyed.size();) {
    std::size_t end = begin + 1;
    while (end < keyed.size() && keyed[end].first == keyed[begin].first) ++end;
    if (end - begin < 2) {
      begin = end;
      continue;
    }
    members.clear();
    for (std::size_t k = begin; k < end; ++k) members.push_back(keyed[k].second);
    begin = end;
    std::sort(members.begin(), members.end(), [&](std::uint32_t a, std::uint32_t b) {
      return components_[a].log_weight > components_[b].log_weight;
    });
    for (std::size_t ii = 0; ii < members.size(); ++ii) {
      const std::uint32_t i = members[ii];
      if (gone[i]) continue;
      SogComponent& ci = components_[i];
      Eigen::LLT<StateCov> llt(ci.P);
      if (llt.info() != Eigen::Success) continue;
      std::vector<std::uint32_t> group;
      for (std::size_t jj = ii + 1; jj < members.size(); ++jj) {
        const std::uint32_t j = members[jj];
        if (gone[j]) continue;
        StateVec diff = components_[j].x - ci.x;
        for (int k = 0; k < 3; ++k) diff[idx::kAtt + k] = wrap_angle(diff[idx::kAtt + k]);
        if (diff.dot(llt.solve(diff)) < config_.merge_mahalanobis) group.push_back(j);
      }
      if (group.empty()) continue;
      // Moment-matched merge (eq. (18) restricted to the group), angles relative to i.
      group.push_back(i);
      const double base = ci.log_weight;
      const GaussianMoments<idx::kStateDim> merged_moments =
          moments_of(components_, group, ci.x, base);
      ci.x = merged_moments.mean;
      ci.x[idx::kAtt + 2] = wrap_angle(ci.x[idx::kAtt + 2]);  // a component's yaw is wrapped
      ci.P = 0.5 * (merged_moments.covariance + merged_moments.covariance.transpose());
      // Cov(x, E) of the merged Gaussian: E's mean is 0 in every member, so only the weighted
      // cross-covariances add.
      CalibrationCross cross = CalibrationCross::Zero();
      for (const std::uint32_t g : group)
        cross += std::exp(components_[g].log_weight - base) * components_[g].calibration_cross;
      ci.calibration_cross = cross / merged_moments.weight_sum;
      ci.log_weight = base + std::log(merged_moments.weight_sum);
      // The members' weights already carry their surface factor: restart the bookkeeping from
      // the merged Gaussian so later steps apply only the change.
      ci.log_support = prior_log_support(ci);
      for (std::size_t g = 0; g + 1 < group.size(); ++g) gone[group[g]] = 1;
      merged += group.size() - 1;
    }
  }
  if (merged == 0) return 0;
  std::size_t out = 0;
  for (std::size_t i = 0; i < components_.size(); ++i)
    if (!gone[i]) components_[out++] = components_[i];
  components_.resize(out);
  return merged;
}

MixtureMoments SogFilter::moments() const {
  MixtureMoments mm;
  if (components_.empty()) return mm;
  std::size_t best = 0;
  for (std::size_t i = 1; i < components_.size(); ++i)
    if (components_[i].log_weight > components_[best].log_weight) best = i;
  // Weights are normalised (log-sum-exp = 0): log_base 0.
  const GaussianMoments<idx::kStateDim> g =
      moments_of(components_, AllIndices{components_.size()}, components_[best].x, 0.0);
  mm.mean = g.mean;
  mm.covariance = g.covariance;
  return mm;
}

VictimEstimate SogFilter::estimate(std::size_t top_k) const {
  VictimEstimate e = estimate_from(
      components_.empty() ? MixtureMoments{} : moments(), components_.size(), config_.converged_radius_m, top_k,
      [&](std::size_t i) { return components_[i].log_weight; },
      [&](std::size_t i) {
        return MixtureComponentSummary{std::exp(components_[i].log_weight), components_[i].x.segment<3>(idx::kPos),
                                       components_[i].P.block<3, 3>(idx::kPos, idx::kPos)};
      });
  e.rescuer_id = rescuer_id_;
  e.signal_id = signal_id_;
  e.stamp = last_stamp_;
  return e;
}

}  // namespace sarloc::avalanche
