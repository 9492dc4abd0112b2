#pragma once
// On a responder's device: whose guidance to follow, the core daemon's or the device's own
// estimator's (its hot standby), and whether the daemon counts as reachable. Pure logic, fed
// by the device's DDS node with what the daemon said and when; one instance per device, used
// under the node's lock.
//
// Rules:
//   - the daemon is reachable while it answered within fallback_timeout_s (mission time), or,
//     before any answer, for fallback_timeout_s after the device started; never while every
//     core daemon's liveliness is lost (on_daemons_lost);
//   - a late answer to an older epoch never replaces a newer one (guidance and its sequence
//     stay a pair);
//   - the daemon's guidance is followed only as the answer to this very epoch, and only when
//     the daemon's estimate of the guided signal, for this same epoch, is at least as far
//     along (INITIALISING < MULTIMODAL < CONVERGED < LOCATED < FOUND) as the device's own of
//     the signal it would guide to: a restarted daemon with an empty filter is not followed;
//   - never when the two estimates of the guided signal conflict: both at least CONVERGED
//     for the same epoch (same frame G_k) and their difference outside chi2_3(0.999) with
//     summed covariances. They filter the same samples, so one of them is wrong (seen: after
//     a 37 s radio fade the daemon's filter settled LOCATED 7 m from the device's, which was
//     0.07 m from the victim). Conflicting signals are reported (ArbiterDecision), so that
//     the device publishes its own estimate next to the daemon's and incident command sees
//     the conflict instead of a confident guess;
//   - hysteresis: once the device guides on its own, it goes back to the daemon only after
//     the daemon passed every rule above for rejoin_epochs epochs in a row (the first answer
//     of a session is followed at once). Under packet loss the daemon misses single epochs;
//     without it the guidance flapped between two filters whose estimates differ a little,
//     and the rescuer zig-zagged;
//   - otherwise the device's own guidance, if any.
//
//   GuidanceArbiter arbiter(3.0, clock.now(), 3);
//   arbiter.on_daemon_guidance(g, seq, now, wall);            // from the reader callbacks
//   if (arbiter.worth_waiting()) wait until arbiter.answered(seq);
//   auto d = arbiter.decide({now, seq, wall_published, local_guidance, local_status});
#include <cstdint>
#include <functional>
#include <map>
#include <optional>

#include <set>
#include <vector>

#include "sarloc/core/responder/guidance.hpp"
#include "sarloc/core/responder/victim_estimate.hpp"

namespace sarloc::responder {

/// kPlan: no signal to follow, the search plan's strip (incident::strip_guidance; the device
/// node chooses it after the arbiter).
enum class GuidanceSource : std::uint8_t { kNone = 0, kDaemon = 1, kLocal = 2, kPlan = 3 };
const char* to_string(GuidanceSource source);

struct ArbiterInput {
  TimestampNs now = 0;             ///< mission time
  std::uint64_t sequence = 0;      ///< this epoch's measurement sequence (0: nothing measured)
  std::int64_t published_wall_ns = 0;  ///< when this epoch's samples were published (wall)
  std::optional<Guidance> local_guidance;
  /// The device's own status of a signal (kInitialising if never measured).
  std::function<EstimatorStatus(std::uint32_t)> local_status;
  /// The device's own estimates of this epoch (checked against the daemon's).
  std::vector<VictimEstimate> local_estimates;
};

struct ArbiterDecision {
  std::optional<Guidance> guidance;  ///< what to do now (nullopt: no signal yet)
  GuidanceSource source = GuidanceSource::kNone;
  bool daemon_reachable = false;
  bool daemons_lost = false;         ///< every core daemon's liveliness was lost
  bool fell_back = false;            ///< reachable at the previous epoch, not now
  bool reconnected = false;          ///< the daemon answered again after being unreachable
  /// The daemon's status of every signal, when its guidance is followed.
  std::map<std::uint32_t, EstimatorStatus> daemon_signals;
  double latency_ms = -1.0;          ///< publication -> this epoch's daemon guidance (wall), -1 if none
  /// Signals whose daemon estimate of this epoch conflicts with the device's own.
  std::set<std::uint32_t> conflicting_signals;
};

class GuidanceArbiter {
 public:
  /// Throws ConfigError unless fallback_timeout_s is in (0, 600] and rejoin_epochs in [1, 100].
  GuidanceArbiter(double fallback_timeout_s, TimestampNs started, int rejoin_epochs = 3);

  void on_daemon_guidance(const Guidance& guidance, std::uint64_t sequence, TimestampNs now, std::int64_t wall_ns);
  void on_daemon_estimate(std::uint32_t signal_id, EstimatorStatus status, std::uint64_t sequence, TimestampNs now,
                          const GaussianPosition& relative = {});
  /// A core daemon's status was seen alive / every one's liveliness was lost. A daemon that
  /// comes back starts from nothing, so its signal statuses are forgotten.
  void on_daemon_seen() { seen_daemon_ = true; daemons_lost_ = false; }
  void on_daemons_lost();

  /// Both halves of the daemon's answer to `sequence` arrived: guidance and its signal's estimate.
  bool answered(std::uint64_t sequence) const;
  /// Wait for the daemon's answer only while it is believed alive (or never answered yet):
  /// an unreachable one would make every epoch late.
  bool worth_waiting() const { return was_reachable_ || answered_at_ == 0; }

  /// The decision for one epoch; counts fallbacks.
  ArbiterDecision decide(const ArbiterInput& input);
  /// The daemon's estimate of local.signal_id for this same epoch conflicts with `local`
  /// (see the rules above).
  bool conflicts(const VictimEstimate& local, std::uint64_t sequence) const;
  int fallbacks() const { return fallbacks_; }
  /// Epochs whose guidance came from another source than the epoch before (daemon <-> device).
  int switches() const { return switches_; }

 private:
  struct SignalStatus {
    EstimatorStatus status = EstimatorStatus::kInitialising;
    std::uint64_t sequence = 0;  ///< the measurement it answers
    GaussianPosition relative;   ///< the daemon's estimate, G_k of that measurement
  };
  const SignalStatus* guided_signal_status() const;

  TimestampNs timeout_ns_;
  TimestampNs started_;
  int rejoin_epochs_;
  int daemon_streak_ = 0;             ///< epochs in a row the daemon's answer could be followed
  GuidanceSource followed_ = GuidanceSource::kNone;
  std::optional<Guidance> guidance_;
  std::uint64_t guidance_sequence_ = 0;
  TimestampNs guidance_at_ = 0;       ///< mission time it arrived
  std::int64_t guidance_wall_ns_ = 0;
  TimestampNs answered_at_ = 0;       ///< mission time of the daemon's last answer (0: never)
  std::map<std::uint32_t, SignalStatus> status_;
  bool seen_daemon_ = false;
  bool daemons_lost_ = false;
  bool was_reachable_ = false;
  int fallbacks_ = 0;
  int switches_ = 0;
};

}  // namespace sarloc::responder
