#include "recorded_coverage.hpp"

#include "sarloc/core/incident/search_coverage.hpp"
#include "sarloc/core/incident/search_strips.hpp"

namespace sarloc::report {

std::optional<RecordedCoverage> recorded_coverage(const MissionRecord& r) {
  if (r.search_plan && !r.search_plan->plan.strips.empty()) {
    RecordedCoverage out;
    out.from_plan = true;
    for (const auto& s : r.search_plan->plan.strips) {
      out.strips.push_back({s.strip.index, s.strip.outline, s.strip.width_m, s.searched});
      out.rescuers.push_back(s.rescuer_id);
    }
    out.deposit_searched = r.search_plan->plan.searched;
    return out;
  }
  if (!r.deposit) return std::nullopt;
  const incident::Deposit& deposit = *r.deposit;
  // Entered from where the avalanche rescuers started (the planner's rule without a fall line).
  Eigen::Vector2d entry = Eigen::Vector2d::Zero();
  std::size_t starts = 0;
  for (const auto& [id, track] : r.responders) {
    if (track.firefighter || track.samples.empty() || !track.samples.front().position.position.allFinite()) continue;
    entry += track.samples.front().position.position.head<2>();
    ++starts;
  }
  const std::size_t rescuers = starts;
  if (starts == 0) {
    for (const auto& v : deposit.vertices()) entry += v;
    starts = deposit.vertices().size();
  }
  const incident::StripPlanConfig config;
  const auto strips = incident::plan_strips(deposit, config, entry / static_cast<double>(starts), rescuers);
  incident::SearchCoverage coverage(deposit, strips, 1.0);
  for (const auto& [id, track] : r.responders) {
    if (track.firefighter) continue;
    for (std::size_t k = 1; k < track.samples.size(); ++k) {
      const Vec3& a = track.samples[k - 1].position.position;
      const Vec3& b = track.samples[k].position.position;
      if (a.allFinite() && b.allFinite()) coverage.add_walk(a.head<2>(), b.head<2>(), 0.5 * config.strip_width_m);
    }
  }
  RecordedCoverage out;
  for (const auto& s : strips) out.strips.push_back({s.index, s.outline, s.width_m, coverage.searched(s.index)});
  out.deposit_searched = coverage.searched();
  return out;
}

}  // namespace sarloc::report
