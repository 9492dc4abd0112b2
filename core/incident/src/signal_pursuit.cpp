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
  struct Eligible {
    const FusedVictim* victim;
    std::set<std::string> hearing;  ///< searching rescuers among its sources
  };
  std::vector<Eligible> eligible;
  for (const auto& v : victims) {
    if (is_found(v.state) || v.evidence_conflict || ambiguous.count(v.victim_id) != 0 ||
        given_up_.count(v.victim_id) != 0 || !v.position.position.allFinite()) {
      continue;
    }
    std::set<std::string> hearing;
    for (const auto& s : v.sources)
      if (searching.count(s.rescuer_id) != 0) hearing.insert(s.rescuer_id);
    if (hearing.size() >= 2) eligible.push_back({&v, std::move(hearing)});
  }
  // Pursuits under way first, so that a new victim goes to a rescuer who pursues nothing: with
  // several victims close together, one each, not all to whoever stands nearest the cluster.
  std::map<std::uint32_t, Pursuit> kept;
  std::set<std::string> busy;
  for (const auto& e : eligible) {
    const auto id = e.victim->victim_id;
    const auto previous = pursuits_.find(id);
    if (previous == pursuits_.end() || e.hearing.count(previous->second.rescuer_id) == 0) continue;
    if (now - previous->second.since > timeout_ns_) {
      given_up_.insert(id);
      events_.push_back({true, "victim " + std::to_string(id) + " not found by " + previous->second.rescuer_id +
                                   " in time: every rescuer who hears it may pursue it again"});
      continue;
    }
    kept.emplace(id, previous->second);
    busy.insert(previous->second.rescuer_id);
  }
  for (const auto& e : eligible) {
    const auto id = e.victim->victim_id;
    if (kept.count(id) != 0 || given_up_.count(id) != 0) continue;
    const Vec2 at = e.victim->position.position.head<2>();
    auto nearest_of = [&](bool only_free) {
      std::string best;
      double nearest = std::numeric_limits<double>::infinity();
      for (const auto& r : e.hearing) {
        if (only_free && busy.count(r) != 0) continue;
        const double d = (searching.at(r) - at).norm();
        if (d < nearest) {
          nearest = d;
          best = r;
        }
      }
      return best;
    };
    std::string pursuer = nearest_of(true);
    if (pursuer.empty()) pursuer = nearest_of(false);
    kept.emplace(id, Pursuit{pursuer, now});
    busy.insert(pursuer);
    events_.push_back({false, "victim " + std::to_string(id) + ": pursued by " + pursuer + " (of " +
                                  std::to_string(e.hearing.size()) +
                                  " who hear it, the nearest not pursuing another); the others' signals of it are "
                                  "handed over"});
  }
  std::vector<SignalHandOver> out;
  for (const auto& e : eligible) {
    const auto it = kept.find(e.victim->victim_id);
    if (it == kept.end()) continue;
    for (const auto& s : e.victim->sources)
      if (s.rescuer_id != it->second.rescuer_id && out.size() < kSignalHandOversMax)
        out.push_back({s.rescuer_id, s.signal_id, e.victim->victim_id, it->second.rescuer_id});
  }
  pursuits_ = std::move(kept);
  return out;
}

void SignalPursuits::adopt(const std::vector<SignalHandOver>& active, TimestampNs now) {
  std::map<std::uint32_t, Pursuit> adopted;
  for (const auto& h : active) {
    if (adopted.count(h.victim_id) != 0) continue;
    const auto own = pursuits_.find(h.victim_id);
    const bool same = own != pursuits_.end() && own->second.rescuer_id == h.pursued_by;
    adopted[h.victim_id] = {h.pursued_by, same ? own->second.since : now};
  }
  pursuits_ = std::move(adopted);
}

std::optional<std::string> SignalPursuits::pursuer_of(std::uint32_t victim_id) const {
  const auto it = pursuits_.find(victim_id);
  if (it == pursuits_.end()) return std::nullopt;
  return it->second.rescuer_id;
}

}  // namespace sarloc::incident
