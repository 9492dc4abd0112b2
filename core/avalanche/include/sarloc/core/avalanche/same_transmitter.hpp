#pragma once
// Are two signals of one receiver one transmitter? A receiver's separation can split one
// transmitter into two signals (a track lost and started again, a carrier re-timed); each
// signal's filter then finds the same victim, and incident command, which never lets two
// signals of one rescuer share a victim, would confirm it twice. Two filters of one transmitter
// agree on its position AND on its moment (up to sign: the receiver loses the field's sign
// between pulses); two transmitters a few decimetres apart almost never share a moment
// (docs/estimation/avalanche.md, "One transmitter, two signals").
#include "sarloc/core/avalanche/sog_filter.hpp"

namespace sarloc::avalanche {

/// Squared Mahalanobis distance of [position; moment] between two filters' moments in the same
/// frame, covariances summed, the smaller of the moment compared as it is and with its sign
/// flipped. 6 degrees of freedom. 0 when the covariances cannot be used (nothing told apart).
double same_transmitter_distance2(const MixtureMoments& a, const MixtureMoments& b);

/// The moment is known well enough for the test to tell transmitters apart: its 1-sigma spread
/// (sqrt of the trace of its covariance) below `relative_spread` of its magnitude. A mixture
/// that still holds both signs averages the moment towards zero with a wide spread: not known.
bool moment_determined(const MixtureMoments& m, double relative_spread);

}  // namespace sarloc::avalanche
