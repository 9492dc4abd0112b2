#include "sarloc/core/incident/signal_pursuit.hpp"

#include <algorithm>
#include <cstdio>
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

namespace {

std::string signature_text(const responder::TransmitterSignature& t) {
  char text[96];
  std::snprintf(text, sizeof text, "carrier %+.1f Hz, period %.3f s", t.carrier_offset_hz, t.period_s);
  return text;
}

}  // namespace

std::vector<SignalHandOver> SignalPursuits::update(const std::vector<FusedVictim>& victims,
                                                   const std::map<std::string, Vec2>& searching, TimestampNs now,
                                                   const SignalGroups& groups) {
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
    std::vector<SignalKey> signals;  ///< its sources, and the signals not yet placed that joined it
    std::set<std::string> hearing;   ///< searching rescuers among them
  };
  std::vector<Eligible> eligible;
  for (const auto& v : victims) {
    if (is_found(v.state) || v.evidence_conflict || ambiguous.count(v.victim_id) != 0 ||
        given_up_.count(v.victim_id) != 0 || !v.position.position.allFinite()) {
      continue;
    }
    Eligible e{&v, {}, {}};
    for (const auto& s : v.sources) e.signals.emplace_back(s.rescuer_id, s.signal_id);
    const auto joined = groups.joined.find(v.victim_id);
    if (joined != groups.joined.end())
      for (const auto& s : joined->second) e.signals.emplace_back(s.rescuer_id, s.signal_id);
    for (const auto& [rescuer, signal] : e.signals)
      if (searching.count(rescuer) != 0) e.hearing.insert(rescuer);
    if (e.hearing.size() >= 2) eligible.push_back(std::move(e));
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
    // Its transmitter was pursued before anyone placed it: that pursuer keeps it.
    const auto carried = std::find_if(group_pursuits_.begin(), group_pursuits_.end(), [&](const GroupPursuit& g) {
      return e.hearing.count(g.pursuit.rescuer_id) != 0 &&
             std::any_of(e.signals.begin(), e.signals.end(),
                         [&](const SignalKey& k) { return g.signals.count(k) != 0; });
    });
    if (carried != group_pursuits_.end()) {
      kept.emplace(id, carried->pursuit);
      busy.insert(carried->pursuit.rescuer_id);
      events_.push_back({false, "victim " + std::to_string(id) + ": placed; still pursued by " +
                                    carried->pursuit.rescuer_id + ", who took its signal first"});
      continue;
    }
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
    for (const auto& [rescuer, signal] : e.signals)
      if (rescuer != it->second.rescuer_id && out.size() < kSignalHandOversMax)
        out.push_back({rescuer, signal, e.victim->victim_id, it->second.rescuer_id});
  }
  pursuits_ = std::move(kept);
  pursue_unplaced(groups, searching, busy, now, out);
  return out;
}

void SignalPursuits::pursue_unplaced(const SignalGroups& groups, const std::map<std::string, Vec2>& searching,
                                     std::set<std::string>& busy, TimestampNs now, std::vector<SignalHandOver>& out) {
  std::vector<GroupPursuit> kept;
  for (const auto& group : groups.unplaced) {
    GroupPursuit now_pursued;
    std::vector<const HeardSignal*> hearing;  // searching, in order of first heard
    for (const auto& s : group) {
      now_pursued.signals.emplace(s.rescuer_id, s.signal_id);
      if (searching.count(s.rescuer_id) != 0) hearing.push_back(&s);
    }
    const bool given_up = std::any_of(now_pursued.signals.begin(), now_pursued.signals.end(),
                                      [&](const SignalKey& k) { return given_up_signals_.count(k) != 0; });
    if (hearing.size() < 2 || given_up) continue;
    auto hears = [&](const std::string& rescuer) {
      return std::any_of(hearing.begin(), hearing.end(),
                         [&](const HeardSignal* s) { return s->rescuer_id == rescuer; });
    };
    const auto previous = std::find_if(group_pursuits_.begin(), group_pursuits_.end(), [&](const GroupPursuit& g) {
      return hears(g.pursuit.rescuer_id) && std::any_of(g.signals.begin(), g.signals.end(), [&](const SignalKey& k) {
               return now_pursued.signals.count(k) != 0;
             });
    });
    const std::string label = "signal " + group.front().rescuer_id + "/" + std::to_string(group.front().signal_id) +
                              " (" + signature_text(group.front().transmitter) + "; not yet placed)";
    if (previous != group_pursuits_.end()) {
      if (now - previous->pursuit.since > timeout_ns_) {
        given_up_signals_.insert(now_pursued.signals.begin(), now_pursued.signals.end());
        events_.push_back({true, label + " not placed by " + previous->pursuit.rescuer_id +
                                     " in time: every rescuer who hears it may pursue it again"});
        continue;
      }
      now_pursued.pursuit = previous->pursuit;
    } else {
      // The first to take it keeps it (the standard practice), unless he pursues another:
      // `group` is in order of first heard.
      const auto free = std::find_if(hearing.begin(), hearing.end(),
                                     [&](const HeardSignal* s) { return busy.count(s->rescuer_id) == 0; });
      now_pursued.pursuit = {(free != hearing.end() ? *free : hearing.front())->rescuer_id, now};
      events_.push_back({false, label + ": pursued by " + now_pursued.pursuit.rescuer_id + " (of " +
                                    std::to_string(hearing.size()) +
                                    " who hear it, the first to take it not pursuing another); the others' signals "
                                    "of it are handed over"});
    }
    busy.insert(now_pursued.pursuit.rescuer_id);
    for (const auto& s : group)
      if (s.rescuer_id != now_pursued.pursuit.rescuer_id && out.size() < kSignalHandOversMax)
        out.push_back({s.rescuer_id, s.signal_id, 0, now_pursued.pursuit.rescuer_id});
    kept.push_back(std::move(now_pursued));
  }
  group_pursuits_ = std::move(kept);
}

void SignalPursuits::adopt(const std::vector<SignalHandOver>& active, TimestampNs now) {
  std::map<std::uint32_t, Pursuit> adopted;
  std::map<std::string, GroupPursuit> groups;  // transmitters not yet placed, by pursuer
  for (const auto& h : active) {
    if (h.victim_id == 0) {
      auto& g = groups[h.pursued_by];
      g.pursuit.rescuer_id = h.pursued_by;
      g.signals.emplace(h.rescuer_id, h.signal_id);
      continue;
    }
    if (adopted.count(h.victim_id) != 0) continue;
    const auto own = pursuits_.find(h.victim_id);
    const bool same = own != pursuits_.end() && own->second.rescuer_id == h.pursued_by;
    adopted[h.victim_id] = {h.pursued_by, same ? own->second.since : now};
  }
  pursuits_ = std::move(adopted);
  std::vector<GroupPursuit> adopted_groups;
  for (auto& [pursuer, g] : groups) {
    const auto own = std::find_if(group_pursuits_.begin(), group_pursuits_.end(), [&](const GroupPursuit& o) {
      return o.pursuit.rescuer_id == pursuer &&
             std::any_of(o.signals.begin(), o.signals.end(),
                         [&](const SignalKey& k) { return g.signals.count(k) != 0; });
    });
    g.pursuit.since = own != group_pursuits_.end() ? own->pursuit.since : now;
    adopted_groups.push_back(std::move(g));
  }
  group_pursuits_ = std::move(adopted_groups);
}

std::optional<std::string> SignalPursuits::pursuer_of_signal(const SignalKey& signal) const {
  for (const auto& g : group_pursuits_)
    if (g.signals.count(signal) != 0) return g.pursuit.rescuer_id;
  return std::nullopt;
}

std::optional<std::string> SignalPursuits::pursuer_of(std::uint32_t victim_id) const {
  const auto it = pursuits_.find(victim_id);
  if (it == pursuits_.end()) return std::nullopt;
  return it->second.rescuer_id;
}

}  // namespace sarloc::incident
