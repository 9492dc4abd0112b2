#include "sarloc/core/incident/victim_fusion.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <tuple>
#include <utility>

#include "position_gate.hpp"
#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "sarloc/core/common/time_units.hpp"
#include "sarloc/core/common/validate.hpp"
#include "sarloc/core/incident/assignment.hpp"

namespace sarloc::incident {
namespace {

using responder::compare_signatures;
using responder::SignatureMatch;

bool open_unit(double p) { return std::isfinite(p) && p > 0.0 && p < 1.0; }

// A covariance the fusion can use: finite, symmetric, positive definite (InputError naming
// `where` otherwise).
void check_covariance(const std::string& where, const Mat3& p) {
  if (!p.allFinite()) throw InputError(where + ".covariance: must be finite");
  if ((p - p.transpose()).cwiseAbs().maxCoeff() > 1e-9 * (1.0 + p.cwiseAbs().maxCoeff()))
    throw InputError(where + ".covariance: must be symmetric");
  if (Eigen::LLT<Mat3>(p).info() != Eigen::Success) throw InputError(where + ".covariance: must be positive definite");
}

bool kept_apart(const FusedVictim& a, const FusedVictim& b) {
  // Two confirmed victims, one of which has lost every source: nothing new says they are one,
  // and the evidence that may have kept them apart (a rescuer with a signal in each) left with
  // the sources. Seen: A and D, FOUND 1.5 m apart with 0.9 m radii (inside each other's merge
  // gate), merged once their rescuers had walked off, into one confirmed victim far from both.
  // A new source near a sourceless victim joins it by association, not by a merge.
  return (a.sources.empty() || b.sources.empty()) && a.state >= VictimState::kLocated &&
         b.state >= VictimState::kLocated;
}

bool same_rescuer_conflict(const FusedVictim& a, const FusedVictim& b) {
  for (const VictimSource& x : a.sources)
    for (const VictimSource& y : b.sources)
      if (x.rescuer_id == y.rescuer_id) return true;
  return false;
}

TimestampNs earliest_set(TimestampNs a, TimestampNs b) {
  if (a == 0) return b;
  if (b == 0) return a;
  return std::min(a, b);
}

}  // namespace

void VictimFusionConfig::validate() const {
  require(open_unit(gate_probability), "fusion.gate_probability", gate_probability, "must be in (0, 1)");
  require(open_unit(keep_gate_probability), "fusion.keep_gate_probability", keep_gate_probability, "must be in (0, 1)");
  require(keep_gate_probability >= gate_probability, "fusion.keep_gate_probability", keep_gate_probability,
          "must be >= gate_probability");
  require(open_unit(merge_gate_probability), "fusion.merge_gate_probability", merge_gate_probability,
          "must be in (0, 1)");
  require(std::isfinite(source_timeout_s) && source_timeout_s > 0.0 && source_timeout_s <= 3600.0,
          "fusion.source_timeout_s", source_timeout_s, "must be in (0, 3600]");
  require(std::isfinite(located_radius_m) && located_radius_m > 0.0 && located_radius_m <= 100.0,
          "fusion.located_radius_m", located_radius_m, "must be in (0, 100]");
  require(std::isfinite(dug_out_grace_s) && dug_out_grace_s >= 0.0 && dug_out_grace_s <= 600.0,
          "fusion.dug_out_grace_s", dug_out_grace_s, "must be in [0, 600]");
  require(weighting == CiWeighting::kInverseTrace || weighting == CiWeighting::kMinTrace, "fusion.weighting",
          static_cast<double>(weighting), "must be inverse_trace or min_trace");
}

VictimFusion::VictimFusion(VictimFusionConfig config) : config_(config) {
  config_.validate();
  gate_ = chi_square_quantile(config_.gate_probability, 3.0);
  keep_gate_ = chi_square_quantile(config_.keep_gate_probability, 3.0);
  merge_gate_ = chi_square_quantile(config_.merge_gate_probability, 3.0);
}

void check_adoptable(const FusedVictim& v) {
  const std::string where = "fused_victim[" + std::to_string(v.victim_id) + "]";
  if (v.victim_id == 0) throw InputError("fused_victim.victim_id = 0: ids start at 1");
  if (!v.position.position.allFinite()) throw InputError(where + ".position: must be finite");
  check_covariance(where, v.position.covariance);
  for (const VictimSource& vs : v.sources)
    if (vs.rescuer_id.empty()) throw InputError(where + ".sources.rescuer_id = \"\": must not be empty");
}

void VictimFusion::adopt(const std::vector<FusedVictim>& picture, std::uint32_t largest_id_seen) {
  std::vector<FusedVictim> sorted(picture);
  std::sort(sorted.begin(), sorted.end(),
            [](const FusedVictim& a, const FusedVictim& b) { return a.victim_id < b.victim_id; });
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    check_adoptable(sorted[i]);
    if (i > 0 && sorted[i].victim_id == sorted[i - 1].victim_id)
      throw InputError("fused_victim[" + std::to_string(sorted[i].victim_id) + "]: listed twice");
  }

  // What step() advanced on the victims adopted last time (a standby steps between
  // adoptions) is kept; victims it opened itself were never published and are dropped.
  std::map<std::uint32_t, FusedVictim> advanced;
  for (FusedVictim& v : victims_)
    if (adopted_ids_.count(v.victim_id) != 0) advanced.emplace(v.victim_id, std::move(v));
  for (auto& [key, s] : sources_) s.victim_id = 0;
  victims_.clear();
  removed_.clear();
  orphaned_.clear();
  adopted_bindings_.clear();
  adopted_ids_.clear();
  contradicted_.clear();
  withdrawals_.clear();
  withdrawn_.clear();
  for (FusedVictim& v : sorted) {
    adopted_ids_.insert(v.victim_id);
    if (const auto own = advanced.find(v.victim_id); own != advanced.end() && own->second.state > v.state) {
      v.state = own->second.state;
      if (v.located_at == 0) v.located_at = own->second.located_at;
      if (v.found_at == 0) v.found_at = own->second.found_at;
    }
    if (v.state == VictimState::kRecovered) {  // dug out: its sources are retired, its list kept
      // Its recovery not heard yet: its newest source stamp stands for the dig (no later).
      recoveries_.emplace(v.victim_id, Recovery{v.last_update, {}});
      for (const VictimSource& vs : v.sources) retire({vs.rescuer_id, vs.signal_id});
      victims_.push_back(std::move(v));
      continue;
    }
    std::vector<VictimSource> listed;
    listed.swap(v.sources);
    // A withdrawn victim as published: unconfirmed, flagged, nothing bound.
    if (listed.empty() && v.evidence_conflict && v.state == VictimState::kUnconfirmed) withdrawn_.insert(v.victim_id);
    for (const VictimSource& vs : listed) {
      const SourceKey key{vs.rescuer_id, vs.signal_id};
      const auto it = sources_.find(key);
      if (it == sources_.end()) {
        adopted_bindings_.emplace(key, v.victim_id);  // the first victim listing it wins
        continue;
      }
      if (it->second.victim_id != 0) continue;  // listed by a victim before this one
      it->second.victim_id = v.victim_id;
      it->second.last_victim_id = v.victim_id;
      v.sources.push_back(vs);  // the picture's last_update, as published
    }
    std::sort(v.sources.begin(), v.sources.end(), [](const VictimSource& a, const VictimSource& b) {
      return std::tie(a.rescuer_id, a.signal_id) < std::tie(b.rescuer_id, b.signal_id);
    });
    victims_.push_back(std::move(v));
  }
  const std::uint32_t largest = victims_.empty() ? 0 : victims_.back().victim_id;
  next_id_ = std::max(largest, largest_id_seen) + 1;
}

bool VictimFusion::update(const SourceEstimate& estimate) {
  const std::string where =
      "source_estimate[" + estimate.rescuer_id + "/" + std::to_string(estimate.signal_id) + "]";
  if (estimate.rescuer_id.empty()) throw InputError("source_estimate.rescuer_id = \"\": must not be empty");
  if (!estimate.position.position.allFinite()) throw InputError(where + ".position: must be finite");
  const Mat3& p = estimate.position.covariance;
  check_covariance(where, p);
  // Heights are above the snow surface (z = 0): a victim is buried. An estimate confidently
  // above the surface comes from a filter locked on its mirror solution and would open a
  // ghost victim (seen under packet loss: 30 m up, "found").
  const double z = estimate.position.position.z();
  if (estimate.below_surface && z - 5.0 * std::sqrt(p(2, 2)) > 0.0) {  // 5 sigma: never a noise draw
    std::ostringstream os;
    os << where << ".position.z = " << z << " m (sigma " << std::sqrt(p(2, 2))
       << "): above the snow surface, a buried victim cannot be there";
    throw InputError(os.str());
  }

  const SourceKey key{estimate.rescuer_id, estimate.signal_id};
  if (retired_.count(key) != 0) return false;  // a recovered victim's: its transmitter is off
  auto it = sources_.find(key);
  if (it == sources_.end()) {
    it = sources_.emplace(key, Source{}).first;
    it->second.estimate = estimate;
    it->second.first_stamp = estimate.stamp;
    check_conflict(it->second, estimate);
    // First heard after adopt(): it joins the victim the adopted picture listed it under.
    if (const auto bound = adopted_bindings_.find(key); bound != adopted_bindings_.end()) {
      if (FusedVictim* v = find_victim(bound->second); v != nullptr && v->floor == estimate.floor) bind(it->second, *v);
      adopted_bindings_.erase(bound);
    }
    if (const std::uint32_t dug_out = dug_out_echo_of(it->second); dug_out != 0) {  // "Late echoes"
      retire_echo(key, dug_out);
      return false;
    }
    return true;
  }
  check_conflict(it->second, estimate);
  Source& s = it->second;
  // While conflicted, a source with a device estimator follows that one only.
  const bool distrusted = !s.trusted.empty() && estimate.stamp < s.conflict_until && estimate.estimator != s.trusted;
  // The device's own LOCATED / FOUND holds the source (see the header, Conflicts).
  auto device_located = [](const SourceEstimate& e) { return e.from_device && e.state >= SourceState::kLocated; };
  const bool held = device_located(s.estimate) && !estimate.from_device;
  const bool takes_over = device_located(estimate) && !s.estimate.from_device;
  if (distrusted || held || (estimate.stamp < s.estimate.stamp && !takes_over)) return false;
  s.estimate = estimate;
  return true;
}

void VictimFusion::check_conflict(Source& s, const SourceEstimate& estimate) {
  const auto window = seconds_to_ns(config_.source_timeout_s);
  auto& mine = s.by_estimator[estimate.estimator];
  if (estimate.stamp < mine.stamp) return;  // an older sample of the same estimator
  mine = estimate;
  if (estimate.state < SourceState::kConverged) return;
  for (const auto& [name, other] : s.by_estimator) {
    if (name == estimate.estimator || other.state < SourceState::kConverged) continue;
    if (std::llabs(other.stamp - estimate.stamp) > window) continue;
    if (mahalanobis2(estimate.position, other.position) > keep_gate_) {
      s.conflict_until = std::max(s.conflict_until, std::max(estimate.stamp, other.stamp) + window);
      if (estimate.from_device != other.from_device) {
        const SourceEstimate& device = estimate.from_device ? estimate : other;
        s.trusted = device.estimator;
        if (s.estimate.estimator != s.trusted) s.estimate = device;
      } else {
        s.trusted.clear();
      }
    }
  }
}

std::size_t VictimFusion::remove_source(const std::string& rescuer_id) {
  std::size_t n = 0;
  for (auto it = sources_.lower_bound({rescuer_id, 0});
       it != sources_.end() && it->first.first == rescuer_id;) {
    unbind(it->second, Unbind::kInactive);
    it = sources_.erase(it);
    ++n;
  }
  for (FusedVictim& v : victims_) refuse(v);
  return n;
}

bool VictimFusion::remove_source(const std::string& rescuer_id, std::uint32_t signal_id) {
  auto it = sources_.find({rescuer_id, signal_id});
  if (it == sources_.end()) return false;
  const std::uint32_t vid = it->second.victim_id;
  unbind(it->second, Unbind::kInactive);
  sources_.erase(it);
  if (FusedVictim* v = find_victim(vid)) refuse(*v);
  return true;
}

std::vector<std::uint32_t> VictimFusion::take_removed() {
  std::vector<std::uint32_t> out;
  out.swap(removed_);
  return out;
}

std::vector<VictimFusion::Withdrawal> VictimFusion::take_withdrawn() {
  std::vector<Withdrawal> out;
  out.swap(withdrawals_);
  return out;
}

void VictimFusion::withdraw_contradicted() {
  for (const Withdrawal& w : contradicted_) {
    FusedVictim* v = find_victim(w.victim_id);
    if (v == nullptr || !v->sources.empty() || v->state != VictimState::kLocated) continue;
    v->state = VictimState::kUnconfirmed;
    v->located_at = 0;
    withdrawn_.insert(v->victim_id);
    withdrawals_.push_back(w);
  }
  contradicted_.clear();
}

const FusedVictim* VictimFusion::victim(std::uint32_t id) const {
  auto it = std::lower_bound(victims_.begin(), victims_.end(), id,
                             [](const FusedVictim& v, std::uint32_t i) { return v.victim_id < i; });
  return (it != victims_.end() && it->victim_id == id) ? &*it : nullptr;
}

FusedVictim* VictimFusion::find_victim(std::uint32_t id) {
  return const_cast<FusedVictim*>(std::as_const(*this).victim(id));  // the one lookup, for the owner
}

std::set<std::uint32_t> VictimFusion::found_ids() const {
  std::set<std::uint32_t> found;
  for (const FusedVictim& v : victims_)
    if (v.state == VictimState::kFound) found.insert(v.victim_id);
  return found;
}

std::vector<GaussianPosition> VictimFusion::bound_positions(const FusedVictim& v,
                                                            const std::string& except_rescuer) const {
  std::vector<GaussianPosition> out;
  out.reserve(v.sources.size());
  for (const VictimSource& vs : v.sources) {
    if (vs.rescuer_id == except_rescuer) continue;
    out.push_back(sources_.at({vs.rescuer_id, vs.signal_id}).estimate.position);
  }
  return out;
}

void VictimFusion::bind(Source& s, FusedVictim& v) {
  if (s.last_victim_id != 0 && s.last_victim_id != v.victim_id)
    contradicted_.push_back({s.last_victim_id, s.estimate.rescuer_id, s.estimate.signal_id, v.victim_id});
  s.victim_id = v.victim_id;
  s.last_victim_id = v.victim_id;
  VictimSource vs{s.estimate.rescuer_id, s.estimate.signal_id, s.estimate.stamp, s.estimate.signal_event,
                  s.estimate.signal_event_stamp};
  auto pos = std::lower_bound(v.sources.begin(), v.sources.end(), vs,
                              [](const VictimSource& a, const VictimSource& b) {
                                return std::tie(a.rescuer_id, a.signal_id) <
                                       std::tie(b.rescuer_id, b.signal_id);
                              });
  v.sources.insert(pos, vs);
}

void VictimFusion::unbind(Source& s, Unbind reason) {
  if (s.victim_id == 0) return;
  FusedVictim* v = find_victim(s.victim_id);
  s.victim_id = 0;
  if (v == nullptr) return;
  auto& vs = v->sources;
  vs.erase(std::remove_if(vs.begin(), vs.end(),
                          [&](const VictimSource& x) {
                            return x.rescuer_id == s.estimate.rescuer_id &&
                                   x.signal_id == s.estimate.signal_id;
                          }),
           vs.end());
  if (vs.empty() && reason == Unbind::kReassociated) orphaned_.push_back(v->victim_id);
}

std::vector<GaussianPosition> VictimFusion::finder_positions(const FusedVictim& v,
                                                             const std::string& except_rescuer) const {
  std::vector<GaussianPosition> out;
  for (const VictimSource& vs : v.sources) {
    if (vs.rescuer_id == except_rescuer) continue;
    const Source& s = sources_.at({vs.rescuer_id, vs.signal_id});
    if (confirming_state(s) == SourceState::kFound) out.push_back(s.estimate.position);
  }
  return out;
}

void VictimFusion::refuse(FusedVictim& v) {
  // Without sources, or dug out: keeps its last fused position.
  if (v.sources.empty() || v.state == VictimState::kRecovered) return;
  // A FOUND victim is where the devices standing over it say, and stays there when they walk
  // on: another rescuer's source (a split or mixed signal) must not drag the dig site (seen
  // live under load: a FOUND victim moved 2.4 m, 2.1 m too deep, by later sources).
  const std::vector<GaussianPosition> from =
      v.state == VictimState::kFound ? finder_positions(v, std::string()) : bound_positions(v, std::string());
  if (!from.empty()) v.position = covariance_intersection(from, config_.weighting).fused;
  for (VictimSource& vs : v.sources) {
    const SourceEstimate& e = sources_.at({vs.rescuer_id, vs.signal_id}).estimate;
    vs.last_update = e.stamp;
    vs.signal_event = e.signal_event;
    vs.signal_event_stamp = e.signal_event_stamp;
    v.last_update = std::max(v.last_update, vs.last_update);
  }
}

void VictimFusion::associate_rescuer(const std::string& rescuer_id, TimestampNs /*now*/) {
  // All active sources of this rescuer are solved together (see header, step 3).
  std::vector<Source*> rows;
  std::vector<std::uint32_t> previous;
  for (auto it = sources_.lower_bound({rescuer_id, 0});
       it != sources_.end() && it->first.first == rescuer_id; ++it) {
    if (!it->second.active) continue;
    rows.push_back(&it->second);
    // Unbound (silent for a while, or out of its keep gate a moment): the victim it was last
    // bound to. Seen live: a FOUND signal silent for 12 s came back to find a suspected repeat of
    // it in its place, opened a second FOUND victim, and the picture held one victim twice.
    previous.push_back(it->second.victim_id != 0 ? it->second.victim_id : it->second.last_victim_id);
    unbind(it->second, Unbind::kReassociated);
  }
  if (rows.empty()) return;

  // Each victim without this rescuer: CI of the other rescuers' sources (a FOUND victim: their
  // finders'), else its last fused position (a FOUND victim's dig site: its finder coming back
  // rejoins it however far another source has drifted).
  const std::size_t nv = victims_.size(), k = rows.size();
  std::vector<GaussianPosition> excl(nv);
  for (std::size_t j = 0; j < nv; ++j) {
    if (victims_[j].state == VictimState::kRecovered) continue;  // takes no source (excl unused)
    const std::vector<GaussianPosition> others = victims_[j].state == VictimState::kFound
                                                     ? finder_positions(victims_[j], rescuer_id)
                                                     : bound_positions(victims_[j], rescuer_id);
    excl[j] = others.empty() ? victims_[j].position
                             : covariance_intersection(others, config_.weighting).fused;
  }
  Eigen::MatrixXd cost = Eigen::MatrixXd::Constant(static_cast<Eigen::Index>(k),
                                                   static_cast<Eigen::Index>(nv + k), kInfeasible);
  for (std::size_t i = 0; i < k; ++i) {
    // A signal its device located stays with its victim while inside the keep gate: the best
    // evidence of where that victim is never gives its place to a newcomer of the same rescuer
    // (seen live: r3's split of C took C's place, and r3's FOUND of C opened a second C).
    const std::optional<SourceState> st = confirming_state(*rows[i]);
    const bool located = st && *st >= SourceState::kLocated;
    bool stays = false;
    for (std::size_t j = 0; j < nv; ++j) {
      if (rows[i]->estimate.floor != victims_[j].floor || victims_[j].state == VictimState::kRecovered) continue;
      const double d2 = mahalanobis2(rows[i]->estimate.position, excl[j]);
      if (previous[i] == victims_[j].victim_id && d2 <= keep_gate_) {
        cost(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = located ? 0.0 : d2 * gate_ / keep_gate_;
        stays = located;
      } else if (d2 <= gate_) {
        cost(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = d2;
      }
    }
    // Its private "new victim" column; a located signal that can stay has none.
    cost(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(nv + i)) = stays ? kInfeasible : gate_;
  }
  const std::vector<int> col = solve_assignment(cost);

  std::set<std::uint32_t> touched;
  for (std::size_t i = 0; i < k; ++i) {
    const int c = col[i];
    if (c >= 0 && static_cast<std::size_t>(c) < nv) {
      bind(*rows[i], victims_[static_cast<std::size_t>(c)]);
      touched.insert(victims_[static_cast<std::size_t>(c)].victim_id);
    } else {  // its private "new victim" column
      FusedVictim v;
      v.victim_id = next_id_++;
      v.position = rows[i]->estimate.position;
      v.floor = rows[i]->estimate.floor;
      v.first_seen = rows[i]->estimate.stamp;
      v.last_update = rows[i]->estimate.stamp;
      victims_.push_back(v);  // ids increase: stays sorted
      bind(*rows[i], victims_.back());
      touched.insert(v.victim_id);
    }
  }
  for (std::uint32_t id : touched) refuse(*find_victim(id));
}

void VictimFusion::merge_victims() {
  for (;;) {
    double best = std::numeric_limits<double>::infinity();
    std::size_t bi = 0, bj = 0;
    for (std::size_t i = 0; i < victims_.size(); ++i)
      for (std::size_t j = i + 1; j < victims_.size(); ++j) {
        if (victims_[i].floor != victims_[j].floor) continue;
        if (victims_[i].state == VictimState::kRecovered || victims_[j].state == VictimState::kRecovered) continue;
        if (kept_apart(victims_[i], victims_[j])) continue;
        // Two FOUND victims are two dig sites, each stood over by a device: merged only when
        // every pair of their sources names one transmitter (a merge by position alone sent the
        // diggers to neither of two victims 1.5 m apart: seen live under load, four within 5 m).
        if (victims_[i].state == VictimState::kFound && victims_[j].state == VictimState::kFound &&
            !one_transmitter(victims_[i], victims_[j]))
          continue;
        const double d2 = mahalanobis2(victims_[i].position, victims_[j].position);
        if (d2 <= merge_gate_ && d2 < best && !same_rescuer_conflict(victims_[i], victims_[j])) {
          best = d2;
          bi = i;
          bj = j;
        }
      }
    if (!std::isfinite(best)) return;
    merge_into(victims_[bi].victim_id, victims_[bj].victim_id);  // the lower id survives
  }
}

void VictimFusion::merge_into(std::uint32_t keep_id, std::uint32_t gone_id) {
  const auto gone_it = std::find_if(victims_.begin(), victims_.end(),
                                    [&](const FusedVictim& v) { return v.victim_id == gone_id; });
  FusedVictim gone = *gone_it;
  victims_.erase(gone_it);
  withdrawn_.erase(gone_id);
  FusedVictim& keep = *find_victim(keep_id);
  for (const VictimSource& vs : gone.sources) {
    Source& s = sources_.at({vs.rescuer_id, vs.signal_id});
    s.victim_id = 0;
    bind(s, keep);
  }
  // A FOUND victim's position is its dig site (see refuse()): it is what the merged one keeps.
  const bool keep_found = keep.state == VictimState::kFound, gone_found = gone.state == VictimState::kFound;
  if (gone_found && !keep_found)
    keep.position = gone.position;
  else if (keep_found == gone_found && keep.sources.empty())
    keep.position = covariance_intersection({keep.position, gone.position}, config_.weighting).fused;
  keep.state = std::max(keep.state, gone.state);
  refuse(keep);
  keep.first_seen = earliest_set(keep.first_seen, gone.first_seen);
  keep.last_update = std::max(keep.last_update, gone.last_update);
  keep.located_at = earliest_set(keep.located_at, gone.located_at);
  keep.found_at = earliest_set(keep.found_at, gone.found_at);
  for (FusedVictim& other : victims_)
    if (other.possibly_same_as == gone_id) other.possibly_same_as = other.victim_id != keep_id ? keep_id : 0;
  removed_.push_back(gone_id);
}

bool VictimFusion::one_transmitter(const FusedVictim& a, const FusedVictim& b) const {
  if (a.sources.empty() || b.sources.empty()) return false;
  for (const VictimSource& x : a.sources)
    for (const VictimSource& y : b.sources) {
      if (x.rescuer_id == y.rescuer_id) return false;  // one receiver's two signals: its repeat test decides
      const auto& sx = sources_.at({x.rescuer_id, x.signal_id}).estimate.transmitter;
      const auto& sy = sources_.at({y.rescuer_id, y.signal_id}).estimate.transmitter;
      if (compare_signatures(sx, sy, config_.gate_probability, true) != SignatureMatch::kAlike) return false;
    }
  return true;
}

std::pair<responder::RepeatState, std::uint32_t> VictimFusion::repeat_claim(const Source& s) const {
  // Only estimators heard within the source timeout of the newest: a stopped one's last word
  // (a daemon killed while it suspected a repeat) must not hold the source down for good.
  const auto window = seconds_to_ns(config_.source_timeout_s);
  std::pair<responder::RepeatState, std::uint32_t> claim{s.estimate.repeat, s.estimate.repeat_of_signal};
  for (const auto& [name, e] : s.by_estimator)
    if (e.repeat > claim.first && e.stamp >= s.estimate.stamp - window) claim = {e.repeat, e.repeat_of_signal};
  return claim;
}

void VictimFusion::merge_confirmed_repeats() {
  for (auto& [key, s] : sources_) {
    const auto [repeat, of] = repeat_claim(s);
    if (repeat != responder::RepeatState::kConfirmed || s.last_victim_id == 0) continue;
    const FusedVictim* left = find_victim(s.last_victim_id);
    const auto original = sources_.find({key.first, of});
    if (left == nullptr || !left->sources.empty() || original == sources_.end()) continue;
    const std::uint32_t into = original->second.victim_id != 0 ? original->second.victim_id
                                                               : original->second.last_victim_id;
    if (into == 0 || into == left->victim_id || find_victim(into) == nullptr) continue;
    merge_into(into, left->victim_id);
  }
}

std::optional<SourceState> VictimFusion::confirming_state(const Source& s) const {
  if (repeat_claim(s).first != responder::RepeatState::kNone) return std::nullopt;  // may be another's
  if (!config_.confirm_requires_device) return s.estimate.state;
  const auto window = seconds_to_ns(config_.source_timeout_s);
  const SourceEstimate* device = nullptr;
  for (const auto& [name, e] : s.by_estimator)
    if (e.from_device && (device == nullptr || e.stamp > device->stamp)) device = &e;
  if (device == nullptr || device->state < SourceState::kConverged) return std::nullopt;
  if (std::llabs(s.estimate.stamp - device->stamp) > window) return std::nullopt;
  return device->state;
}

const FusedVictim* VictimFusion::indistinct_twin(const FusedVictim& v) const {
  // merge_victims() ran first: any other victim still inside the merge gate was kept apart by
  // a rescuer with a signal in each.
  const FusedVictim* twin = nullptr;
  double closest = merge_gate_;
  for (const FusedVictim& u : victims_) {
    if (u.victim_id == v.victim_id || u.floor != v.floor || u.state == VictimState::kRecovered) continue;
    const double d2 = mahalanobis2(v.position, u.position);
    if (d2 <= closest) {
      closest = d2;
      twin = &u;
    }
  }
  return twin;
}

const FusedVictim* VictimFusion::alike_transmitter(const FusedVictim& v) const {
  // A device's LOCATED or FOUND, now or once (not the fused radius alone), says where the
  // transmitter is: such a victim is named first, whatever the order the victims are judged in.
  auto stood_by = [&](const FusedVictim& u) {
    if (u.state >= VictimState::kLocated && by_radius_only_.count(u.victim_id) == 0) return true;
    return std::any_of(u.sources.begin(), u.sources.end(), [&](const VictimSource& vs) {
      const auto st = confirming_state(sources_.at({vs.rescuer_id, vs.signal_id}));
      return st && (*st == SourceState::kLocated || *st == SourceState::kFound);
    });
  };
  const FusedVictim* alike = nullptr;
  for (const FusedVictim& u : victims_) {
    if (u.victim_id == v.victim_id || u.state == VictimState::kRecovered || !one_transmitter(v, u)) continue;
    if (stood_by(u)) return &u;
    if (alike == nullptr) alike = &u;
  }
  return alike;
}

void VictimFusion::update_states(TimestampNs now) {
  for (FusedVictim& v : victims_) {
    if (v.state == VictimState::kRecovered) continue;       // final
    if (!v.sources.empty()) withdrawn_.erase(v.victim_id);  // judged afresh on what binds now
    v.evidence_conflict =
        withdrawn_.count(v.victim_id) != 0 || std::any_of(sources_.begin(), sources_.end(), [&](const auto& kv) {
          return kv.second.last_victim_id == v.victim_id && now < kv.second.conflict_until;
        });
    // Confirmed by nothing but conflicted sources: the picture cannot stand by it.
    if (v.evidence_conflict && v.sources.empty() && v.state != VictimState::kUnconfirmed) {
      v.state = VictimState::kUnconfirmed;
      v.located_at = 0;
      v.found_at = 0;
    }
    if (v.sources.empty()) {
      if (v.possibly_same_as != 0 && find_victim(v.possibly_same_as) == nullptr) v.possibly_same_as = 0;
      continue;
    }
    // A reporter cannot tell every source here from another signal of its own: possibly one
    // transmitter seen twice, which the picture cannot stand by either.
    v.possibly_same_as = 0;
    bool all_repeats = true;
    for (const VictimSource& vs : v.sources) {
      const auto [repeat, of] = repeat_claim(sources_.at({vs.rescuer_id, vs.signal_id}));
      if (repeat == responder::RepeatState::kNone) {
        all_repeats = false;
        continue;
      }
      const auto original = sources_.find({vs.rescuer_id, of});
      if (original == sources_.end()) continue;
      const std::uint32_t there = original->second.victim_id != 0 ? original->second.victim_id
                                                                  : original->second.last_victim_id;
      if (there != v.victim_id) v.possibly_same_as = there;
    }
    if (all_repeats && v.state != VictimState::kUnconfirmed) {
      v.state = VictimState::kUnconfirmed;
      v.located_at = 0;
      v.found_at = 0;
    }
    VictimState target = VictimState::kUnconfirmed;
    std::size_t corroborating = 0;  // rescuers whose device stands by a bound source (one source each)
    for (const VictimSource& vs : v.sources) {
      const std::optional<SourceState> st = confirming_state(sources_.at({vs.rescuer_id, vs.signal_id}));
      if (!st) continue;
      ++corroborating;
      if (*st == SourceState::kFound) target = VictimState::kFound;
      else if (*st == SourceState::kLocated) target = std::max(target, VictimState::kLocated);
    }
    // A victim inside another's merge gate, kept apart only because one rescuer has a signal in
    // each, may be one transmitter that every such rescuer's separation split in two: the
    // picture cannot tell. Unless a device's own LOCATED or FOUND stands by it, it says so
    // (possibly_same_as), the fused radius does not confirm it, and a confirmation that rested
    // on the fused radius alone is withdrawn (never one a device gave: its finder may have
    // walked on). Seen live (four within 5 m, clean seed 1): three devices each held two signals
    // of one victim, and incident command confirmed it twice, 0.56 m apart.
    const FusedVictim* twin = nullptr;
    if (target == VictimState::kUnconfirmed) {
      twin = indistinct_twin(v);
      if (twin == nullptr) twin = alike_transmitter(v);
    }
    if (target != VictimState::kUnconfirmed) {
      by_radius_only_.erase(v.victim_id);
    } else if (twin != nullptr) {
      if (v.possibly_same_as == 0) v.possibly_same_as = twin->victim_id;
      if (by_radius_only_.erase(v.victim_id) > 0 && v.state != VictimState::kUnconfirmed) {
        v.state = VictimState::kUnconfirmed;
        v.located_at = 0;
        v.found_at = 0;
      }
    } else if (corroborating >= 2 && radius95_3d(v.position.covariance) < config_.located_radius_m) {
      // Two rescuers' devices agreeing: one device's own estimate confirms with its own state,
      // whose LOCATED also asks its samples to agree; its radius alone is overconfident near a
      // victim (docs/estimation/avalanche.md, "Left"), a split signal's too.
      target = VictimState::kLocated;
      if (v.state == VictimState::kUnconfirmed) by_radius_only_.insert(v.victim_id);
    }
    const bool found_before = v.state == VictimState::kFound;
    v.state = std::max(v.state, target);  // never backwards
    if (v.state >= VictimState::kLocated && v.located_at == 0) v.located_at = now;
    if (v.state >= VictimState::kFound && v.found_at == 0) v.found_at = now;
    if (!found_before && v.state == VictimState::kFound) refuse(v);  // found now: its finders' word from here on
  }
}

void VictimFusion::step(TimestampNs now) {
  // 1. activity.
  const double timeout_ns = config_.source_timeout_s * 1e9;
  for (auto& [key, s] : sources_) {
    const TimestampNs heard = std::max(s.estimate.stamp, s.estimate.received);
    s.active = s.estimate.state >= SourceState::kConverged && static_cast<double>(now - heard) <= timeout_ns &&
               (now >= s.conflict_until || !s.trusted.empty()) &&
               repeat_claim(s).first != responder::RepeatState::kConfirmed;
    if (!s.active) unbind(s, Unbind::kInactive);
  }
  // A LOCATED victim's only source that jumped outside the keep gate of where it located the
  // victim no longer stands by it: re-associated (see Withdrawal), not followed 29 m.
  for (FusedVictim& v : victims_) {
    if (v.state != VictimState::kLocated || v.sources.size() != 1) continue;
    Source& s = sources_.at({v.sources[0].rescuer_id, v.sources[0].signal_id});
    if (mahalanobis2(s.estimate.position, v.position) > keep_gate_) unbind(s, Unbind::kReassociated);
  }
  for (FusedVictim& v : victims_) refuse(v);

  // 2. keep test: drop the worst source outside the keep gate, one at a time.
  for (FusedVictim& v : victims_) {
    while (v.sources.size() >= 2 && v.state != VictimState::kRecovered) {
      double worst = -1.0;
      Source* worst_src = nullptr;
      for (const VictimSource& vs : v.sources) {
        Source& s = sources_.at({vs.rescuer_id, vs.signal_id});
        const std::vector<GaussianPosition> others = bound_positions(v, vs.rescuer_id);
        const double d2 = mahalanobis2(s.estimate.position,
                                       covariance_intersection(others, config_.weighting).fused);
        if (d2 > worst) {
          worst = d2;
          worst_src = &s;
        }
      }
      if (worst <= keep_gate_) break;
      unbind(*worst_src, Unbind::kReassociated);
      refuse(v);
    }
  }

  // 3. association, per rescuer with an unbound active source.
  std::map<std::string, std::pair<std::size_t, bool>> rescuers;  // active count, needs work
  for (const auto& [key, s] : sources_) {
    if (!s.active) continue;
    auto& r = rescuers[key.first];
    ++r.first;
    if (s.victim_id == 0) r.second = true;
  }
  std::vector<std::pair<std::size_t, std::string>> order;
  for (const auto& [id, r] : rescuers)
    if (r.second) order.emplace_back(r.first, id);
  std::stable_sort(order.begin(), order.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  for (const auto& [count, id] : order) associate_rescuer(id, now);

  withdraw_contradicted();
  // Ghosts of a wrong association: unconfirmed, and their last source went elsewhere (a
  // withdrawn victim stays: a device once stood by it).
  for (std::uint32_t id : orphaned_) {
    FusedVictim* v = find_victim(id);
    if (v == nullptr || !v->sources.empty() || v->state != VictimState::kUnconfirmed) continue;
    if (withdrawn_.count(id) != 0) continue;
    removed_.push_back(id);
    victims_.erase(victims_.begin() + (v - victims_.data()));
  }
  orphaned_.clear();

  // 4./5. fusion is up to date; merge duplicates.
  merge_confirmed_repeats();
  merge_victims();
  // 6. states.
  update_states(now);
}

}  // namespace sarloc::incident
