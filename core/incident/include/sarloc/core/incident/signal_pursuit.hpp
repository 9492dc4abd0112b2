#pragma once
// One rescuer per victim (issue 63, item 3): when several rescuers hear one victim, incident
// command sends the nearest and hands the others' signals of it over, so that they go back to
// their strips (the standard practice: when one rescuer takes a signal, the others continue).
// The hand-overs travel in the search plan; each device and the core daemon stop guiding their
// rescuer to a signal handed over (avalanche::RescuerSearch::leave_to_others).
//
// Rules, each with its unit test (tests/unit/incident/signal_pursuit_test.cpp):
//   - only a victim not found, without conflicting evidence and not possibly the same as
//     another (incident command cannot tell which is which: everyone keeps searching), heard
//     by at least two searching rescuers (link alive, GNSS fix);
//   - the pursuer is the one of them nearest to the victim when it is first handed out, among
//     those not pursuing another victim if any (victims close together go one to each rescuer,
//     not all to whoever stands nearest the cluster), and stays the pursuer while it searches and
//     hears the victim (no flapping between two rescuers who walk about equally near);
//   - a pursuer who has not found the victim within `pursuit_timeout_s` gives it up for good
//     (while it is in the picture; forgotten once unseen for a whole timeout):
//     every rescuer who hears it may pursue it again (a wrong filter must not hide a victim);
//   - every other rescuer's signal of the victim is handed over;
//   - before anyone has placed it, a transmitter that several rescuers hear (their signals
//     grouped by its signature, signal_groups.hpp) goes to the nearest of them by his own
//     distance reading (HeardSignal::range_m; the first to take it when one reads none),
//     among those pursuing nothing else, and the others' signals of it are handed over (victim
//     id 0);
//     once it is placed, its victim stays with that pursuer if he is among those who placed it
//     (or all of those pursue another and he hears it, for kMatchedPursuerGraceNs), else the
//     nearest of those is sent; signals not yet
//     placed that are a victim's transmitter count as hearing it, and are handed over with its
//     sources.
//
//   SignalPursuits pursuits(240.0);
//   picture.handed_over = pursuits.update(fusion.victims(), searching_positions, now,
//                                         group_heard_signals(heard, fusion.victims(), 0.999));
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "sarloc/core/incident/deposit.hpp"
#include "sarloc/core/incident/fused_victim.hpp"
#include "sarloc/core/incident/signal_groups.hpp"

namespace sarloc::incident {

/// At most this many hand-overs (the SearchPlan topic's bound); beyond it the rest are left
/// out: those rescuers keep pursuing (the safe side).
inline constexpr std::size_t kSignalHandOversMax = 256;

/// A rescuer's signal of a victim that another rescuer pursues: not to be guided to.
struct SignalHandOver {
  std::string rescuer_id;  ///< whose signal
  std::uint32_t signal_id = 0;
  std::uint32_t victim_id = 0;  ///< 0: a transmitter not yet placed (SignalGroups::unplaced)
  std::string pursued_by;  ///< the rescuer incident command sends
};

/// A plan's hand-overs hold this long after its stamp (mission time) without a newer plan: a
/// silent incident command (and no standby) hides no victim for long.
inline constexpr TimestampNs kHandOverLapseNs = 30'000'000'000;
/// A pursuit of a transmitter not yet placed outlives its group by this long (handing nothing
/// over meanwhile), so that a group that breaks for a cycle or two (a fix on its way, a position
/// late) comes back with the same pursuer and the same start of its timeout.
inline constexpr TimestampNs kUnplacedPursuitGraceNs = 10'000'000'000;
/// A transmitter not yet placed must be placed by its pursuer within this long (or the pursuit
/// timeout, if shorter), else it is given back to everyone: walking at about 1 m/s towards a
/// signal heard from at most 60-70 m, a filter converges within about a minute (20-45 s measured
/// on large-deposit.yaml); one that has not in 90 s is not closing in, and the others who hear
/// it must not wait for the whole pursuit timeout.
inline constexpr TimestampNs kUnplacedPursuitPlaceNs = 90'000'000'000;
/// A victim's pursuer who only matched its signature (his own signal not yet placed) must place
/// it within this long, else the nearest of those who placed it is sent: a wrong match must not
/// keep the rescuer who placed it away for a whole pursuit timeout.
inline constexpr TimestampNs kMatchedPursuerGraceNs = 30'000'000'000;

/// The signals of `rescuer_id` that `handed_over` gives to others.
std::set<std::uint32_t> signals_left_to_others(const std::vector<SignalHandOver>& handed_over,
                                               const std::string& rescuer_id);

class SignalPursuits {
 public:
  /// `pursuit_timeout_s`: search.pursuit_timeout_s (SearchPlanConfig validates it).
  explicit SignalPursuits(double pursuit_timeout_s);

  /// The hand-overs now. `searching`: the searching rescuers' latest positions (incident
  /// frame); `groups`: the signals heard and not yet placed, grouped by transmitter. What
  /// changed since the last call is in events().
  std::vector<SignalHandOver> update(const std::vector<FusedVictim>& victims,
                                     const std::map<std::string, Vec2>& searching, TimestampNs now,
                                     const SignalGroups& groups = {});
  std::optional<std::string> pursuer_of(std::uint32_t victim_id) const;
  /// Who pursues the transmitter not yet placed that `signal` (a rescuer's) is one of.
  std::optional<std::string> pursuer_of_signal(const SignalKey& signal) const;
  /// A standby takes the active incident command's pursuits (its hand-overs), so that taking
  /// over sends nobody else; a pursuit new to it counts from `now` (the active one's start is
  /// not on the wire).
  void adopt(const std::vector<SignalHandOver>& active, TimestampNs now);
  /// Victims and signals given back to everyone and still remembered (for tests).
  std::size_t given_up_count() const { return given_up_.size() + given_up_signals_.size(); }
  /// For incident command's log, of the last update: a pursuit begun or moved (info), given up
  /// (a warning: the pursuer did not find it).
  struct Event {
    bool warning = false;
    std::string text;
  };
  const std::vector<Event>& events() const { return events_; }

 private:
  struct Pursuit {
    std::string rescuer_id;
    TimestampNs since = 0;
    /// Since when the pursuer only matches the victim's signature (0: a signal of his placed it).
    TimestampNs matched_only_since = 0;
  };
  /// A transmitter not yet placed: its pursuer and the rescuers' signals of it.
  struct GroupPursuit {
    Pursuit pursuit;
    std::set<SignalKey> signals;
    TimestampNs last_seen = 0;  ///< its group last formed
  };
  void pursue_unplaced(const SignalGroups& groups, const std::map<std::string, Vec2>& searching,
                       std::set<std::string>& busy, TimestampNs now, std::vector<SignalHandOver>& out);

  /// Given-up victims and signals in the picture this cycle (a fused victim; a signal heard,
  /// grouped or not) are kept, those unseen for a whole pursuit timeout forgotten: incident
  /// command runs for hours, and a victim id or signal nobody reports any more needs no memory
  /// (should it come back, it is pursued afresh, under a new timeout).
  void refresh_given_up(const std::vector<FusedVictim>& victims, const SignalGroups& groups, TimestampNs now);

  TimestampNs timeout_ns_;
  std::map<std::uint32_t, Pursuit> pursuits_;  ///< by victim id
  /// Victims every rescuer may pursue again, with when each was last in the picture.
  std::map<std::uint32_t, TimestampNs> given_up_;
  std::vector<GroupPursuit> group_pursuits_;
  /// Signals of transmitters not placed, given up, with when each was last heard.
  std::map<SignalKey, TimestampNs> given_up_signals_;
  std::vector<Event> events_;
};

}  // namespace sarloc::incident
