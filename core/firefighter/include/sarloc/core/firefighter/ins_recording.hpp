#pragma once
// The boot INS run over a whole recording, and its errors against the truth a recording has:
// a closed loop (the foot ends where it started) or footprints measured on the floor (one per
// stance phase). What `sarloc-eval ins` prints (docs/estimation/firefighter.md, "Real
// recordings").
//
//   InsRecording run = run_ins(samples, config);
//   run.aligned_at_s; run.stances; loop_error(run); footprint_errors(run, truth);
#include <Eigen/Core>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sarloc/core/firefighter/imu_sample.hpp"
#include "sarloc/core/firefighter/zupt_ins.hpp"

namespace sarloc::firefighter {

struct TrackPoint {
  double t = 0.0;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();  ///< navigation frame (x, y level, z up)
  bool stationary = false;
};

/// One stance phase after alignment: where the foot stood (its mean position) and when, and the
/// INS's displacement since the previous stance (ZuptIns::take_displacement at each stance's end,
/// so its covariance is the one the device publishes for that stride).
struct Stance {
  double t0 = 0.0, t1 = 0.0;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector3d stride = Eigen::Vector3d::Zero();
  Eigen::Matrix3d stride_covariance = Eigen::Matrix3d::Zero();
};

struct InsRecording {
  std::size_t samples = 0;
  std::map<std::string, std::size_t> refused;           ///< by the INS, by reason
  std::optional<double> aligned_at_s;                   ///< the sample time alignment happened at
  double roll_rad = 0.0, pitch_rad = 0.0;               ///< the boot's tilt at alignment
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();  ///< estimated at alignment (rad/s)
  RestNoise rest_noise;                                 ///< measured at alignment
  double longest_still_s = 0.0;                         ///< the longest still spell before alignment
  std::vector<TrackPoint> track;                        ///< every sample after alignment
  /// Footprints: stance phases after alignment (the first: where it aligned); one within 0.25 m
  /// of the previous footprint is that footprint again (merged).
  std::vector<Stance> stances;
  double distance_m = 0.0;  ///< walked: between successive stances, 3-D
  double duration_s = 0.0;  ///< of the recording
};

InsRecording run_ins(const std::vector<ImuSample>& samples, const ZuptInsConfig& config);

struct LoopError {
  Eigen::Vector3d end = Eigen::Vector3d::Zero();  ///< the last stance's position (start = 0)
  double error_3d_m = 0.0, horizontal_m = 0.0, vertical_m = 0.0;
};
/// A closed loop: the last stance against the first. nullopt without two stances.
std::optional<LoopError> loop_error(const InsRecording& run);

struct FootprintErrors {
  std::size_t strides_truth = 0, strides_track = 0, compared = 0;
  /// Stride-aligned: the track turned about its start so that stride 1 points where the
  /// truth's does; error of each footprint (2-D).
  double final_m = 0.0, rms_m = 0.0, max_m = 0.0;
  /// After the 2-D rigid (rotation and translation) alignment of the whole track to the
  /// footprints.
  double rigid_final_m = 0.0, rigid_rms_m = 0.0, rigid_max_m = 0.0;
  double truth_distance_m = 0.0;  ///< along the footprints
  double turn_rad = 0.0;          ///< the stride alignment: truth = truth[0] + Rot(turn) track
  /// Consistency of the stride covariances (item 5 of issue 62), over the strides paired by
  /// match_strides (stride_pairs; stride_groups of them pair a split or missed footfall). Each
  /// pair's 2-D error in a local frame: the INS's stride turned by the median heading offset of the
  /// neighbouring strides (kStrideNeighbours each side, itself left out), so that the slow yaw
  /// drift the map-aided filter tracks as a heading is not counted as stride error. Against the
  /// INS's stated covariance of that stride: the mean NEES (2 degrees of freedom) and its
  /// two-sided 95 % bounds for that many strides.
  double stride_nees_mean = 0.0, stride_nees_lower = 0.0, stride_nees_upper = 0.0;
  /// The horizontal variance per metre walked that the stated covariance lacks, by the method of
  /// moments: sum(|e|^2 - trace C) / (2 sum |stride|) (m^2/m; negative: the covariance is wider).
  double missing_variance_per_m = 0.0;
  /// The heading offset's change from one stride to the next, RMS (rad): the yaw the INS loses
  /// per stride, with the truth's own foot placement.
  double heading_wander_rad = 0.0;
  double mean_stride_m = 0.0;  ///< along the INS's compared strides
  std::size_t stride_pairs = 0, stride_groups = 0;
};
/// `truth[k]`: footprint of stride k (0 = the start pose). Compared over the strides both have.
std::optional<FootprintErrors> footprint_errors(const InsRecording& run, const std::vector<Eigen::Vector2d>& truth);

}  // namespace sarloc::firefighter
