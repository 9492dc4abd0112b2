#pragma once
// Pulse timing of one tracked transmitter (issue 12): a two-state Kalman filter on the start of
// its pulses and its period. EN 300 718 transmitters pulse on a crystal clock, so the period is
// constant to a few ppm and the start of pulse n is start_0 + n * period. What is uncertain is
// the receiver's estimate of them: a weak pulse's edges are found tens of milliseconds off, so
// a period taken from two weak pulses can be a few ms wrong, and after 20 periods the predicted
// start is 100 ms away. The filter carries that uncertainty, so the gate widens with the number
// of periods predicted and narrows as clean pulses accumulate.
//
//   PulseTiming timing(config);
//   auto fit = timing.fit(start_s, edge_sigma_s);
//   if (!fit || fit->sigmas() <= 4.0) timing.update(start_s, edge_sigma_s);
#include <optional>

#include "sarloc/core/common/types.hpp"

namespace sarloc::avalanche {

struct PulseTimingConfig {
  double min_period_s = 0.65;        ///< two starts this far apart (or up to max) are one period
  double max_period_s = 1.35;        ///< EN 300 718: 1000 +- 300 ms, plus margin
  double clock_jitter_s = 0.001;     ///< random walk of the start per period (clock drift)
  double reanchor_period_sigma_s = 0.005;  ///< period uncertainty kept by reanchor()
};

struct TimingFit {
  double periods = 0.0;      ///< whole periods from the last update to this pulse
  double innovation_s = 0.0; ///< measured - predicted start
  double variance_s2 = 0.0;  ///< of the innovation: prediction + measurement
  double sigmas() const;     ///< |innovation| / sqrt(variance)
};

class PulseTiming {
 public:
  explicit PulseTiming(PulseTimingConfig config = {}) : config_(config) {}

  /// A pulse started at start_s, found to within edge_sigma_s (1 sigma). The first pulse sets
  /// the phase; a second one a period later sets the period; later ones refine both.
  void update(double start_s, double edge_sigma_s);
  /// Fit of a pulse against the prediction (nullopt until the period is known).
  std::optional<TimingFit> fit(double start_s, double edge_sigma_s) const;
  /// Forgets the phase and widens the period to a prior: a reacquired transmitter whose pulses no
  /// longer fit (its estimate drifted while it was unheard).
  void reanchor();

  bool has_phase() const { return last_start_s_.has_value(); }
  bool has_period() const { return period_s_.has_value(); }
  double last_start_s() const { return *last_start_s_; }
  double period_s() const { return *period_s_; }
  /// 1 sigma of the period estimate (s), 0 before it is known.
  double period_sigma_s() const;

 private:
  PulseTimingConfig config_;
  std::optional<double> last_start_s_;
  std::optional<double> period_s_;
  Eigen::Matrix2d covariance_ = Eigen::Matrix2d::Zero();  ///< of (last start, period)
};

}  // namespace sarloc::avalanche
