#pragma once
// Which responders' last positions to write again, so that a writer with a lifespan keeps each
// one and forgets the rest.
//
// Fast DDS 2.9 sends, with every periodic heartbeat, a GAP for every hole between the oldest
// sample a writer keeps and its newest, and every reader walks those holes number by number
// (docs/topics.md, "Lifespan bounds what every heartbeat carries"). The core daemon writes every
// firefighter's map-aided position on one writer: a firefighter who falls silent would leave his
// last positions at old sequence numbers for the rest of the incident, and the readers' cost
// would grow with every position written since. With a lifespan those samples leave the
// history, but the newest is a lost firefighter's last known position, which a reader that
// joins late (a restarted incident command) must still get. So it is written again, unchanged
// (same stamp), once `interval` has passed since it was last written: shorter than the lifespan,
// it is never gone. Readers know a copy by its stamp: not newer than what they hold, it says
// nothing new about the responder (TeamTracker, the device, the dashboard, the report).
//
//   worker:        refresh.written(position, now);
//   status thread: for (auto& p : refresh.due(now)) writer.write(p);
// Thread-safe.
#include <chrono>
#include <cstddef>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "sarloc/core/responder/responder_position.hpp"

namespace sarloc::estimator {

class PositionRefresh {
 public:
  using Clock = std::chrono::steady_clock;

  /// interval: how long a position may go unwritten (> 0).
  explicit PositionRefresh(Clock::duration interval);

  /// `position` was written at `at`. An older stamp than the one held is ignored.
  void written(const responder::ResponderPosition& position, Clock::time_point at);
  /// The positions not written for `interval` by `now`, oldest first; each counts as written at
  /// `now`.
  std::vector<responder::ResponderPosition> due(Clock::time_point now);
  /// Stops writing `responder_id`'s position again (another daemon serves him now).
  void forget(const std::string& responder_id);
  /// Responders whose last position is held.
  std::size_t size() const;

 private:
  struct Held {
    responder::ResponderPosition position;
    Clock::time_point written_at;
  };

  Clock::duration interval_;
  mutable std::mutex mutex_;
  std::map<std::string, Held> held_;
};

}  // namespace sarloc::estimator
