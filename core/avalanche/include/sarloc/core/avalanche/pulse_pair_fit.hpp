#pragma once
// Two overlapping pulses on one carrier (issue 12, multiple burials): two transmitters whose
// carriers fall within a frequency cell and whose pulses overlap in time. Successive
// cancellation cannot take them apart (the first burst it finds is their sum), and it either
// flags the pulse blended or carves the pair into abutting pieces whose fields are mixtures.
// What still tells them apart is where each starts and ends (and, at high signal-to-noise, a
// carrier a few hertz off): the model "burst x on [a1, b1) at f1 plus burst y on [a2, b2) at f2",
// each with its own complex amplitude per axis, fitted jointly by least squares.
//
// PulsePairFit scores that model by the energy it captures (whitened samples: sum over the axes
// of c^H G^-1 c, c the columns' projections, G their Gram matrix), and refines a pair by
// alternating: one burst's interval and carrier with the other held, then the other, a few
// rounds. The detector (pulse_detector.cpp) keeps the pair only when it captures more than the
// best single burst by its detection threshold.
//
//   PulsePairFit fit(whitened, window);
//   auto [x, y] = fit.refine(x0, y0, lo, hi, limits);
//   if (fit.energy(x, y) - fit.best_single(lo, hi, x.carrier_hz, limits).energy > threshold) ...
#include <complex>
#include <utility>

#include <Eigen/Core>

#include "sarloc/core/avalanche/pulse_train.hpp"

namespace sarloc::avalanche {

using WhitenedSamples = Eigen::Matrix<std::complex<double>, 3, Eigen::Dynamic>;

/// Prefix sums of the samples demodulated at f: P(:, n) = sum_{k<n} z(:, k) e^{-j2pi f t_k}.
WhitenedSamples demodulated_prefix(const WhitenedSamples& whitened, const BasebandWindow& w, double f);

struct ToneBurst {
  double carrier_hz = 0.0;
  Eigen::Index begin = 0, end = 0;  ///< sample interval [begin, end)
  double energy = 0.0;              ///< captured energy (set by the functions that score it)
};

struct BurstLimits {
  Eigen::Index min_length = 4;
  Eigen::Index max_length = 110;
  double carrier_span_hz = 1.0;  ///< carrier refinement: +- this around the current
  double carrier_step_hz = 0.05;
  /// A burst [a, b) is between the shortest and the longest length.
  bool fits(Eigen::Index a, Eigen::Index b) const { return b - a >= min_length && b - a <= max_length; }
};

class PulsePairFit {
 public:
  PulsePairFit(const WhitenedSamples& whitened, const BasebandWindow& window);

  /// Energy captured by x and y fitted jointly; 0 if their columns are nearly collinear
  /// (variance inflation above 50: nothing tells them apart).
  double energy(const ToneBurst& x, const ToneBurst& y) const;
  /// The single burst in [lo, hi) that captures the most energy, carrier within
  /// +- limits.carrier_span_hz of carrier_hz.
  ToneBurst best_single(Eigen::Index lo, Eigen::Index hi, double carrier_hz, const BurstLimits& limits) const;
  /// y's best interval in [lo, hi) with x held (each edge within `slack` samples of y's, or
  /// anywhere if slack < 0), over a coarse carrier grid around y's; then y's carrier on the fine
  /// grid with that interval.
  ToneBurst best_partner(const ToneBurst& x, ToneBurst y, Eigen::Index lo, Eigen::Index hi,
                         const BurstLimits& limits, Eigen::Index slack) const;
  /// Alternating refinement of both (rounds of best_partner each way); energies set.
  std::pair<ToneBurst, ToneBurst> refine(ToneBurst x, ToneBurst y, Eigen::Index lo, Eigen::Index hi,
                                         const BurstLimits& limits, int rounds = 3, Eigen::Index slack = 12) const;
  /// Two bursts on carrier f whose union is [begin, end), searched over every interior edge:
  /// one from begin and the other to end (overlapping or apart), or one spanning [begin, end)
  /// and the other inside it. A pair in lockstep overlaps like this at every pulse, and local
  /// refinement from one burst does not find the partner's edges. Energies set; both 0 when no
  /// split fits the limits.
  std::pair<ToneBurst, ToneBurst> best_spanning_pair(Eigen::Index begin, Eigen::Index end, double f,
                                                     const BurstLimits& limits) const;
  /// All four edges moved together, each within `slack` samples, carriers held: alternating
  /// refinement stalls where one burst's edge covers the other's tail; energies set.
  std::pair<ToneBurst, ToneBurst> polish_edges(ToneBurst x, ToneBurst y, Eigen::Index lo, Eigen::Index hi,
                                               const BurstLimits& limits, Eigen::Index slack) const;

 private:
  /// Projection of the samples on a burst: sum over its interval of z e^{-j2pi f t}.
  Eigen::Vector3cd projection(const ToneBurst& b) const;
  /// y's best interval at carrier f with x held (projection cx): begin in [a_lo, a_hi], end in
  /// [b_lo, b_hi].
  ToneBurst best_interval_with(const ToneBurst& x, const Eigen::Vector3cd& cx, double f, Eigen::Index a_lo,
                               Eigen::Index a_hi, Eigen::Index b_lo, Eigen::Index b_hi,
                               const BurstLimits& limits) const;

  const WhitenedSamples& z_;
  const BasebandWindow& w_;
};

}  // namespace sarloc::avalanche
