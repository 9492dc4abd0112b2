#pragma once
// Primary search, planned (issue 63, item 2): the deposit cut into strips along the fall line,
// each walked down its centre by one rescuer, who hears every transmitter within half the strip
// width on either side (the standard practice: rescuers abreast at the search-strip width).
//
// The strips: the deposit's extent across the fall line is divided into the fewest strips no
// wider than `strip_width_m` (or one per rescuer, if more), all of one width; each strip is the deposit's part between
// two parallel lines (a concave deposit can give a strip in pieces: each piece is a strip). A strip's centreline runs
// from its top (the end the rescuers enter from) to its bottom. The fall line: `fall_line_deg` (ENU bearing, 0 = east,
// 90 = north, of downhill) when given, else the deposit's long axis (its minimum-area bounding rectangle), entered from
// the end nearer the rescuers.
//
// Assignment: each rescuer to one strip, the pairs that minimise the summed walk to the strips'
// tops (solve_assignment); more strips than rescuers leaves strips open for the next one free,
// more rescuers leaves rescuers free.
//
//   const auto strips = plan_strips(deposit, StripPlanConfig{}, rescuers_mean);
//   const auto strip_of = assign_strips(strips, rescuer_positions, open);
#include <optional>
#include <vector>

#include "sarloc/core/incident/deposit.hpp"

namespace sarloc::incident {

struct StripPlanConfig {
  /// Widest strip (m). 40 m: the evaluations' primary strip passes within 20 m of the victim and
  /// every simulated search hears it; real transceivers reach 40-70 m and their makers advise
  /// 40-50 m strips (docs/operations/search-planning.md).
  double strip_width_m = 40.0;
  std::optional<double> fall_line_deg;  ///< downhill bearing; none: the deposit's long axis
  void validate() const;                ///< ConfigError naming search.strip_width_m, search.fall_line_deg
};

struct Strip {
  std::size_t index = 0;      ///< across the fall line, from the left looking downhill
  std::vector<Vec2> outline;  ///< counter-clockwise, not closed
  Vec2 top = Vec2::Zero();    ///< the centreline's ends
  Vec2 bottom = Vec2::Zero();
  double width_m = 0.0;
  double area_m2 = 0.0;
};

/// Narrower than this, strips are not cut for more rescuers (m): at 10 m apart their hearing
/// ranges overlap four times over; a rescuer more probes or digs instead.
inline constexpr double kMinStripWidth_m = 10.0;

/// `entry`: where the rescuers are (their mean position); with no fall line configured, the
/// strips are entered from the end of the long axis nearer to it. `at_least`: the rescuers who
/// will search; with more of them than the fewest strips, as many strips (none narrower than
/// kMinStripWidth_m), so that nobody waits while the deposit is still unsearched.
std::vector<Strip> plan_strips(const Deposit& deposit, const StripPlanConfig& config, const Vec2& entry,
                               std::size_t at_least = 1);

/// For each rescuer (by position), the strip it walks, or nullopt (free). Only strips with
/// `open[i]` true are assigned (`open` empty: all).
std::vector<std::optional<std::size_t>> assign_strips(const std::vector<Strip>& strips,
                                                      const std::vector<Vec2>& rescuers,
                                                      const std::vector<bool>& open = {});

}  // namespace sarloc::incident
