#pragma once
// Pattern comparison (seed 004 section IV-D, Algorithm 1). The last d metres of the odometry
// trajectory are rotated to the building's principal headings (eq. (1)), then compared by ICP,
// from four initial rotations (0, 90, 180, 270 deg), with every search pattern: the d-metre
// windows {p_eta ... p_eta+dN} of the node sequences. Per window the result is E (the smallest
// ICP RMSE per column), Pos (p_eta for a left-hand search, p_eta+dN for a right-hand one) and
// Hea (the walking direction on arriving there). Nearest neighbours come from a k-d tree per
// window (nanoflann).
//
// Deviations, named: each observation also carries its best ICP fit (the transformed current
// position and the implied heading of the odometry frame), from which the q % replacement
// draws new particles: Hea is a grid direction, up to 45 deg from where the firefighter
// actually walks along a wall at a slant or sweeps, and a particle that far off in heading
// walks into the next wall. The windows are densified to `pattern_point_spacing_m` so that the RMSE
// of a perfect fit is not the grid's quantisation; an ICP whose RMSE after three iterations
// already exceeds the best so far by `prune_margin_m` stops there and keeps that RMSE (its
// likelihood, eq. (2), is below e^-50 of the best's); Hea at p_eta+dN is the arriving
// direction p_eta+dN - p_eta+dN-1 (seed 004 writes the leaving one). A sequence's room skips
// (search_pattern.hpp) add the windows that span each skip: the same d metres of directional
// search with that room passed by; their observations sit at the same window ends as the
// loop's own, so a particle takes whichever fits better.
//
// A comparison can be restricted to the window ends that are the nearest end to some particle
// (`EndMask`, from MapParticleFilter::observation_ends): the particles take only those
// observations (weights only), so the restricted comparison gives them the same weights at a
// fraction of the cost once the cloud has concentrated. Every window touching a wanted end is
// compared, so the observations at that end are all there; observations at the other ends are
// left out (theirs would be incomplete).
//
//   PatternMatcher matcher(extract_node_sequences(plan, grid), grid, PatternMatchConfig{});
//   std::vector<PseudoObservation> obs = matcher.compare(last_20_m_of_odometry);
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "sarloc/core/firefighter/point_index.hpp"
#include "sarloc/core/firefighter/search_pattern.hpp"

namespace sarloc::firefighter {

struct PatternMatchConfig {
  double pattern_length_m = 20.0;          ///< d, seed 004 section V-B
  double compare_every_m = 2.0;            ///< a new comparison after this much walking
  double trajectory_spacing_m = 1.0;       ///< the odometry trajectory is resampled to this
  double pattern_point_spacing_m = 0.25;
  std::uint32_t icp_iterations = 20;
  double icp_tolerance_m = 0.01;  ///< an RMSE change this small is nothing at eq. (2)'s sigma
  double prune_margin_m = 0.5;
  void validate() const;
};

/// One entry of Pos / Hea with its E: where the firefighter would be now, walking which way,
/// if the last d metres were this part of a directional search.
struct PseudoObservation {
  std::size_t floor = 0;
  Vec2 position = Vec2::Zero();
  double heading = 0.0;                                    ///< walking direction, map frame
  double rmse = std::numeric_limits<double>::infinity();   ///< E; infinity: no ICP chose it
  /// The best ICP fit behind E: where it puts the trajectory's last point, and the map
  /// heading of the INS navigation frame it implies (rotation of the odometry into the map).
  Vec2 fitted_position = Vec2::Zero();
  double frame_heading = 0.0;
};

/// Per floor, one flag per distinct window end (PatternMatcher::ends): whether a comparison
/// must produce the observations there.
using EndMask = std::vector<std::vector<char>>;

class PatternMatcher {
 public:
  PatternMatcher(const std::vector<NodeSequence>& sequences, const PatternGridConfig& grid,
                 PatternMatchConfig config);

  /// `trajectory`: horizontal odometry positions, oldest first, the last one now, about
  /// pattern_length_m long. Returns 2 observations per window (empty when the trajectory is
  /// shorter than half the pattern length).
  /// With `wanted`: only the windows with a wanted end, and only the observations at wanted ends.
  std::vector<PseudoObservation> compare(const std::vector<Vec2>& trajectory, const EndMask* wanted = nullptr) const;

  /// The distinct window ends of a floor: the positions every observation is at.
  const std::vector<Vec2>& ends(std::size_t floor) const;
  EndMask empty_end_mask() const;
  /// Marks every end that may be the nearest end to some point within `radius_m` of `centre`.
  void mark_ends_near(std::size_t floor, const Vec2& centre, double radius_m, EndMask& mask) const;
  /// How many windows a comparison restricted to `mask` compares.
  std::size_t windows_touching(const EndMask& mask) const;

  std::size_t window_count() const { return windows_.size(); }
  const PatternMatchConfig& config() const { return config_; }

  /// eq. (1): the rotation that brings the trajectory's displacements closest to the four
  /// principal headings (rad, in [-pi/4, pi/4)).
  static double principal_rotation(const std::vector<Vec2>& trajectory);
  /// The trajectory resampled every `spacing` metres along its length (first and last kept).
  static std::vector<Vec2> resample(const std::vector<Vec2>& trajectory, double spacing);

 private:
  struct Window {
    std::size_t floor = 0;
    std::uint32_t first_end = 0, last_end = 0;  // into ends_[floor]
    Vec2 first, last, centroid;
    double heading_first = 0.0, heading_last = 0.0;
    PointIndex points;
  };
  struct Fit {
    double rmse;
    Vec2 last;      // the trajectory's last point, transformed
    double angle;   // of the ICP rotation
  };
  Fit icp(const std::vector<Vec2>& source, const Window& window, double abandon_above) const;
  void check_mask(const EndMask& mask) const;  ///< throws InputError unless shaped as empty_end_mask's

  PatternMatchConfig config_;
  std::vector<Window> windows_;
  std::vector<std::unique_ptr<PointIndex>> ends_;  // per floor; null: no window on it
};

}  // namespace sarloc::firefighter
