#pragma once
// Probe points covering the horizontal 95 % region of an estimate, the way rescuers probe
// around a transceiver's pinpoint: a hexagonal grid walked as a spiral from the centre (the
// most probable point) outwards.
//
// Region: the ellipse E = {x : x^T C^-1 x <= chi2_2(0.95)} of the horizontal covariance C,
// centred on the estimate. Coverage: every point of E lies within `cover_radius_m` of a probe
// point. Construction: a hexagonal lattice of spacing sqrt(3) * cover_radius_m centred on the
// estimate, whose Voronoi cells (hexagons of circumradius cover_radius_m) tile the plane; a
// lattice point is kept iff its cell meets E (exact test: in coordinates whitened by C the
// ellipse is a disc and the cell a convex polygon). Every point of E lies in a kept cell, so
// within cover_radius_m of its centre. When E fits in the disc of cover_radius_m around the
// estimate (largest semi-axis <= cover_radius_m), the estimate alone is the pattern.
//
//   std::vector<Eigen::Vector2d> offsets = probe_pattern(estimate.relative.covariance, 0.5);
//   // offsets[0] = (0, 0); walk to estimate + offsets[k] in order.
#include <vector>

#include "sarloc/core/common/types.hpp"

namespace sarloc::avalanche {

/// Horizontal offsets (m, in the frame of the covariance, G_k) from the estimate: centre first,
/// then ring by ring of the hexagonal lattice, each ring by angle (a spiral). The region is the
/// horizontal (x, y) marginal of the 3-D `position_covariance` (symmetric positive
/// semi-definite, m^2); its largest semi-axis is radius95_2d (common/gaussian.hpp).
/// Throws InputError for a non-finite covariance or cover_radius_m <= 0.
std::vector<Eigen::Vector2d> probe_pattern(const Mat3& position_covariance, double cover_radius_m);

}  // namespace sarloc::avalanche
