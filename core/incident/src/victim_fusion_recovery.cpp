// VictimFusion's dug-out victims (victim_fusion.hpp, "Dug out" and "Late echoes"): their
// sources retired, and a late estimate of their switched-off transmitter retired with them.
#include <algorithm>

#include "position_gate.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/time_units.hpp"
#include "sarloc/core/incident/victim_fusion.hpp"

namespace sarloc::incident {

void VictimFusion::retire(const SourceKey& key) {
  retired_.insert(key);
  if (const auto it = sources_.find(key); it != sources_.end()) {
    unbind(it->second, Unbind::kInactive);
    sources_.erase(it);
  }
  adopted_bindings_.erase(key);
}

bool VictimFusion::recover(std::uint32_t victim_id, TimestampNs at) {
  FusedVictim* v = find_victim(victim_id);
  if (v == nullptr) throw InputError("victim_recovery.victim_id = " + std::to_string(victim_id) + ": no such victim");
  if (v->state == VictimState::kRecovered) {
    // Adopted as recovered before its recovery arrived: the time is now known.
    if (auto it = recoveries_.find(victim_id); it != recoveries_.end()) it->second.at = std::max(it->second.at, at);
    return false;
  }
  if (v->state != VictimState::kFound) {
    throw InputError("victim_recovery.victim_id = " + std::to_string(victim_id) + ": the victim is " +
                     to_string(v->state) + ", not FOUND: only a found victim is dug out");
  }
  // Its list stays as published (who found it); the sources themselves hear a switched-off
  // transmitter no more, and any that did would be another transmitter.
  const std::vector<VictimSource> listed = v->sources;
  std::vector<SourceKey> retiring;
  for (const VictimSource& vs : listed) retiring.emplace_back(vs.rescuer_id, vs.signal_id);
  for (const auto& [key, s] : sources_)
    if (s.last_victim_id == victim_id) retiring.push_back(key);
  Recovery recovery{at, {}};
  for (const SourceKey& key : retiring) {
    const auto it = sources_.find(key);
    if (it == sources_.end()) continue;
    for (const auto& [name, e] : it->second.by_estimator)
      if (e.transmitter.known()) recovery.transmitters.push_back(e.transmitter);
  }
  for (const SourceKey& key : retiring) retire(key);
  v = find_victim(victim_id);
  v->sources = listed;
  v->state = VictimState::kRecovered;
  v->evidence_conflict = false;
  v->possibly_same_as = 0;
  by_radius_only_.erase(victim_id);
  withdrawn_.erase(victim_id);
  recoveries_[victim_id] = std::move(recovery);
  // Heard already, not associated yet (it arrived in this cycle): a late echo too.
  std::vector<SourceKey> echoes;
  for (const auto& [key, s] : sources_)
    if (dug_out_echo_of(s) == victim_id) echoes.push_back(key);
  for (const SourceKey& key : echoes) retire_echo(key, victim_id);
  return true;
}

void VictimFusion::retire_echo(const SourceKey& key, std::uint32_t victim_id) {
  if (const auto it = sources_.find(key); it != sources_.end())
    late_echoes_.push_back({victim_id, key.first, key.second, it->second.first_stamp});
  retire(key);
}

std::vector<VictimFusion::LateEcho> VictimFusion::take_late_echoes() {
  std::vector<LateEcho> out;
  out.swap(late_echoes_);
  return out;
}

std::uint32_t VictimFusion::dug_out_echo_of(const Source& s) const {
  if (s.victim_id != 0 || s.last_victim_id != 0) return 0;  // associated once: its own story
  const auto grace = seconds_to_ns(config_.dug_out_grace_s);
  for (const auto& [id, recovery] : recoveries_) {
    if (s.first_stamp > recovery.at + grace) continue;  // first heard after the switch-off
    const FusedVictim* v = victim(id);
    if (v == nullptr || v->state != VictimState::kRecovered || v->floor != s.estimate.floor) continue;
    if ((s.estimate.position.position - v->position.position).norm() > kDugOutReachM) continue;
    if (mahalanobis2(s.estimate.position, v->position) > gate_) continue;
    const bool other_transmitter =
        std::any_of(recovery.transmitters.begin(), recovery.transmitters.end(), [&](const auto& t) {
          return responder::compare_signatures(t, s.estimate.transmitter, config_.gate_probability) ==
                 responder::SignatureMatch::kDistinct;
        });
    if (!other_transmitter) return id;
  }
  return 0;
}

}  // namespace sarloc::incident
