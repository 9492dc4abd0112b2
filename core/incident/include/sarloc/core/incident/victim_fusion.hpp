#pragma once
// Multi-rescuer victim fusion for incident command (docs/estimation/incident-fusion.md).
//
// Every reporter (today a rescuer's device, per separated beacon signal; later a robot's camera
// or a dog team) publishes victim estimates relative to itself. Placed in the incident frame
// with the reporter's fix (source_estimate.hpp) each one is a SOURCE, keyed by (rescuer_id,
// signal_id); update() keeps the newest estimate per source.
// step(now) turns the sources into VICTIMS with stable ids:
//
//   1. activity: a source takes part only while its state >= kConverged (a multimodal mixture
//      mean is meaningless) and it was heard (SourceEstimate::received, else its stamp) within
//      source_timeout_s; an inactive source is unbound, its victim keeps its last fused
//      position and state;
//   2. keep: a bound source stays bound while its Mahalanobis d^2 to the CI fusion of the
//      victim's OTHER sources, with summed covariances, is inside the keep gate
//      (chi2_3(keep_gate_probability)); otherwise it is unbound. A LOCATED victim's only
//      source is held to the victim's last fused position the same way;
//   3. associate: for each rescuer with an unbound active source (most active sources first,
//      then by id), ALL its active sources are re-solved together against every victim,
//      fused without that rescuer: cost d^2 (summed covariances) if inside the gate
//      (chi2_3(gate_probability); the keep gate, scaled down to the gate, for the pair that
//      was bound before: hysteresis), forbidden otherwise; one private "new victim" column per
//      source at cost = gate; minimum-cost assignment (assignment.hpp). A source its device
//      LOCATED or FOUND that was last bound to a victim (also when unbound since: silent a
//      while) and is inside its keep gate stays or returns there (cost 0, no "new victim"
//      column): a newcomer of the same rescuer that fits the
//      other rescuers' estimates better never takes its place (seen live: r3's split of C took
//      victim 2 from r3's FOUND of C, which opened a second FOUND C). Solving one rescuer's
//      signals jointly is what separates close victims: the rescuer's common GNSS bias moves
//      all its signals together, and swapping two signals always costs 2 s^2 / S more than the
//      right assignment (s = separation). Same-rescuer different-signal sources can never share
//      a victim: distinct columns inside one assignment, and victims holding another signal of
//      that rescuer are not candidates;
//   4. fuse: a victim's position = covariance intersection of its bound sources; a FOUND
//      victim's = that of its bound sources whose device stands over it (confirming state
//      kFound), and where it was last so fused once none is bound: later sources never move a
//      dig site (step 3 gates against the same: its finders', else that dig site);
//   5. merge: two victims whose fused estimates are inside each other's gate (d^2 with summed
//      covariances <= chi2_3(merge_gate_probability)) and that hold no two sources of the same
//      rescuer are merged, closest pair first; the lower id survives, the other is reported by
//      take_removed(). Two FOUND victims (two dig sites) merge only when every pair of their
//      sources (different rescuers) has alike transmitter signatures, carrier and period
//      (responder/transmitter_signature.hpp): one transmitter stood over twice. Two confirmed
//      victims never merge once one of them has lost every source (nothing new says they are
//      one).
//      An unconfirmed victim that lost all its sources to re-association (never
//      to a timeout) is a ghost of a wrong association and is removed the same way;
//   Withdrawal: a LOCATED (never a FOUND) victim left without sources, one of whose former
//      sources is now bound to another victim (its own reporter estimates that signal
//      elsewhere), goes back to kUnconfirmed and carries evidence_conflict until a source binds
//      to it again: nothing stands by it and its own evidence says elsewhere, so the picture
//      says so rather than keep confirming it (seen in CI: a device LOCATED a signal 39 m away
//      with a 3.9 m radius, 29 m from any victim, then found the victim with that signal; the
//      picture kept a confirmed victim where nobody was buried). It is kept as an unconfirmed
//      contact, not removed: a device once stood by it. take_withdrawn() names each one once;
//   Repeats (one transmitter split into two signals by a reporter's separation: the reporter
//      says so, VictimEstimate::repeat, from the latest estimate of any of its estimators):
//      a SUSPECTED repeat fuses as usual but confirms nothing; a victim whose every bound source
//      is one goes back to kUnconfirmed and names the victim of the signal it may repeat
//      (possibly_same_as). A CONFIRMED repeat is inactive; the victim it leaves without sources
//      is merged into the victim of the signal it repeats (the reporter stood over both).
//   Dug out (recover()): a FOUND victim becomes kRecovered and keeps its last fused position and
//      the sources it lists (who found it). Every source bound to it, or last bound to it, is
//      retired: its estimates are ignored from then on (its transmitter is off; a device may
//      still republish its last FOUND). A recovered victim takes no source, never merges and
//      is nobody's twin: a signal still heard there is a new, unknown victim.
//      Late echoes: a source never bound to any victim (first heard by this fusion only now:
//      a radio fade or a link loss kept it, or erased it) whose first estimate was measured no
//      later than dug_out_grace_s after the recovery, inside a recovered victim's gate and
//      within kDugOutReachM of it, with no transmitter signature distinct from the recovered
//      victim's sources', heard that switched-off transmitter before it went off: it is
//      retired too. Seen under fades (large-deposit.yaml): the picture lost r7's source of C
//      in a fade, C was dug out, r7's FOUND of C (stamped before) came back and opened a
//      second FOUND victim at the hole. One first heard later is another transmitter.
//   Sources and victims on different floors never associate or merge (a victim's floor is
//      that of its first source).
//   Conflicts: a source is estimated by more than one estimator (a rescuer's device and the
//      core daemon filter the same samples). When their latest estimates (both >= kConverged,
//      within source_timeout_s of each other) are outside each other's keep gate, the source
//      is conflicted for source_timeout_s and the victim it was bound to carries
//      evidence_conflict. If one of them was computed on the reporter's own device
//      (from_device: it saw every sample) and the other not, the source follows the device's
//      estimates only; otherwise it is treated as inactive (fuses and confirms nothing) and a
//      victim confirmed only by conflicted sources goes back to kUnconfirmed.
//      The device's own kLocated / kFound holds its source whatever the stamps: a daemon
//      estimate never replaces it, and it replaces a newer daemon estimate. Seen under fades:
//      the daemon restarted its filter (motion unknown for > 10 s) next to a victim the device
//      had FOUND, its fresh filter claimed kConverged 10 m off, and its newer stamps kept the
//      device's FOUND (republished with the stamp of the epoch it was found in) out. Seen under radio
//      fades: the daemon's filter LOCATED 7 m from the device's, which was 0.07 m from the
//      victim, and incident command confirmed ghosts from the daemon's copy.
//   6. state: kLocated when a bound source is kLocated or kFound or the fused 95 % radius
//      (worst axis) is below located_radius_m with corroborated sources of two rescuers (one
//      device's estimate confirms with its own state only: its radius alone is overconfident
//      near a victim); kFound when a bound source is kFound; states
//      never go back. located_at / found_at are set once (to `now`).
//      Twins: a victim inside another's merge gate (kept apart by the same-rescuer rule: possibly
//      one transmitter every such rescuer split into two signals) that no device's own LOCATED
//      or FOUND stands by names it (possibly_same_as), is not confirmed by the fused radius, and
//      loses a confirmation that rested on the fused radius alone. So does a victim that no
//      device's LOCATED or FOUND stands by and whose sources' transmitter signatures are alike
//      those of another victim's sources (other rescuers, carrier and period), however far
//      apart: one transmitter, most likely; it names one a device stands by if there is one,
//      which the unconfirmed one placed wrongly, else the other is as unconfirmed as it (seen in
//      the restart mission: r1's filter of C's signal, fed only pulses at the detection floor
//      from 45-50 m, converged 48 m from C, stated 95 % radius 1.45 m, and stayed there).
//      Only CORROBORATED sources confirm (confirm_requires_device, the default): a source
//      whose reporter's own device (from_device: every sample, no network in between) sent an
//      estimate of at least kConverged within source_timeout_s of the source's newest. Its
//      state for confirmation is the device's, and the radius rule needs one such source bound.
//      A source known only through the core daemon's copy fuses and shows where a victim may
//      be, but confirms nothing: under radio fades the daemon misses samples and was seen
//      LOCATED 12 m from any victim with nothing to compare it against.
//
// Cost per step: O(S) for activity and fusion, O(k^2) per victim for the keep test, and for
// each rescuer that needs association O(S + V) gate tests and an O(k^2 (V + k)) assignment
// (k = that rescuer's sources). The merge search is over victim pairs (V <= ~50).
//
// Hot standby (docs/operations.md, "Incident command that cannot be lost"): a second
// incident command feeds update() with the same estimates and, every cycle, adopt()s the
// picture the active one publishes and then step()s as the active one would. Nothing of it is
// published until it takes over; then it continues from that picture: the same ids, states
// and timestamps, no victim opened twice, and what it fused itself since the active one's
// last picture (e.g. a FOUND heard while the active one was already dead) is not lost.
//
//   VictimFusion fusion(VictimFusionConfig{});      // config validated here
//   fusion.update(make_source_estimate(estimate, antenna_at(estimate.stamp)));
//   fusion.step(now);
//   for (const FusedVictim& v : fusion.victims()) ...;
//   for (std::uint32_t id : fusion.take_removed()) dispose(id);
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "sarloc/core/common/types.hpp"
#include "sarloc/core/incident/covariance_intersection.hpp"
#include "sarloc/core/incident/fused_victim.hpp"
#include "sarloc/core/incident/source_estimate.hpp"

namespace sarloc::incident {

/// Every parameter of VictimFusion (docs/estimation/incident-fusion.md, parameter table).
struct VictimFusionConfig {
  double gate_probability = 0.999;        ///< association gate: d^2 <= chi2_3(p) (16.27)
  double keep_gate_probability = 0.9999;  ///< looser gate to keep a binding (21.11), >= gate
  double merge_gate_probability = 0.99;   ///< two victims closer than chi2_3(p) may merge
  double source_timeout_s = 10.0;         ///< sources older than this leave the fusion
  double located_radius_m = 1.0;          ///< fused 95 % radius (worst axis) that means located
  CiWeighting weighting = CiWeighting::kInverseTrace;  ///< covariance intersection weights
  /// Only sources corroborated by their reporter's own device confirm a victim (step 6).
  bool confirm_requires_device = true;
  /// A new source measured up to this long after a dig-out, at the hole, heard the dug-out
  /// transmitter ("Late echoes" above): the rescuer reports the dig and switches its
  /// transmitter off within about this time.
  double dug_out_grace_s = 10.0;

  /// Throws ConfigError "fusion.<key> = value: rule".
  void validate() const;
};

/// A late echo of a dug-out transmitter ("Late echoes" above) lies within this distance (m)
/// of its victim: a FOUND estimate well inside it, a second victim seldom.
inline constexpr double kDugOutReachM = 3.0;

/// Throws InputError unless `v` can join a fusion: id > 0, finite position, symmetric
/// positive-definite covariance, sources with a rescuer id.
void check_adoptable(const FusedVictim& v);

class VictimFusion {
 public:
  explicit VictimFusion(VictimFusionConfig config = {});

  /// Stores or replaces the newest estimate of (rescuer_id, signal_id). Returns false (and
  /// ignores it) if older than the stored one. Throws InputError for an empty rescuer_id, a
  /// non-finite position, a covariance that is not symmetric positive definite, or, for a
  /// below_surface source, a position more than 5 sigma above the snow surface (z > 0).
  bool update(const SourceEstimate& estimate);

  /// Forgets every signal of a rescuer (e.g. its estimates were declared stale). Its victims
  /// keep their last fused position and state. Returns the number of sources removed.
  std::size_t remove_source(const std::string& rescuer_id);
  /// Forgets one signal of a rescuer. Returns whether it existed.
  bool remove_source(const std::string& rescuer_id, std::uint32_t signal_id);

  /// Associate, fuse, merge and update states (see the overview above).
  void step(TimestampNs now);

  /// Marks a FOUND victim dug out at `at` (mission time; see "Dug out" above). Throws
  /// InputError, changing nothing, for an unknown id or a victim that is not FOUND; a victim
  /// already recovered stays so (returns false).
  bool recover(std::uint32_t victim_id, TimestampNs at);
  /// Sources retired by recover() (or adopted as a recovered victim's).
  std::size_t retired_count() const { return retired_.size(); }

  /// Makes `picture` (another incident command's published victims) this fusion's victims
  /// (a recovered one's sources retired):
  /// ids, positions, floors, states, first_seen / last_update / located_at / found_at and
  /// evidence_conflict as published, except that a victim of the previous adopted picture that
  /// step() has since advanced further keeps its further state (and the time it got there):
  /// states never go back. Victims this fusion opened itself are dropped (never published: the
  /// picture has them, or step() opens them again). Each source the picture lists is bound to
  /// its victim (a source not heard yet is bound when its first estimate arrives). Nothing is
  /// fused here. Victims opened later get ids after the largest of the picture and
  /// `largest_id_seen` (ids disposed of earlier stay unused). Throws InputError (and changes
  /// nothing) for a victim that check_adoptable() refuses or an id listed twice.
  void adopt(const std::vector<FusedVictim>& picture, std::uint32_t largest_id_seen = 0);
  /// The id the next new victim gets.
  std::uint32_t next_id() const { return next_id_; }

  /// Current victims, stable ids (from 1), sorted by id.
  const std::vector<FusedVictim>& victims() const { return victims_; }
  /// The victim of that id, nullptr when there is none.
  const FusedVictim* victim(std::uint32_t id) const;
  /// The ids of the victims FOUND now (not dug out yet).
  std::set<std::uint32_t> found_ids() const;
  /// Ids removed (merged away or ghosts) since the last call; the caller disposes of them.
  std::vector<std::uint32_t> take_removed();

  /// A LOCATED victim withdrawn (see "Withdrawal" above) and the source that now says elsewhere.
  struct Withdrawal {
    std::uint32_t victim_id = 0;
    std::string rescuer_id;
    std::uint32_t signal_id = 0;
    std::uint32_t now_bound_to = 0;  ///< the victim that source is bound to now
  };
  /// The withdrawals since the last call.
  std::vector<Withdrawal> take_withdrawn();

  /// A source retired as a late echo of a dug-out victim's transmitter ("Late echoes" above).
  struct LateEcho {
    std::uint32_t victim_id = 0;  ///< the dug-out victim
    std::string rescuer_id;
    std::uint32_t signal_id = 0;
    TimestampNs measured = 0;  ///< its first estimate's stamp
  };
  /// The late echoes since the last call.
  std::vector<LateEcho> take_late_echoes();

  const VictimFusionConfig& config() const { return config_; }
  std::size_t source_count() const { return sources_.size(); }

 private:
  using SourceKey = std::pair<std::string, std::uint32_t>;
  struct Source {
    SourceEstimate estimate;            ///< the newest, whichever estimator
    std::uint32_t victim_id = 0;        ///< 0 = unbound
    std::uint32_t last_victim_id = 0;   ///< the victim it was last bound to
    bool active = false;
    std::map<std::string, SourceEstimate> by_estimator;  ///< the latest of each estimator
    TimestampNs first_stamp = 0;                         ///< of the first estimate this fusion heard
    TimestampNs conflict_until = 0;     ///< conflicted until then
    std::string trusted;                ///< while conflicted: the device's estimator, if any
  };
  enum class Unbind : std::uint8_t { kInactive, kReassociated };

  FusedVictim* find_victim(std::uint32_t id);
  std::vector<GaussianPosition> bound_positions(const FusedVictim& v,
                                                const std::string& except_rescuer) const;
  void bind(Source& s, FusedVictim& v);
  /// A recovered victim's source: forgotten, and its estimates ignored from now on.
  void retire(const SourceKey& key);
  /// A dug-out victim: when, and the transmitter signatures its sources measured.
  struct Recovery {
    TimestampNs at = 0;
    std::vector<responder::TransmitterSignature> transmitters;
  };
  /// "Late echoes": the recovered victim whose switched-off transmitter `s` heard, or 0.
  std::uint32_t dug_out_echo_of(const Source& s) const;
  void unbind(Source& s, Unbind reason);
  /// Bound sources of other rescuers whose device stands over the victim (confirming state
  /// kFound).
  std::vector<GaussianPosition> finder_positions(const FusedVictim& v, const std::string& except_rescuer) const;
  /// Step 4 for one victim: its position from its bound sources (a FOUND victim: its finders'
  /// only, unchanged without them) and its sources' last updates.
  void refuse(FusedVictim& v);
  void associate_rescuer(const std::string& rescuer_id, TimestampNs now);
  /// Every pair of sources, one in each (no rescuer in both), has alike transmitter signatures,
  /// carrier and period: one transmitter, as far as the receivers can tell.
  bool one_transmitter(const FusedVictim& a, const FusedVictim& b) const;
  void merge_victims();
  /// `gone`'s sources, states and times into `keep`; `gone` is erased and reported removed.
  void merge_into(std::uint32_t keep_id, std::uint32_t gone_id);
  /// Step 5 for confirmed repeats (see the overview).
  void merge_confirmed_repeats();
  /// The strongest repeat claim of the latest estimates of a source's estimators, of those
  /// within source_timeout_s of its newest.
  std::pair<responder::RepeatState, std::uint32_t> repeat_claim(const Source& s) const;
  void update_states(TimestampNs now);
  /// Withdrawal (see the overview) of the victims that contradicted_ names.
  void withdraw_contradicted();
  /// The closest other victim inside v's merge gate (one the same-rescuer rule keeps apart), or
  /// nullptr.
  const FusedVictim* indistinct_twin(const FusedVictim& v) const;
  /// Another victim (not dug out) whose transmitter v's sources heard too, by their signatures
  /// (one_transmitter), however far from v: one a device's LOCATED or FOUND stands by if any,
  /// else any such; nullptr if none.
  const FusedVictim* alike_transmitter(const FusedVictim& v) const;
  /// The state a source confirms with (step 6): its device's, nullopt if not corroborated.
  std::optional<SourceState> confirming_state(const Source& s) const;
  /// Records the estimate as its estimator's latest; marks the source conflicted when it
  /// disagrees with another estimator's.
  void check_conflict(Source& s, const SourceEstimate& estimate);

  VictimFusionConfig config_;
  double gate_ = 0.0, keep_gate_ = 0.0, merge_gate_ = 0.0;  ///< chi-square thresholds
  std::map<SourceKey, Source> sources_;
  std::vector<FusedVictim> victims_;          ///< sorted by id
  std::vector<std::uint32_t> removed_;
  std::vector<std::uint32_t> orphaned_;       ///< lost their last source to re-association
  std::vector<Withdrawal> contradicted_;      ///< a former source now bound elsewhere (this step)
  std::set<std::uint32_t> withdrawn_;         ///< withdrawn, no source bound since
  std::vector<Withdrawal> withdrawals_;       ///< not yet taken
  std::map<SourceKey, std::uint32_t> adopted_bindings_;  ///< adopted, source not heard yet
  std::set<std::uint32_t> adopted_ids_;      ///< victims of the last adopted picture
  std::set<std::uint32_t> by_radius_only_;   ///< confirmed by the fused radius, no device's word
  std::set<SourceKey> retired_;              ///< a recovered victim's: ignored for good
  std::map<std::uint32_t, Recovery> recoveries_;  ///< by victim id, kept across adopt()
  std::vector<LateEcho> late_echoes_;             ///< not yet taken
  /// Retires `key` as a late echo of `victim_id` and reports it.
  void retire_echo(const SourceKey& key, std::uint32_t victim_id);
  std::uint32_t next_id_ = 1;
};

}  // namespace sarloc::incident
