#include "sarloc/core/incident/signal_pursuit.hpp"

#include <limits>

#include "sarloc/core/common/time_units.hpp"

namespace sarloc::incident {

std::set<std::uint32_t> signals_left_to_others(const std::vector<SignalHandOver>& handed_over,
                                               const std::string& rescuer_id) {
  std::set<std::uint32_t> out;
  for (const auto& h : handed_over)
    if (h.rescuer_id == rescuer_id) out.insert(h.signal_id);
  return out;
}

SignalPursuits::SignalPursuits(double pursuit_timeout_s) : timeout_ns_(seconds_to_ns(pursuit_timeout_s)) {}

std::vector<SignalHandOver> SignalPursuits::update(const std::vector<FusedVictim>& victims,
                                                   const std::map<std::string, Vec2>& searching, TimestampNs now) {
  events_.clear();
  // Victims incident command cannot tell apart: nobody is sent away from either.
  std::set<std::uint32_t> ambiguous;
  for (const auto& v : victims) {
    if (v.possibly_same_as == 0) continue;
    ambiguous.insert(v.victim_id);
    ambiguous.insert(v.possibly_same_as);
  }
  std::vector<SignalHandOver> out;
  std::map<std::uint32_t, Pursuit> kept;
  for (const auto& v : victims) {
    const auto id = std::to_string(v.victim_id);
    if (is_found(v.state) || v.evidence_conflict || ambiguous.count(v.victim_id) != 0 ||
        given_up_.count(v.victim_id) != 0 || !v.position.position.allFinite()) {
      continue;
    }
    std::set<std::string> hearing;
    for (const auto& s : v.sources)
      if (searching.count(s.rescuer_id) != 0) hearing.insert(s.rescuer_id);
    if (hearing.size() < 2) continue;
    const auto previous = pursuits_.find(v.victim_id);
    Pursuit p;
    if (previous != pursuits_.end() && hearing.count(previous->second.rescuer_id) != 0) {
      p = previous->second;
      if (now - p.since > timeout_ns_) {
        given_up_.insert(v.victim_id);
        events_.push_back({true, "victim " + id + " not found by " + p.rescuer_id +
                                     " in time: every rescuer who hears it may pursue it again"});
        continue;
      }
    } else {
      double nearest = std::numeric_limits<double>::infinity();
      for (const auto& r : hearing) {
        const double d = (searching.at(r) - v.position.position.head<2>()).norm();
        if (d < nearest) {
          nearest = d;
          p.rescuer_id = r;
        }
      }
      p.since = now;
      events_.push_back({false, "victim " + id + ": pursued by " + p.rescuer_id + " (nearest of " +
                                    std::to_string(hearing.size()) +
                                    " who hear it); the others' signals of it are handed over"});
    }
    for (const auto& s : v.sources)
      if (s.rescuer_id != p.rescuer_id && out.size() < kSignalHandOversMax)
        out.push_back({s.rescuer_id, s.signal_id, v.victim_id, p.rescuer_id});
    kept.emplace(v.victim_id, std::move(p));
  }
  pursuits_ = std::move(kept);
  return out;
}

std::optional<std::string> SignalPursuits::pursuer_of(std::uint32_t victim_id) const {
  const auto it = pursuits_.find(victim_id);
  if (it == pursuits_.end()) return std::nullopt;
  return it->second.rescuer_id;
}

}  // namespace sarloc::incident
