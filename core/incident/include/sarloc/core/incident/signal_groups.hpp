#pragma once
// Which rescuers hear one transmitter before anyone has placed it (issue 63, item 3): the
// standard practice hands a signal to one rescuer as soon as he takes it, long before any
// filter converges, and incident command can do the same by the transmitter's signature
// (carrier offset and pulse period, which every receiver measures alike within its stated
// sigmas; responder::compare_signatures).
//
// Conservative by construction: a signal whose signature could be two transmitters' is in no
// group (a partly known signature whose known part agrees counts as could-be), so that a wrong
// group only ever delays a victim for a bounded time (signal_pursuit.hpp), never hides one.
//   - a signal not yet placed (its estimate below CONVERGED) joins a fused victim when its
//     signature is alike (carrier and period both known and within the gate) with every
//     source of that victim that has one, with no source of any other victim and with no
//     other signal placed or not of its own rescuer; and its rescuer has no other such signal;
//   - the signals not placed and not joined form groups: signals of different rescuers whose
//     signatures are alike, pairwise, one signal per rescuer, none alike with a placed signal
//     or with another signal of its own rescuer.
//
//   const SignalGroups groups = group_heard_signals(heard, victims, 0.999);
//   groups.joined[victim_id]   // rescuers' signals of that victim not yet placed
//   groups.unplaced            // each a transmitter heard by several, not yet placed
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "sarloc/core/incident/fused_victim.hpp"
#include "sarloc/core/responder/transmitter_signature.hpp"

namespace sarloc::incident {

/// One rescuer's signal as incident command last heard of it (any status).
struct HeardSignal {
  std::string rescuer_id;
  std::uint32_t signal_id = 0;
  responder::TransmitterSignature transmitter;
  /// Its estimate is CONVERGED or better: it is (or is about to be) a source of a fused victim.
  bool placed = false;
  /// When incident command first heard of it (the stamp of its first estimate): without
  /// distance readings, the first to take a signal keeps it.
  TimestampNs first_heard = 0;
  /// The distance its estimate reads (its top components' weighted mean range, as a
  /// transceiver's display reads one before any position); NaN when it states none.
  double range_m = std::numeric_limits<double>::quiet_NaN();
};

using SignalKey = std::pair<std::string, std::uint32_t>;  ///< (rescuer_id, signal_id)

struct SignalGroups {
  /// Per fused victim id: signals not yet placed that are that victim's transmitter.
  std::map<std::uint32_t, std::vector<HeardSignal>> joined;
  /// Transmitters heard by two or more rescuers and placed by none; each group's signals are of
  /// different rescuers, in order of first heard.
  std::vector<std::vector<HeardSignal>> unplaced;
  /// Every signal heard, grouped or not (one rescuer's alone, a signature that could be two).
  std::set<SignalKey> heard;
};

/// `gate_probability`: the signature gate (incident command's fusion.gate_probability).
SignalGroups group_heard_signals(const std::vector<HeardSignal>& heard, const std::vector<FusedVictim>& victims,
                                 double gate_probability);

}  // namespace sarloc::incident
