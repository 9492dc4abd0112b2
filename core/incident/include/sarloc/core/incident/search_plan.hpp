#pragma once
// Incident command's primary-search plan (issue 63, item 2): the deposit cut into strips
// (plan_strips), one searching rescuer per strip (assign_strips), and what every rescuer's walk
// has searched so far (SearchCoverage), kept as positions arrive.
//
// The rules, each with its unit test (tests/unit/incident/search_plan_test.cpp):
//   - the strips are cut at the first update with a rescuer's position, entered from where the
//     rescuers are, one per searching rescuer if there are more rescuers than the fewest strips;
//     while less than `recut_below_searched` of the deposit is searched, rescuers who arrive
//     later re-cut them (what was walked already still counts);
//   - every walk between two fixes of a rescuer counts, searching or not (its transceiver keeps
//     listening), up to `max_walk_step_m`: a longer step is a gap in the fixes, not a walk;
//   - a strip is done once `strip_done_fraction` of it is searched or no row across it is left
//     unsearched, and its rescuer is free;
//   - free searching rescuers take open strips (not done, nobody's): the pairs that minimise the
//     summed walk to the strips' tops; a released rescuer's strip is open again;
//   - with no strip open, a free rescuer helps on a strip still walked: it walks it from the
//     bottom up while its rescuer walks down, one helper a strip. Only where it saves time: with
//     L the unsearched stretch between the two walkers' next points and D the helper's walk to
//     the bottom one, the strip is done at (L + D) / 2 instead of L; the pairs with the largest
//     saving L - D first, none unless D < L;
//   - the revision counts changes of strips or assignments, so readers can tell a new plan.
//
//   SearchPlanner planner(deposit, config);
//   planner.on_position("r1", fix);  ...  if (planner.update()) publish(planner.plan());
//   const auto target = planner.next_point("r1");   // where r1 walks next
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sarloc/core/incident/deposit.hpp"
#include "sarloc/core/incident/search_coverage.hpp"
#include "sarloc/core/incident/search_strips.hpp"
#include "sarloc/core/incident/signal_pursuit.hpp"
#include "sarloc/core/incident/victim_digs.hpp"

namespace sarloc::incident {

/// At most this many strips are cut (the SearchPlan topic's bound): more rescuers share them.
inline constexpr std::size_t kSearchStripsMax = 64;
/// Walks kept for a re-cut (a deposit nobody reaches keeps none beyond this: no re-cut then).
inline constexpr std::size_t kRecutWalksMax = 100000;

struct SearchPlanConfig {
  StripPlanConfig strips;        ///< search.strip_width_m, search.fall_line_deg
  double coverage_cell_m = 1.0;  ///< search.coverage_cell_m, [0.5, 5]
  /// search.strip_done_fraction, [0.5, 1]: a strip's last cells are often a corner nobody needs
  /// to walk to (heard from the centreline at an angle the grid does not credit).
  double strip_done_fraction = 0.98;
  /// search.max_walk_step_m, [2, 100]: 25 m is 25 s of walking, longer than any fade's gap.
  double max_walk_step_m = 25.0;
  /// search.recut_below_searched, [0, 0.5]: rescuers who arrive while less than this share of
  /// the deposit is searched re-cut the strips; later ones wait for a strip to come free.
  double recut_below_searched = 0.05;
  /// search.pursuit_timeout_s, [30, 3600]: a victim's pursuer who has not found it by then gives
  /// it up to every rescuer who hears it (signal_pursuit.hpp). 240 s: four times the default
  /// mission's median search from first signal to FOUND, short of the 35 min survival cliff.
  double pursuit_timeout_s = 240.0;
  void validate() const;  ///< ConfigError naming the key
};

struct PlannedStrip {
  Strip strip;
  double searched = 0.0;   ///< share of the strip's cells
  std::string rescuer_id;  ///< who walks it (from the top); empty: nobody
  bool done = false;
  std::string helper_id;  ///< who walks it from the bottom up, helping; empty: nobody
};

struct SearchPlan {
  std::uint32_t revision = 0;
  std::vector<PlannedStrip> strips;
  double searched = 0.0;  ///< share of the deposit's cells
};

/// The plan as incident command publishes it (SearchPlan topic).
struct SearchPlanPicture {
  std::string incident_id;
  std::int64_t stamp = 0;     ///< mission time (ns)
  std::vector<Vec2> deposit;  ///< counter-clockwise
  SearchPlan plan;
  std::vector<std::optional<Vec2>> next_points;  ///< per strip: where its rescuer walks next
  std::vector<std::optional<Vec2>> helper_next_points;  ///< per strip: where its helper walks next
  /// Signals of victims another rescuer pursues (signal_pursuit.hpp): not to be guided to.
  std::vector<SignalHandOver> handed_over;
  /// The dig order over the FOUND victims (victim_digs.hpp), and the mission time the victims
  /// count as buried from (0: unknown).
  VictimDigs digs;
  TimestampNs incident_start = 0;
};

class SearchPlanner {
 public:
  /// ConfigError (config.validate()).
  SearchPlanner(Deposit deposit, SearchPlanConfig config);
  /// A plan over a redrawn outline that keeps what `before` found searched: its strips are cut
  /// afresh (over the new outline, for the rescuers where they stand), and every cut takes
  /// over `before`'s searched cells that lie inside the new outline (SearchCoverage::carry_over).
  SearchPlanner(Deposit deposit, SearchPlanConfig config, const SearchPlanner& before);

  /// A rescuer's fix (incident frame, east/north). InputError for a non-finite one.
  void on_position(const std::string& rescuer_id, const Vec2& position);
  /// It no longer searches (link lost, signed off, on a signal, digging): its strip is open.
  void release(const std::string& rescuer_id);
  /// It searches again (its signal FOUND or handed over, link back): a strip at the next update.
  void resume(const std::string& rescuer_id);

  /// Applies the rules (file comment); true when the strips or the assignments changed.
  bool update();
  /// A standby takes the active incident command's assignments (who walks which, done), so
  /// that no rescuer is sent to another strip when it takes over. Only onto strips cut alike
  /// (same count, ends within 0.5 m: both cut from the same fixes); false, nothing changed,
  /// otherwise.
  bool adopt_assignments(const SearchPlan& active);

  const SearchPlan& plan() const { return plan_; }
  const Deposit& deposit() const { return deposit_; }
  /// The strip the rescuer walks from the top.
  std::optional<std::size_t> strip_of(const std::string& rescuer_id) const;
  /// The strip the rescuer helps on, walking it from the bottom up.
  std::optional<std::size_t> strip_helped_by(const std::string& rescuer_id) const;
  /// Where the rescuer walks next: the first point down its strip's centreline, from the top
  /// in cell steps, whose row across the strip is not all searched yet; for a helper, the same
  /// from the bottom up. Nullopt without a strip or when none is left.
  std::optional<Vec2> next_point(const std::string& rescuer_id) const;
  /// The plan as published: strips, the deposit and every strip's next point.
  SearchPlanPicture picture(const std::string& incident_id, std::int64_t stamp) const;

 private:
  struct Rescuer {
    std::optional<Vec2> last;
    bool searching = true;
  };
  void cut(std::size_t searching_rescuers);
  void assign_helpers(std::vector<std::string> free_ids, std::vector<Vec2> free_at);
  /// The first row down the strip's centreline (from_bottom: up) still holding an unsearched cell.
  std::optional<Vec2> first_unsearched(std::size_t strip, bool from_bottom = false) const;
  std::size_t searching_with_fix() const;

  Deposit deposit_;
  SearchPlanConfig config_;
  std::map<std::string, Rescuer> rescuers_;
  std::optional<SearchCoverage> coverage_;
  /// A replaced plan's coverage (over its own outline), carried into every cut of this one.
  std::optional<SearchCoverage> inherited_;
  /// Walks kept while the strips may still be re-cut (coverage is per strip); dropped after.
  std::vector<std::pair<Vec2, Vec2>> walks_;
  bool may_recut_ = true;
  std::size_t cut_for_ = 0;  ///< searching rescuers the strips were last cut for
  SearchPlan plan_;
  mutable std::vector<std::size_t> first_open_row_;  ///< per strip: rows before it are searched
  mutable std::vector<std::size_t> last_open_row_;   ///< the same counted from the bottom
};

}  // namespace sarloc::incident
