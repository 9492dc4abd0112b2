#include "sarloc/core/incident/signal_groups.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>
#include <tuple>

#include "sarloc/core/common/chi_square.hpp"

namespace sarloc::incident {
namespace {

bool fully_known(const responder::TransmitterSignature& s) { return s.carrier_known() && s.period_known(); }

/// Pairs of signals whose signatures are alike (both components known). A sweep over the
/// carriers: at hundreds of rescuers only neighbours on the carrier axis are compared.
std::vector<std::vector<std::size_t>> alike_pairs(const std::vector<HeardSignal>& heard, double gate) {
  std::vector<std::size_t> known;
  double widest = 0.0;
  for (std::size_t i = 0; i < heard.size(); ++i) {
    if (!fully_known(heard[i].transmitter)) continue;
    known.push_back(i);
    widest = std::max(widest, heard[i].transmitter.carrier_sigma_hz);
  }
  std::sort(known.begin(), known.end(), [&](std::size_t a, std::size_t b) {
    return heard[a].transmitter.carrier_offset_hz < heard[b].transmitter.carrier_offset_hz;
  });
  // Alike needs the carrier's own share of the distance inside the two-component gate.
  const double reach = std::sqrt(chi_square_quantile(gate, 2.0));
  std::vector<std::vector<std::size_t>> out(heard.size());
  for (std::size_t a = 0; a < known.size(); ++a) {
    const auto& sa = heard[known[a]].transmitter;
    const double bound = reach * std::hypot(sa.carrier_sigma_hz, widest);
    for (std::size_t b = a + 1; b < known.size(); ++b) {
      const auto& sb = heard[known[b]].transmitter;
      if (sb.carrier_offset_hz - sa.carrier_offset_hz > bound) break;
      if (responder::compare_signatures(sa, sb, gate, true) != responder::SignatureMatch::kAlike) continue;
      out[known[a]].push_back(known[b]);
      out[known[b]].push_back(known[a]);
    }
  }
  return out;
}

/// `alike`, and the pairs with a signal whose signature is partly known (a carrier without its
/// period, or the reverse) whose known part agrees: such a pair may be one transmitter, so it
/// makes the other signal ambiguous, never a group.
std::vector<std::vector<std::size_t>> maybe_pairs(const std::vector<HeardSignal>& heard,
                                                  std::vector<std::vector<std::size_t>> alike, double gate) {
  for (std::size_t p = 0; p < heard.size(); ++p) {
    const auto& sp = heard[p].transmitter;
    if (!sp.known() || fully_known(sp)) continue;
    for (std::size_t j = 0; j < heard.size(); ++j) {
      const bool partial = heard[j].transmitter.known() && !fully_known(heard[j].transmitter);
      if (j == p || (partial && j < p)) continue;  // a pair of two partial ones once
      if (responder::compare_signatures(sp, heard[j].transmitter, gate) != responder::SignatureMatch::kAlike) continue;
      alike[p].push_back(j);
      alike[j].push_back(p);
    }
  }
  return alike;
}

}  // namespace

SignalGroups group_heard_signals(const std::vector<HeardSignal>& heard, const std::vector<FusedVictim>& victims,
                                 double gate_probability) {
  const auto alike = alike_pairs(heard, gate_probability);
  const auto maybe = maybe_pairs(heard, alike, gate_probability);
  auto key_of = [&](std::size_t i) { return SignalKey{heard[i].rescuer_id, heard[i].signal_id}; };
  std::map<SignalKey, std::size_t> index;
  for (std::size_t i = 0; i < heard.size(); ++i) index[key_of(i)] = i;
  SignalGroups out;
  for (const auto& [key, i] : index) out.heard.insert(key);
  std::map<SignalKey, const FusedVictim*> victim_of;
  for (const auto& v : victims)
    for (const auto& s : v.sources) victim_of[{s.rescuer_id, s.signal_id}] = &v;

  auto is_alike = [&](std::size_t a, std::size_t b) {
    return std::find(alike[a].begin(), alike[a].end(), b) != alike[a].end();
  };
  // Placed signals and victims' sources stand for a transmitter already on the picture.
  auto stands_placed = [&](std::size_t j) { return heard[j].placed || victim_of.count(key_of(j)) != 0; };
  std::vector<bool> candidate(heard.size(), false);
  for (std::size_t i = 0; i < heard.size(); ++i) {
    if (stands_placed(i) || !fully_known(heard[i].transmitter)) continue;
    // Alike with another signal of its own rescuer: it could be either transmitter.
    const bool self_ambiguous = std::any_of(maybe[i].begin(), maybe[i].end(),
                                            [&](std::size_t j) { return heard[j].rescuer_id == heard[i].rescuer_id; });
    candidate[i] = !self_ambiguous;
  }

  std::vector<const FusedVictim*> join(heard.size(), nullptr);
  std::map<std::pair<std::string, std::uint32_t>, int> joining;  // (rescuer, victim id) -> its signals joining
  for (std::size_t i = 0; i < heard.size(); ++i) {
    if (!candidate[i]) continue;
    std::set<const FusedVictim*> victims_alike;
    bool unknown_placed = false;  // alike with a placed signal not (yet) a victim's source
    for (const std::size_t j : maybe[i]) {
      const auto v = victim_of.find(key_of(j));
      if (v != victim_of.end())
        victims_alike.insert(v->second);
      else if (heard[j].placed)
        unknown_placed = true;
    }
    if (unknown_placed || victims_alike.size() != 1) continue;
    const FusedVictim* v = *victims_alike.begin();
    bool all = true;
    bool one_whole = false;  // at least one source with a whole signature alike
    for (const auto& s : v->sources) {
      if (s.rescuer_id == heard[i].rescuer_id) all = false;  // one receiver's two signals: its repeat test decides
      const auto it = index.find({s.rescuer_id, s.signal_id});
      if (it == index.end() || !heard[it->second].transmitter.known()) continue;
      const bool whole = fully_known(heard[it->second].transmitter);
      const bool agrees =
          whole ? is_alike(i, it->second) : std::find(maybe[i].begin(), maybe[i].end(), it->second) != maybe[i].end();
      all = all && agrees;
      one_whole = one_whole || (whole && agrees);
    }
    if (!all || !one_whole) continue;
    join[i] = v;
    ++joining[{heard[i].rescuer_id, v->victim_id}];
  }
  std::vector<bool> joined(heard.size(), false);
  for (std::size_t i = 0; i < heard.size(); ++i) {
    if (join[i] == nullptr || joining[{heard[i].rescuer_id, join[i]->victim_id}] != 1) continue;
    out.joined[join[i]->victim_id].push_back(heard[i]);
    joined[i] = true;
  }

  // The rest: alike with nothing on the picture and with no signal that joined a victim.
  std::vector<bool> free(heard.size(), false);
  for (std::size_t i = 0; i < heard.size(); ++i) {
    free[i] = candidate[i] && !joined[i] && std::none_of(maybe[i].begin(), maybe[i].end(), [&](std::size_t j) {
                return stands_placed(j) || joined[j];
              });
  }
  std::vector<bool> seen(heard.size(), false);
  for (std::size_t start = 0; start < heard.size(); ++start) {
    if (!free[start] || seen[start]) continue;
    std::vector<std::size_t> group{start};
    seen[start] = true;
    bool whole = true;  // every member free (a neighbour that is not makes the group ambiguous)
    for (std::size_t k = 0; k < group.size(); ++k) {
      for (const std::size_t j : maybe[group[k]]) whole = whole && free[j];
      for (const std::size_t j : alike[group[k]]) {
        if (seen[j]) continue;
        seen[j] = true;
        group.push_back(j);
      }
    }
    if (!whole || group.size() < 2) continue;
    std::set<std::string> rescuers;
    bool clique = true;
    for (std::size_t a = 0; a < group.size(); ++a) {
      rescuers.insert(heard[group[a]].rescuer_id);
      for (std::size_t b = a + 1; b < group.size(); ++b) clique = clique && is_alike(group[a], group[b]);
    }
    if (!clique || rescuers.size() != group.size()) continue;
    std::sort(group.begin(), group.end(), [&](std::size_t a, std::size_t b) {
      return std::tie(heard[a].first_heard, heard[a].rescuer_id) < std::tie(heard[b].first_heard, heard[b].rescuer_id);
    });
    std::vector<HeardSignal> members;
    for (const std::size_t i : group) members.push_back(heard[i]);
    out.unplaced.push_back(std::move(members));
  }
  return out;
}

}  // namespace sarloc::incident
