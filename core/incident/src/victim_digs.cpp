#include "sarloc/core/incident/victim_digs.hpp"

#include <algorithm>
#include <limits>
#include <set>

namespace sarloc::incident {

VictimDigs plan_victim_digs(const std::vector<FusedVictim>& victims, const std::map<std::string, Vec2>& free_rescuers,
                            double buried_min, const TriageConfig& triage, const std::vector<std::uint32_t>& first) {
  std::vector<DigCandidate> candidates;
  std::map<std::string, const FusedVictim*> by_name;
  for (const auto& v : victims) {
    if (v.state != VictimState::kFound) continue;
    const std::string name = std::to_string(v.victim_id);
    candidates.push_back({name, std::max(0.0, -v.position.position.z()), buried_min});
    by_name[name] = &v;
  }
  VictimDigs out;
  if (candidates.empty()) return out;
  const std::size_t teams = std::clamp<std::size_t>(free_rescuers.size(), 1, candidates.size());
  std::vector<std::string> first_names;
  for (const std::uint32_t id : first) first_names.push_back(std::to_string(id));
  const DigPlan plan = plan_digs(candidates, teams, triage, first_names);
  std::map<std::size_t, std::string> digger_of_team;
  std::set<std::string> taken;
  for (const Dig& d : plan.digs) {
    const FusedVictim& v = *by_name.at(d.victim_id);
    if (digger_of_team.count(d.team) == 0) {  // the team's first dig: the nearest free rescuer left
      std::string nearest;
      double best = std::numeric_limits<double>::infinity();
      for (const auto& [id, p] : free_rescuers) {
        const double distance = (p - v.position.position.head<2>()).norm();
        if (taken.count(id) == 0 && distance < best) {
          best = distance;
          nearest = id;
        }
      }
      if (!nearest.empty()) taken.insert(nearest);
      digger_of_team[d.team] = nearest;
    }
    if (out.digs.size() == kVictimDigsMax) continue;
    out.digs.push_back({v.victim_id, std::max(0.0, -v.position.position.z()), buried_min, d.start_min, d.done_min,
                        d.survival, digger_of_team[d.team]});
  }
  out.expected_survivors = plan.expected_survivors;
  return out;
}

}  // namespace sarloc::incident
