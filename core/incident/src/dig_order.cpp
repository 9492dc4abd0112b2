#include "sarloc/core/incident/dig_order.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::incident {

void TriageConfig::validate() const {
  const auto& c = survival_curve;
  if (c.size() < 2)
    throw ConfigError("triage.survival_curve: " + std::to_string(c.size()) + " points: needs at least 2");
  if (c.front().first != 0.0)
    throw ConfigError("triage.survival_curve[0] minutes = " + config_value(c.front().first) + ": must start at 0");
  for (std::size_t k = 0; k < c.size(); ++k) {
    const std::string at = "triage.survival_curve[" + std::to_string(k) + "]";
    require(std::isfinite(c[k].second) && c[k].second >= 0.0 && c[k].second <= 1.0, at + " probability", c[k].second,
            "must be in [0, 1]");
    if (k == 0) continue;
    require(std::isfinite(c[k].first) && c[k].first > c[k - 1].first, at + " minutes", c[k].first,
            "must be after the point before");
    require(c[k].second <= c[k - 1].second, at + " probability", c[k].second, "must not rise with time buried");
  }
  require(std::isfinite(dig_min_per_m) && dig_min_per_m >= 0.0 && dig_min_per_m <= 120.0, "triage.dig_min_per_m",
          dig_min_per_m, "must be in [0, 120]");
  require(std::isfinite(dig_min_per_m2) && dig_min_per_m2 >= 0.0 && dig_min_per_m2 <= 120.0, "triage.dig_min_per_m2",
          dig_min_per_m2, "must be in [0, 120]");
  require(std::isfinite(buried_before_start_min) && buried_before_start_min >= 0.0 && buried_before_start_min <= 600.0,
          "triage.buried_before_start_min", buried_before_start_min, "must be in [0, 600]");
}

double TriageConfig::survival(double minutes_buried) const {
  const auto& c = survival_curve;
  if (minutes_buried <= c.front().first) return c.front().second;
  for (std::size_t k = 1; k < c.size(); ++k)
    if (minutes_buried <= c[k].first) {
      const double f = (minutes_buried - c[k - 1].first) / (c[k].first - c[k - 1].first);
      return c[k - 1].second + f * (c[k].second - c[k - 1].second);
    }
  return c.back().second;
}

double TriageConfig::dig_minutes(double depth_m) const {
  return dig_min_per_m * depth_m + dig_min_per_m2 * depth_m * depth_m;
}

namespace {

// The victims in `order`, each to the team free first (the lowest index on a tie).
DigPlan schedule(const std::vector<DigCandidate>& victims, const std::vector<std::size_t>& order, std::size_t teams,
                 const TriageConfig& config) {
  DigPlan plan;
  std::vector<double> free_at(teams, 0.0);
  for (std::size_t i : order) {
    const auto team = static_cast<std::size_t>(std::min_element(free_at.begin(), free_at.end()) - free_at.begin());
    Dig d;
    d.victim_id = victims[i].victim_id;
    d.team = team;
    d.start_min = free_at[team];
    d.done_min = d.start_min + config.dig_minutes(victims[i].depth_m);
    d.survival = config.survival(victims[i].buried_min + d.done_min);
    free_at[team] = d.done_min;
    plan.expected_survivors += d.survival;
    plan.digs.push_back(d);
  }
  return plan;
}

double last_done(const DigPlan& p) {
  double last = 0.0;
  for (const Dig& d : p.digs) last = std::max(last, d.done_min);
  return last;
}

}  // namespace

DigPlan plan_digs(const std::vector<DigCandidate>& victims, std::size_t teams, const TriageConfig& config,
                  const std::vector<std::string>& first) {
  config.validate();
  if (teams == 0) throw InputError("dig plan: no digging team");
  std::set<std::string> ids;
  for (const DigCandidate& v : victims) {
    if (v.victim_id.empty() || !ids.insert(v.victim_id).second)
      throw InputError("dig plan: victim id '" + v.victim_id + "' empty or repeated");
    if (!std::isfinite(v.depth_m) || v.depth_m < 0.0)
      throw InputError("dig plan: victim " + v.victim_id + " depth_m = " + config_value(v.depth_m) + ": must be >= 0");
    if (!std::isfinite(v.buried_min) || v.buried_min < 0.0)
      throw InputError("dig plan: victim " + v.victim_id + " buried_min = " + config_value(v.buried_min) +
                       ": must be >= 0");
  }
  // The operator's victims first, as given; the rest is what is planned.
  std::vector<std::size_t> fixed, order;
  for (const std::string& id : first)
    for (std::size_t i = 0; i < victims.size(); ++i)
      if (victims[i].victim_id == id && std::find(fixed.begin(), fixed.end(), i) == fixed.end()) fixed.push_back(i);
  for (std::size_t i = 0; i < victims.size(); ++i)
    if (std::find(fixed.begin(), fixed.end(), i) == fixed.end()) order.push_back(i);
  auto with_fixed = [&](const std::vector<std::size_t>& rest) {
    std::vector<std::size_t> all = fixed;
    all.insert(all.end(), rest.begin(), rest.end());
    return schedule(victims, all, teams, config);
  };
  // Shortest dig first: the order beyond kExhaustiveVictims, and the first one tried below it.
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return victims[a].depth_m < victims[b].depth_m; });
  DigPlan best = with_fixed(order);
  if (order.size() > kExhaustiveVictims) return best;
  std::sort(order.begin(), order.end());
  do {
    DigPlan p = with_fixed(order);
    if (p.expected_survivors > best.expected_survivors + 1e-12 ||
        (std::abs(p.expected_survivors - best.expected_survivors) <= 1e-12 && last_done(p) < last_done(best) - 1e-12))
      best = std::move(p);
  } while (std::next_permutation(order.begin(), order.end()));
  return best;
}

}  // namespace sarloc::incident
