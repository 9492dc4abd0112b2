#pragma once
// Information-aware opening heading: choose the straight walk whose next few steps are
// expected to leave the shortest way to the victim (a receding-horizon, one-decision lookahead).
//
// While the signal is near the noise floor the mixture is a ring or several arcs, and the
// most probable bearing is a poor guide: walking one way tells the hypotheses apart much better
// than another (the field magnitude changes as 1/r^3 along a radial walk, hardly at all along a
// tangential one). For each candidate heading theta (`headings` evenly spaced) the rescuer is
// imagined walking `horizon_steps` straight steps to x_L, and each hypothesis i (a weighted
// sample of the components' means: position p_i and moment m_i) predicts its fields h_i(t)
// there. If i were the truth, the data would leave hypothesis j with the expected posterior
//   q_ij ~ w_j exp(-0.5 information_scale sum_t |h_i(t) - h_j(t)|^2 / sigma_i(t)^2)
// (noise model of the filter: sigma = relative |h| + floor per axis). The expected cost is
//   J(theta) = sum_i w_i [ |x_L - p_i| + detour_weight sum_j q_ij (|x_L - p_j| + |p_j - p_i| - |x_L - p_i|) ]
// (horizontal distances): the way left, plus the part of the detour the rescuer walks when the
// data still point him to j. Measured against the most probable bearing in
// docs/estimation/avalanche.md ("Opening heading").
//
//   LookaheadConfig cfg;  // defaults documented per field
//   double heading = lookahead_heading(filter.hypotheses(), cfg, 1.0, filter.noise(), floor);
#include <vector>

#include "sarloc/core/avalanche/field_noise_model.hpp"
#include "sarloc/core/avalanche/transmitter_hypothesis.hpp"

namespace sarloc::avalanche {

struct LookaheadConfig {
  int hypotheses = 96;            ///< components drawn (systematic, by weight) as the hypotheses
  int headings = 24;              ///< candidate headings, evenly spaced in G
  int horizon_steps = 8;          ///< straight steps imagined per candidate
  double detour_weight = 2.0;     ///< share of the detour towards a wrong hypothesis walked
  double information_scale = 1.0; ///< < 1 discounts the noise-free expected information

  /// Throws ConfigError "search.lookahead_<key> = value: rule".
  void validate() const;
};

/// Heading (rad, in G) of the candidate with the lowest expected cost, predicting each walk's
/// samples with `noise` over a per-axis floor of `floor_A_per_m` (the measurement's). Deterministic
/// for a given mixture. Throws std::invalid_argument for an empty mixture (call after initialising).
double lookahead_heading(const std::vector<TransmitterHypothesis>& hypotheses, const LookaheadConfig& config,
                         double step_length_m, const FieldNoiseModel& noise, double floor_A_per_m);

}  // namespace sarloc::avalanche
