#pragma once
// The innovation history of one transmitter filter (seed 001, "innovation test"): per update the
// smallest normalised innovation squared over its hypotheses (Gaussians, particles or cells),
// the sample's valid axes, and how wide the position posterior was when it predicted the sample.
// The filter's divergence test and the search control's confirmation gates read it
// (SearchController::evidence); every filter keeps one, so the gates mean the same for each.
//
//   InnovationRecord record(6, 0.9999);   // window of 6 updates, gate chi2_{3n}(0.9999)
//   record.add(min_nis, 3, radius95_before);
//   if (record.window_exceeded()) ...      // no hypothesis fits the recent samples
#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

namespace sarloc::avalanche {

class InnovationRecord {
 public:
  static constexpr std::size_t kHistory = 64;

  /// window: updates summed by the divergence test (0 = no window); gate_probability in (0, 1).
  InnovationRecord(std::uint32_t window, double gate_probability);

  /// A new mixture (or particle set): its history starts empty.
  void clear();
  /// One update: the smallest NIS over the hypotheses, the valid axes of the sample, and the
  /// 95 % radius of the position posterior that predicted it.
  void add(double min_nis, int dof, double radius95_before);

  /// The window is full and its NIS sum exceeds chi2_{3n}(gate_probability).
  bool window_exceeded() const;
  /// Window sum over its gate: above 1, the recent samples do not fit. 0 until the window is full.
  double recent_ratio() const;
  /// The same over the last `samples` updates (fewer while younger; at most kHistory).
  double ratio_over(std::size_t samples) const;
  /// NIS summed over the last `samples` updates made while the 95 % radius was within
  /// `max_radius95`, with their degrees of freedom: chi-square with `dof` if the filter is right.
  struct Sum {
    double nis = 0.0;
    double dof = 0.0;
  };
  Sum within(double max_radius95, std::size_t samples) const;
  /// Smallest NIS of the latest update (0 before any).
  double last_min_nis() const { return last_min_nis_; }

 private:
  struct Entry {
    double min_nis = 0.0;
    int dof = 0;
    double radius95_before = 0.0;
  };
  std::uint32_t window_;
  double window_gate_ = 0.0;
  std::array<double, kHistory + 1> history_gates_{};
  std::vector<double> window_values_;  ///< ring buffer of the last window_ smallest NIS
  std::size_t next_ = 0;
  std::deque<Entry> history_;
  double last_min_nis_ = 0.0;
};

}  // namespace sarloc::avalanche
