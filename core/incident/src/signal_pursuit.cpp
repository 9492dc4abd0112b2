#include "sarloc/core/incident/signal_pursuit.hpp"

#include <algorithm>
#include <cmath>
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
  refresh_given_up(victims, groups, now);
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
    std::set<std::string> placing;   ///< searching rescuers with a source of it
    std::set<std::string> hearing;   ///< searching rescuers with any of its signals
  };
  std::vector<Eligible> eligible;
  for (const auto& v : victims) {
    if (is_found(v.state) || v.evidence_conflict || ambiguous.count(v.victim_id) != 0 ||
        given_up_.count(v.victim_id) != 0 || !v.position.position.allFinite()) {
      continue;
    }
    Eligible e{&v, {}, {}, {}};
    for (const auto& s : v.sources) {
      e.signals.emplace_back(s.rescuer_id, s.signal_id);
      if (searching.count(s.rescuer_id) != 0) e.placing.insert(s.rescuer_id);
    }
    const auto joined = groups.joined.find(v.victim_id);
    if (joined != groups.joined.end())
      for (const auto& s : joined->second) e.signals.emplace_back(s.rescuer_id, s.signal_id);
    for (const auto& [rescuer, signal] : e.signals)
      if (searching.count(rescuer) != 0) e.hearing.insert(rescuer);
    // Given back to everyone before it was placed: for good, placed or not.
    const bool given_up = std::any_of(e.signals.begin(), e.signals.end(),
                                      [&](const SignalKey& k) { return given_up_signals_.count(k) != 0; });
    if (e.hearing.size() >= 2 && !e.placing.empty() && !given_up) eligible.push_back(std::move(e));
  }
  // Pursuits under way first, so that a new victim goes to a rescuer who pursues nothing: with
  // several victims close together, one each, not all to whoever stands nearest the cluster.
  // A rescuer pursuing a transmitter not yet placed is busy too.
  std::map<std::uint32_t, Pursuit> kept;
  std::set<std::string> busy;
  for (const auto& g : group_pursuits_) busy.insert(g.pursuit.rescuer_id);
  for (const auto& e : eligible) {
    const auto id = e.victim->victim_id;
    const auto previous = pursuits_.find(id);
    if (previous == pursuits_.end() || e.hearing.count(previous->second.rescuer_id) == 0) continue;
    Pursuit p = previous->second;
    if (now - p.since > timeout_ns_) {
      given_up_[id] = now;
      events_.push_back({true, "victim " + std::to_string(id) + " not found by " + p.rescuer_id +
                                   " in time: every rescuer who hears it may pursue it again"});
      continue;
    }
    if (e.placing.count(p.rescuer_id) != 0) {
      p.matched_only_since = 0;
    } else if (p.matched_only_since == 0) {
      p.matched_only_since = now;
    } else if (now - p.matched_only_since > kMatchedPursuerGraceNs) {
      events_.push_back({true, "victim " + std::to_string(id) + ": " + p.rescuer_id +
                                   " has not placed it in time (his signal only matched its signature): the "
                                   "nearest of those who placed it is sent"});
      continue;
    }
    kept.emplace(id, p);
    busy.insert(p.rescuer_id);
  }
  // A victim whose transmitter was pursued before anyone placed it: its pursuit then (the one
  // whose pursuer placed it, else one whose pursuer hears it, else any that overlaps).
  std::set<std::size_t> carried_groups;
  std::map<std::uint32_t, std::size_t> carried_to;  // victim id -> group pursuit
  for (const auto& e : eligible) {
    const auto id = e.victim->victim_id;
    if (kept.count(id) != 0 || given_up_.count(id) != 0) continue;
    std::size_t best = group_pursuits_.size();
    int best_rank = 3;
    for (std::size_t g = 0; g < group_pursuits_.size(); ++g) {
      const auto& signals = group_pursuits_[g].signals;
      if (carried_groups.count(g) != 0 ||
          std::none_of(e.signals.begin(), e.signals.end(), [&](const SignalKey& k) { return signals.count(k) != 0; }))
        continue;
      const auto& r = group_pursuits_[g].pursuit.rescuer_id;
      const int rank = e.placing.count(r) != 0 ? 0 : e.hearing.count(r) != 0 ? 1 : 2;
      if (rank < best_rank) {
        best = g;
        best_rank = rank;
      }
    }
    if (best == group_pursuits_.size()) continue;
    carried_groups.insert(best);
    carried_to[id] = best;
    // A pursuer who did not place it is free before anyone is chosen, so that whether a placer
    // is free does not depend on the order of the victims.
    const auto& r = group_pursuits_[best].pursuit.rescuer_id;
    const bool pursues_victim =
        std::any_of(kept.begin(), kept.end(), [&](const auto& k) { return k.second.rescuer_id == r; });
    if (e.placing.count(r) == 0 && !pursues_victim) busy.erase(r);
  }
  for (const auto& e : eligible) {
    const auto id = e.victim->victim_id;
    if (kept.count(id) != 0 || given_up_.count(id) != 0) continue;
    // A pursuer who placed it keeps it, timeout and all. One who did not ends his pursuit, and
    // the nearest of those who placed it is sent: having placed it is better evidence of being
    // near than having heard it first; unless all of those pursue another, when one who hears
    // it keeps it a while (the matched grace).
    const auto carried = carried_to.find(id);
    if (carried != carried_to.end()) {
      Pursuit p = group_pursuits_[carried->second].pursuit;
      const bool placed_by_him = e.placing.count(p.rescuer_id) != 0;
      const bool placer_free =
          std::any_of(e.placing.begin(), e.placing.end(), [&](const std::string& r) { return busy.count(r) == 0; });
      // (Not if he was freed above and has just been sent to another victim.)
      const bool exception = !placer_free && busy.count(p.rescuer_id) == 0 && e.hearing.count(p.rescuer_id) != 0;
      if (placed_by_him || exception) {
        p.matched_only_since = placed_by_him ? 0 : now;
        kept.emplace(id, p);
        busy.insert(p.rescuer_id);
        events_.push_back({false, "victim " + std::to_string(id) + ": placed; still pursued by " + p.rescuer_id +
                                      ", who pursued its signal before it was placed" +
                                      (placed_by_him ? "" : " (those who placed it pursue another)")});
        continue;
      }
      events_.push_back(
          {false, "victim " + std::to_string(id) + ": placed; " + p.rescuer_id +
                      ", who pursued its signal before it was placed, did not place it (or no longer searches): his "
                      "pursuit ends"});
    }
    // The nearest of those who placed it (a signature's match alone sends nobody).
    const Vec2 at = e.victim->position.position.head<2>();
    auto nearest_of = [&](bool only_free) {
      std::string best;
      double nearest = std::numeric_limits<double>::infinity();
      for (const auto& r : e.placing) {
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
    const bool free = !pursuer.empty();
    if (!free) pursuer = nearest_of(false);
    kept.emplace(id, Pursuit{pursuer, now, 0});
    busy.insert(pursuer);
    events_.push_back({false, "victim " + std::to_string(id) + ": pursued by " + pursuer + " (of " +
                                  std::to_string(e.hearing.size()) + " who hear it, the nearest who placed it" +
                                  (free ? " not pursuing another" : "; all of them pursue another") +
                                  "); the others' signals of it are handed over"});
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
  std::vector<GroupPursuit> left;  // not carried to a victim
  for (std::size_t g = 0; g < group_pursuits_.size(); ++g)
    if (carried_groups.count(g) == 0) left.push_back(std::move(group_pursuits_[g]));
  group_pursuits_ = std::move(left);
  pursue_unplaced(groups, searching, busy, now, out);
  return out;
}

void SignalPursuits::refresh_given_up(const std::vector<FusedVictim>& victims, const SignalGroups& groups,
                                      TimestampNs now) {
  auto seen = [&](const SignalKey& k) {
    const auto it = given_up_signals_.find(k);
    if (it != given_up_signals_.end()) it->second = now;
  };
  for (const auto& v : victims) {
    const auto it = given_up_.find(v.victim_id);
    if (it != given_up_.end()) it->second = now;
    for (const auto& s : v.sources) seen({s.rescuer_id, s.signal_id});
  }
  for (const auto& k : groups.heard) seen(k);
  auto forget_unseen = [&](auto& given_up) {
    for (auto it = given_up.begin(); it != given_up.end();)
      it = now - it->second > timeout_ns_ ? given_up.erase(it) : std::next(it);
  };
  forget_unseen(given_up_);
  forget_unseen(given_up_signals_);
}

void SignalPursuits::pursue_unplaced(const SignalGroups& groups, const std::map<std::string, Vec2>& searching,
                                     std::set<std::string>& busy, TimestampNs now, std::vector<SignalHandOver>& out) {
  struct Heard {
    const std::vector<HeardSignal>* group;
    std::set<SignalKey> signals;
    std::vector<std::string> hearing;  ///< searching, in order of first heard
  };
  std::vector<Heard> heard;
  for (const auto& group : groups.unplaced) {
    Heard h{&group, {}, {}};
    for (const auto& s : group) {
      h.signals.emplace(s.rescuer_id, s.signal_id);
      if (searching.count(s.rescuer_id) != 0) h.hearing.push_back(s.rescuer_id);
    }
    const bool given_up = std::any_of(h.signals.begin(), h.signals.end(),
                                      [&](const SignalKey& k) { return given_up_signals_.count(k) != 0; });
    if (h.hearing.size() >= 2 && !given_up) heard.push_back(std::move(h));
  }
  auto label_of = [](const std::vector<HeardSignal>& group) {
    return "signal " + group.front().rescuer_id + "/" + std::to_string(group.front().signal_id) + " (" +
           signature_text(group.front().transmitter) + "; not yet placed)";
  };
  auto hand_over = [&](const Heard& h, const Pursuit& p) {
    for (const auto& s : *h.group)
      if (s.rescuer_id != p.rescuer_id && out.size() < kSignalHandOversMax)
        out.push_back({s.rescuer_id, s.signal_id, 0, p.rescuer_id});
  };
  const TimestampNs place_within = std::min(timeout_ns_, kUnplacedPursuitPlaceNs);
  std::vector<GroupPursuit> kept;
  std::vector<bool> continued(group_pursuits_.size(), false);
  std::vector<bool> served(heard.size(), false);
  // Pursuits under way first (as for victims), then new ones.
  for (std::size_t i = 0; i < heard.size(); ++i) {
    const Heard& h = heard[i];
    for (std::size_t g = 0; g < group_pursuits_.size() && !served[i]; ++g) {
      const GroupPursuit& previous = group_pursuits_[g];
      const bool hears = std::find(h.hearing.begin(), h.hearing.end(), previous.pursuit.rescuer_id) != h.hearing.end();
      if (continued[g] || !hears ||
          std::none_of(previous.signals.begin(), previous.signals.end(),
                       [&](const SignalKey& k) { return h.signals.count(k) != 0; }))
        continue;
      continued[g] = served[i] = true;
      if (now - previous.pursuit.since > place_within) {
        for (const auto& k : h.signals) given_up_signals_[k] = now;
        events_.push_back({true, label_of(*h.group) + " not placed by " + previous.pursuit.rescuer_id + " within " +
                                     std::to_string(place_within / 1'000'000'000) +
                                     " s: every rescuer who hears it may pursue it again"});
        continue;
      }
      kept.push_back({previous.pursuit, h.signals, now});
      hand_over(h, previous.pursuit);
    }
  }
  for (std::size_t i = 0; i < heard.size(); ++i) {
    if (served[i]) continue;
    const Heard& h = heard[i];
    // The nearest by his own distance reading, among those pursuing nothing else (the first to
    // take it when one of them reads none); when everyone who hears it pursues another, nobody
    // is sent away from it.
    std::string first, nearest;
    double nearest_range = std::numeric_limits<double>::infinity();
    bool all_read = true;
    for (const auto& s : *h.group) {
      if (searching.count(s.rescuer_id) == 0 || busy.count(s.rescuer_id) != 0) continue;
      if (first.empty()) first = s.rescuer_id;
      if (!std::isfinite(s.range_m)) {
        all_read = false;
      } else if (s.range_m < nearest_range) {
        nearest_range = s.range_m;
        nearest = s.rescuer_id;
      }
    }
    if (first.empty()) continue;
    const Pursuit p{all_read ? nearest : first, now, 0};
    busy.insert(p.rescuer_id);
    char reading[48] = "";
    if (all_read) std::snprintf(reading, sizeof reading, " (%.0f m)", nearest_range);
    events_.push_back({false, label_of(*h.group) + ": pursued by " + p.rescuer_id + " (of " +
                                  std::to_string(h.hearing.size()) + " who hear it, " +
                                  (all_read ? std::string("the nearest by his distance reading") + reading
                                            : std::string("the first to take it")) +
                                  " not pursuing another); the others' signals of it are handed over"});
    kept.push_back({p, h.signals, now});
    hand_over(h, p);
  }
  // A group broken for a moment keeps its pursuer (handing nothing over) for the grace.
  for (std::size_t g = 0; g < group_pursuits_.size(); ++g)
    if (!continued[g] && now - group_pursuits_[g].last_seen <= kUnplacedPursuitGraceNs)
      kept.push_back(std::move(group_pursuits_[g]));
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
    g.last_seen = now;
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
