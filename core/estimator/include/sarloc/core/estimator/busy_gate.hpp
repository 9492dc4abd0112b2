#pragma once
// Whether the daemon is too busy to take on another responder.
//
// A daemon that admits every new responder while its workers already lag slows down everyone it
// serves: a filter's opening epochs (about 1700 mixture components) cost tens of times what a
// converged filter does, so a crowd of rescuers switching on at once can push every answer
// seconds late (docs/benchmarks.md, "Overload"). Two signs close the gate to new responders for
// `hold_s`: a worker busy for more than `max_utilisation` of the last status period (the
// early sign: it rises with the first samples of the responders just admitted), and a sample
// that waited longer than `max_wait_s` in a worker's queue (the late one, whatever the cause).
// Those already served are served on; a refused device guides on its own filter and is
// admitted by one of its samples once the gate is open again.
// Unless those served are more than the daemon can serve: a sample that waited longer than
// `shed_wait_s` (an answer that late is of use to no one: a device waits 0.25 s for guidance)
// says the served set itself is too much, and the daemon then releases the responder it
// admitted last (note_shed), at most one a second, until the waits fall back. Measured: 300
// rescuers and 200 firefighters on 2 cores, admitted while the gate was open, were answered up to
// 8 s late for minutes (docs/benchmarks.md, "A mixed incident on one daemon").
//
//   BusyGate gate(config.busy);
//   worker:        gate.note_wait(dequeued_at - queued_at, dequeued_at);
//                  if (gate.note_shed(dequeued_at - queued_at, dequeued_at)) release the newest;
//   status thread: gate.note_utilisation(busiest_worker_share, now);
//   listener:      roster.admit(id, now, gate.busy(now));
// Thread-safe (atomics): the workers note, the listener threads ask.
#include <atomic>
#include <chrono>
#include <cstdint>

namespace sarloc::estimator {

struct BusyGateConfig {
  /// A sample that waited longer than this in a worker's queue closes the gate (s); 0: never.
  double max_wait_s = 0.2;
  /// A worker busy for more than this share of a status period closes the gate; 0: never.
  double max_utilisation = 0.85;
  /// How long the gate stays closed after the last such wait (s).
  double hold_s = 5.0;
  /// A sample that waited longer than this (s) releases the responder admitted last; 0: never.
  double shed_wait_s = 2.0;

  /// Throws ConfigError naming the key ("core.busy_wait_s = -1: must be in [0, 10]").
  void validate() const;
};

class BusyGate {
 public:
  using Clock = std::chrono::steady_clock;

  explicit BusyGate(BusyGateConfig config);

  /// A sample waited `wait` in a worker's queue until `now`. Returns true when this wait
  /// closed a gate that was open (the caller logs it once).
  bool note_wait(Clock::duration wait, Clock::time_point now);
  /// The busiest worker was busy for this share of the last period, up to `now`. Returns true
  /// when it closed a gate that was open.
  bool note_utilisation(double share, Clock::time_point now);
  /// A sample waited `wait` until `now`: true when a responder is to be released for it (the
  /// wait is over shed_wait_s, and none was released in the second before `now`).
  bool note_shed(Clock::duration wait, Clock::time_point now);
  /// Whether new responders are refused at `now`.
  bool busy(Clock::time_point now) const;
  /// Times the gate closed from open.
  std::uint64_t closings() const { return closings_.load(); }
  const BusyGateConfig& config() const { return config_; }

 private:
  bool hold_closed_from(Clock::time_point now);

  BusyGateConfig config_;
  Clock::duration max_wait_;
  Clock::duration hold_;
  std::atomic<Clock::rep> busy_until_;
  std::atomic<std::uint64_t> closings_{0};
  std::atomic<Clock::rep> shed_at_;  ///< when a responder was last released for a wait
};

}  // namespace sarloc::estimator
