#pragma once
// Silence on a tracked carrier across listening windows (issue 12, negative information): the
// times at which one of the transmitter's whole pulses could have started, inside a window and
// clear of every other pulse heard, since its carrier was last heard. Once those times hold a
// start for every phase of its pulse train, a whole pulse of it was due in the clear and went
// unheard: a miss, without knowing its phase. A transmitter at the edge of range, unheard for
// a while, has a timing gate wider than a window, so a single window never proves a miss; the
// span does (seen: a rescuer walking back and forth for minutes between a wrong estimate and
// the place its signal was last heard, the filter learning nothing from the silence).
//
//   QuietSpan quiet;
//   quiet.add_window(w0, w1, on_time, other_pulses, margin);
//   if (quiet.every_phase_covered(period, period_spread)) { report_miss(); quiet.reset(); }
#include <cstddef>
#include <utility>
#include <vector>

namespace sarloc::avalanche {

class QuietSpan {
 public:
  using Interval = std::pair<double, double>;

  /// The carrier was heard (or the track changed): start again.
  void reset() { clear_starts_.clear(); }

  /// A window [w0, w1) in which nothing was heard on the carrier. A pulse of `on_time_s`
  /// starting at s is whole inside it when s in [w0, w1 - on_time_s], and clear of another
  /// pulse [a, b] when s is outside [a - on_time_s - margin_s, b + margin_s].
  void add_window(double w0, double w1, double on_time_s, const std::vector<Interval>& other_pulses, double margin_s);

  /// Kept start intervals: the oldest go first (a span that never covers every phase, e.g. a
  /// period equal to the window's, would otherwise grow for as long as the track is silent).
  static constexpr std::size_t kMaxIntervals = 512;

  /// Every pulse train with a period within period_s +- period_spread_s has a start in the clear
  /// start times (each interval narrowed by the drift the spread allows over the periods since
  /// the span began).
  bool every_phase_covered(double period_s, double period_spread_s) const;

  const std::vector<Interval>& clear_starts() const { return clear_starts_; }

 private:
  std::vector<Interval> clear_starts_;  // in time order
};

}  // namespace sarloc::avalanche
