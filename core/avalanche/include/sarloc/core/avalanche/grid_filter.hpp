#pragma once
// Histogram (grid) filter over the transmitter position, the reference of the slides (seed 001,
// "Second solution: Histogram Filter"): the search space cut into cells, each with a weight and,
// since z = C(Psi, p) m is linear in the moment, the moment's Gaussian posterior in closed form
// (moment_kalman.hpp, one Kalman filter per cell: no cell has to guess m).
//
// The slides' objection is the cost near the victim, where the field changes quickly: a
// multi-resolution grid answers it here. Cells start cell_m wide over the ring of the first
// sample (SogFilter::initial_ring), negligible ones are dropped (prune_log_weight), and once the
// live cells fit within refine_cells cells of their 95 % radius each is split in eight, down to
// finest_cell_m.
//
// The grid is fixed in G_1 (ENU axes, origin at the first antenna position); the receiver's pose
// in it is dead-reckoned from the odometry means. A Kalman filter on the dead-reckoning error
// [Psi, s] (attitude, and s the offset the path's error adds to every relative position p) keeps
// what the mean path leaves out: the attitude readings correct Psi and, through their
// correlation, s (a shift of the whole grid), and the growth of s's variance is applied to the
// cells as a diffusion (a blur of weights and moments between neighbouring cells, axis by axis).
// That is the robocentric model's motion noise: the odometry's translation noise and the
// attitude error that turns each step (about 2 deg of heading at 1 m per step: metres over a
// search). The attitude's spread also widens the field noise (in quadrature with the relative
// noise). Left out: what the field samples say about Psi and s, and the cross-axis terms of the
// diffusion (docs/estimation/baselines.md).
//
//   GridFilter f(SogConfig{}, GridFilterConfig{});
//   f.add_odometry(odo);
//   FilterStepResult r = f.update(measurement);
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sarloc/core/avalanche/detection_curve.hpp"
#include "sarloc/core/avalanche/odometry_accumulator.hpp"
#include "sarloc/core/avalanche/sog_filter.hpp"
#include "sarloc/core/avalanche/transmitter_filter.hpp"

namespace sarloc::avalanche {

struct GridFilterConfig {
  double cell_m = 1.0;            ///< initial cell size (grown when the ring would need more than max_cells)
  double finest_cell_m = 0.0625;  ///< no refinement below this
  double refine_cells = 6.0;      ///< split when the live cells' 95 % radius is below this many cells
  double prune_log_weight = 14.0; ///< drop cells with log w < max log w - this
  std::uint32_t max_cells = 400000;

  /// Throws ConfigError "grid.<key> = value: rule".
  void validate() const;
};

class GridFilter : public TransmitterFilter {
 public:
  GridFilter(SogConfig sog, GridFilterConfig config, std::string rescuer_id = {}, std::uint32_t signal_id = 0);

  std::string kind() const override { return "grid"; }
  void add_odometry(const Odometry& odometry) override;
  FilterStepResult update(const FieldMeasurement& measurement) override;
  bool initialised() const override { return !cells_.empty(); }
  std::size_t size() const override { return cells_.size(); }
  MixtureMoments moments() const override;
  MixtureMoments predicted_moments() const override;
  Vec3 predicted_last_measurement_position() const override;
  VictimEstimate estimate(std::size_t top_k = 5) const override;
  std::vector<TransmitterHypothesis> hypotheses() const override;
  const InnovationRecord& innovations() const override { return record_; }
  std::uint64_t mixture_samples() const override { return mixture_samples_; }
  bool moment_plausible() const override;
  FieldNoiseModel noise() const override { return sog_.noise(); }
  double converged_radius_m() const override { return sog_.converged_radius_m; }

  double cell_m() const { return cell_m_; }
  /// Covariance of s, the error the dead-reckoned path adds to every relative position.
  Mat3 drift_covariance() const { return error_covariance_.bottomRightCorner<3, 3>(); }
  /// The part of diag(drift_covariance()) applied to the cells so far: it trails by less than a
  /// tenth of a cell's variance per axis.
  const Vec3& diffused_variance() const { return diffused_; }

 private:
  struct Cell {
    Vec3 centre = Vec3::Zero();  ///< in G_1
    Vec3 m = Vec3::Zero();       ///< moment posterior mean (G axes)
    Mat3 M = Mat3::Zero();       ///< ... and covariance
    double log_w = 0.0;          ///< normalised
  };

  void initialise(const FieldMeasurement& measurement);
  /// The receiver's dead-reckoned pose moved by the odometry mean; the error covariance grows.
  void move_receiver(const Displacement& disp);
  /// The attitude reading: a Kalman update of [Psi, s]; s's correction shifts the grid.
  void read_attitude(const OrientationObservation& observation);
  /// Diffuses the cells by the growth of s's variance not yet applied (per axis).
  void diffuse();
  void diffuse_axis(int axis, double variance);
  void normalise_and_prune();
  void refine();
  Mat3 position_covariance() const;

  SogConfig sog_;
  GridFilterConfig config_;
  std::string rescuer_id_;
  std::uint32_t signal_id_;
  std::vector<Cell> cells_;
  double cell_m_ = 1.0;
  Vec3 receiver_ = Vec3::Zero();       ///< antenna in G_1
  Vec3 attitude_ = Vec3::Zero();       ///< rpy of R_k
  /// Covariance of the dead-reckoning error [Psi (rpy), s (m)].
  Eigen::Matrix<double, 6, 6> error_covariance_ = Eigen::Matrix<double, 6, 6>::Identity();
  Vec3 diffused_ = Vec3::Zero();       ///< the part of diag(s's variance) already applied as diffusion
  Vec3 origin_ = Vec3::Zero();         ///< a lattice point: every centre is origin_ + cell_m_ * integers
  Vec3 heard_at_ = Vec3::Zero();       ///< antenna in G_1 at the last sample heard
  Vec3 last_field_g_ = Vec3::Zero();   ///< R_k z of the last sample heard (refinement's moment gradient)
  OdometryAccumulator odometry_;
  DetectionCurve detection_;
  InnovationRecord record_;
  std::optional<std::uint64_t> last_sequence_;
  TimestampNs last_stamp_ = 0;
  std::uint64_t mixture_samples_ = 0;
  mutable std::optional<MixtureMoments> moments_;
};

}  // namespace sarloc::avalanche
