#pragma once
// Which responders a daemon keeps state for, and when that state goes.
//
// A daemon must not grow with whoever publishes on its topics: a hostile or misconfigured
// publisher cycling through 100,000 rescuer ids would otherwise create 100,000 estimators.
// The roster decides before a sample is queued (so refused samples cost a set look-up and
// never wait in a worker's queue ahead of real ones):
//   - roster mode (`open` false): only the listed responders are served, the mission's
//     roster of the daemon's sector; anything else is refused as unknown.
//   - open mode: any id, up to `max_responders` at once.
//   - either mode: no new id while the daemon is busy (busy_gate.hpp): its workers lag, and a
//     new filter's opening epochs would slow everyone already served; and at most
//     `new_per_s` new ids a second (a burst of as many), so that a crowd switching on at once
//     is admitted as fast as the busy signs can follow, not all before the first of them.
//   - a door start is the exception to both: the first step of a firefighter whose team
//     reported an entry (`door_starts`) is admitted however busy the daemon. Its filter starts
//     at the door with a tight cloud, the cheapest a firefighter's filter ever is; refused, the
//     entry is lost for good (the steps before admission are gone), and the same firefighter
//     admitted later starts near the device's reckoning or, without one, spread over the whole
//     plan: 20000 particles, ten times the cost a step, and a search of the building for where
//     he is. The roster's other limits (max_responders, the listed) still hold. Each id's door
//     start is had once per daemon (a device restarted mid-search, or a forged step, numbers
//     its steps from 1 again), and a door start is released last by release_newest.
// A responder not heard for `idle_evict_s` has its state released (evict_idle): its
// estimators go, its slot frees (open mode). If it is heard again it starts afresh, as after
// a restart of the daemon; the device's own filter, the authority, is unaffected. When those
// served are more than the daemon can serve (BusyGate::note_shed), the one admitted last is
// released the same way (release_newest), and is a new id again: refused while the daemon is
// busy, admitted afresh once it is not.
//
//   ResponderRoster roster(config);
//   if (roster.admit(id, now) is refused) count and drop the sample;
//   for (const auto& id : roster.evict_idle(now)) drop id's estimator state;
// Not thread-safe: the daemon guards it with one mutex.
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace sarloc::estimator {

struct ResponderRosterConfig {
  /// Open mode: any id, up to max_responders; otherwise only `listed`.
  bool open = true;
  std::vector<std::string> listed;
  std::size_t max_responders = 256;
  /// Wall seconds without a sample after which a responder's state is released.
  double idle_evict_s = 300.0;
  /// New ids admitted per second at most, with a burst of as many (0: unpaced).
  double new_per_s = 10.0;
  /// Firefighters with a reported entry: their first step is admitted despite busy and pace (once).
  std::vector<std::string> door_starts{};

  /// Throws ConfigError naming the key ("core.idle_evict_s = 0: must be in [1, 86400]").
  void validate() const;
};

class ResponderRoster {
 public:
  using Clock = std::chrono::steady_clock;

  enum class Admission {
    kServed,     ///< state exists: go on
    kNew,        ///< admitted now: its state is to be created
    kEmptyId,    ///< refused: no id
    kNotListed,  ///< refused: roster mode and not on the roster
    kFull,       ///< refused: open mode and max_responders already served
    kBusy,       ///< refused: a new id while the daemon is busy (BusyGate)
    kPaced,      ///< refused: a new id beyond new_per_s; admitted by a later sample
  };

  explicit ResponderRoster(ResponderRosterConfig config);

  /// Records that `id` was heard at `now` if it is (or becomes) served. `busy`: refuse a new
  /// id (BusyGate::busy); one served already is served on. `first_step`: the sample is the
  /// device's first odometry step (a door start if `id` is one of `door_starts` not used yet).
  Admission admit(const std::string& id, Clock::time_point now, bool busy = false, bool first_step = false);
  /// Responders not heard for idle_evict_s by `now`, removed from the served set (oldest first).
  std::vector<std::string> evict_idle(Clock::time_point now);
  /// The responder admitted last of those `among` accepts (all by default; door starts count
  /// as admitted first), removed from the served set; none when there is none.
  std::optional<std::string> release_newest(const std::function<bool(const std::string&)>& among = {});
  /// Removes `id` from the served set (its estimator went to another sector's daemon); false
  /// when it was not served. A later sample of it is a new id again.
  bool release(const std::string& id) { return served_.erase(id) > 0; }

  std::size_t served() const { return served_.size(); }
  bool open() const { return config_.open; }

 private:
  ResponderRosterConfig config_;
  std::set<std::string> listed_;
  std::set<std::string> door_starts_;
  struct Served {
    Clock::time_point last_heard;
    std::uint64_t admitted;  ///< order of admission
  };
  std::map<std::string, Served> served_;
  std::uint64_t admissions_ = 0;
  double new_tokens_;  ///< the pace's bucket: one spent per new id, new_per_s refilled a second
  std::optional<Clock::time_point> refilled_at_;
};

bool refused(ResponderRoster::Admission a);
/// The rejection reason counted for a refusal ("unknown_rescuer", "too_many_rescuers",
/// "daemon_busy", "admission_paced").
const char* reason_of(ResponderRoster::Admission a);

}  // namespace sarloc::estimator
