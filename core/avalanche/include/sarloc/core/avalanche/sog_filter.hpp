#pragma once
// Robocentric Sum-of-Gaussians filter for one avalanche transmitter (seed 000, Algorithm 1).
//
// One SogFilter per (rescuer, separated signal): nothing is global, several victims are several
// filters. Each Gaussian carries x = [Psi, p, m] (dipole_model.hpp) in the rescuer-centred,
// ENU-aligned frame G_k. Per field measurement:
//   1. prediction: x* = [x; d], P* = blkdiag(P, Q) (eq. (10)-(11), C_k = 0 because odometry
//      is independent of the state; the block structure is used, never a dense 15x15 product);
//   2. EKF update with the dipole model (eq. (14)), weight update in log space (eq. (17)), on
//      the valid axes only and sign-invariant: a real receiver measures the field up to its
//      sign, so p(z | x) = (N(z; h, S) + N(-z; h, S)) / 2 (issue 12); h is the field the
//      receiver resolves at the carrier (SogConfig::field_carrier_hz) and the receiver's fixed
//      calibration errors E are consider parameters (z = (I + E) h, Schmidt-Kalman:
//      SogComponent::calibration_cross);
//   3. composition back to G_k (eq. (9), (15)):
//        P_k = F P*_post F^T = F_x P F_x^T + F_d Q F_d^T - M S^-1 M^T,  M = F_x P H_x^T + F_d Q H_d^T;
//   4. optional attitude-sensor update (OrientationObservation), a linear update of Psi;
//   5. pruning of negligible weights and merging of near-duplicates found by spatial hashing
//      (never an all-pairs pass).
// The first measurement initialises the mixture (section III-B, see SogConfig).
//
//   SogFilter filter(SogConfig{});            // config validated here
//   filter.add_odometry(odo);                  // any number between measurements
//   SogStepResult r = filter.process(field);   // first call initialises
//   VictimEstimate e = filter.estimate(5);     // reduced mixture, eq. (18)
#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "sarloc/core/avalanche/detection_curve.hpp"
#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/avalanche/dipole_window_fit.hpp"
#include "sarloc/core/avalanche/field_fit.hpp"
#include "sarloc/core/avalanche/field_measurement.hpp"
#include "sarloc/core/avalanche/field_noise_model.hpp"
#include "sarloc/core/avalanche/odometry_accumulator.hpp"
#include "sarloc/core/avalanche/receiver_model.hpp"
#include "sarloc/core/avalanche/responder_types.hpp"
#include "sarloc/core/avalanche/transmitter_filter.hpp"
#include "sarloc/core/avalanche/transmitter_standard.hpp"

namespace sarloc::avalanche {

/// The receiver's calibration errors E, 3x3 row-major (SogConfig::calibration_variance).
inline constexpr int kCalibrationDim = 9;
using CalibrationVec = Eigen::Matrix<double, kCalibrationDim, 1>;
using CalibrationCross = Eigen::Matrix<double, idx::kStateDim, kCalibrationDim>;

/// Every parameter of the filter, with its default and source (docs/estimation/avalanche.md).
struct SogConfig {
  // --- initialisation (seed 000, section III-B) ---
  /// Seed 000 (section V) opens with 1700; 600 cover the same ring with wider Gaussians and
  /// find, as accurately and no slower, at a third of the opening's cost, with a NEES nearer
  /// its bounds (docs/estimation/avalanche.md, "Fewer Gaussians at the opening", issue 64).
  std::uint32_t initial_components = 600;
  TransmitterStandard standard;             ///< moment bounds m_min, m_max (EN 300 718)
  double antenna_height_m = 1.0;   ///< receiver antenna above the snow surface
  double max_burial_depth_m = 3.0; ///< 95 % of burials are shallower (seed 000, ref. [9])
  std::uint32_t depth_layers = 1;  ///< Gaussians stacked over the depth range
  double depth_sigma_factor = 0.6; ///< sigma_z = factor * layer thickness
  /// Near field: a ring first heard this close is cut into thinner layers, each with sigma_z at
  /// most this fraction of r_min, so that 1/r^3 stays near linear over one Gaussian (a 1.8 m
  /// layer 5 m from the antenna is not: seen converging 1 m off a 3.9 m deep victim with a
  /// NEES of 60). 0 = the configured layers at every range.
  double near_field_depth_sigma_per_range = 0.15;
  /// ... and those layers reach this deep: the depths one layer over max_burial_depth_m covered
  /// to 2 sigma, which thin layers alone would no longer cover.
  double near_field_burial_depth_m = 5.0;
  /// A near-field ring, cut into up to 20 layers, opens with this many Gaussians instead of
  /// initial_components: seed 000's 1700, since 600 spread over 20 layers lost multiple burials'
  /// signals separated at the cluster (docs/estimation/avalanche.md, "Fewer Gaussians at the opening").
  std::uint32_t near_field_initial_components = 1700;
  double horizontal_overlap = 0.55;///< sigma_xy = overlap * grid spacing (hexagonal grid)
  double max_range_m = 90.0;       ///< receivers do not detect beyond this (NOTES: 40-70 m)
  double range_noise_sigmas = 3.0; ///< widen r_min/r_max by this many sigma of |z_1| noise
  double moment_margin = 0.15;     ///< keep hypotheses whose implied |m| is within bounds +-15 %
  bool jacobian_initial_weights = true;  ///< w0 ~ r^9/|m|^2 (change of variables z->m), else 1/n
  Vec3 attitude_prior_sigma_rad = Vec3(0.035, 0.035, 0.087);  ///< used without an orientation obs
  // --- measurement noise known to the filter (same model as the simulator) ---
  double noise_relative = 0.05;         ///< per-axis sigma = relative * |h(x)| + floor
  double noise_floor_A_per_m = 2.1e-9;  ///< >= strongest on-axis field at 60 m / 10
  /// The field noise model of these two keys (every filter's, the search's).
  FieldNoiseModel noise() const { return FieldNoiseModel{noise_relative, noise_floor_A_per_m}; }
  /// The transmitter's carrier (EN 300 718): a receiver resolves the major axis of the full
  /// dipole field at this frequency (DipoleField::major_axis), which differs from the
  /// quasi-static field of eq. (12) by about (k r)^2 / 2: 0.5 % at 10 m, 11 % at 50 m. Modelled with the
  /// quasi-static field, the filter was over-confident with the realistic receiver (pooled NEES
  /// 3.57 with a device free of calibration error; docs/estimation/avalanche.md, "The field a
  /// receiver resolves"). 0: the quasi-static field, what seed 000's ideal receiver measures.
  double field_carrier_hz = 457000.0;
  double wavenumber() const { return carrier_wavenumber(field_carrier_hz); }
  /// This configuration with the quasi-static field and no calibration errors: the field model
  /// of seed 000, which the particle and grid baselines keep (their moment is linear in the
  /// field, docs/estimation/baselines.md); they build their first hypotheses with it.
  SogConfig quasi_static() const;
  /// The receiver's calibration tolerance (1 sigma): each antenna's gain error, and its pointing
  /// error towards each of the other two (ReceiverModelConfig::gain_sigma,
  /// misalignment_sigma_deg). Fixed per device, they are carried as consider parameters (a
  /// Schmidt-Kalman filter: their correlation with the state is tracked, they are never
  /// estimated), not as white noise the filter would average out (docs/estimation/avalanche.md,
  /// "Calibration as consider parameters"). 0 for both: a receiver without calibration error
  /// (seed 000's ideal one).
  double calibration_gain_sigma = 0.03;
  double calibration_pointing_sigma_deg = 1.0;
  /// Variances of the calibration errors E (z = (I + E) h), row-major: E(a, a) a gain, E(a, b) a
  /// pointing error of antenna a towards axis b.
  CalibrationVec calibration_variance() const;
  /// An axis the receiver reports invalid is below this many times its noise (the receiver's
  /// detection threshold, ReceiverModelConfig::detect_snr): used when initialising.
  double censored_axis_sigmas = 3.0;
  /// Every update, not only the first, reads an invalid axis as 0 with its noise floor raised to
  /// censored_axis_sigmas times its noise (plus the relative term of any axis): "below
  /// detection" bounds the field there; predictive_fit still asks the valid axes only. Without
  /// it an update sees the valid axes only, and a mixture fed one-axis pulses from the
  /// detection floor was seen converged on a single Gaussian 48 m from its transmitter, kept
  /// while the rescuer walked to 1.5 m of it (docs/estimation/avalanche.md, "Left"). Off:
  /// measured worse on multiple burials (the same page).
  bool censored_axes_in_update = false;
  // --- odometry ---
  double idle_translation_sigma_m = 0.02;  ///< displacement sigma when no odometry arrived
  double idle_rotation_sigma_rad = 0.005;
  // --- orientation observations ---
  bool use_orientation = true;  ///< apply FieldMeasurement::orientation when present
  /// The transmitter is buried: weight each Gaussian by P(p_z <= -antenna_height_m), which
  /// removes the point-symmetric mirror solution H(r) = H(-r) of the dipole above the receiver.
  bool surface_constraint = false;
  /// The transmitter obeys EN 300 718: weight each Gaussian by P(|m| within the standard's
  /// bounds widened by moment_margin), |m| linearised along its mean. It undoes a mixture that
  /// settled on a source 12 m deep with a fifth of the smallest moment allowed (fed another
  /// transmitter's pulses), but measured on multiple burials it confirmed more ghosts (5 against
  /// 1 in 400 trials): off (docs/estimation/avalanche.md).
  bool moment_constraint = false;
  /// Innovation gate (seed 001, "innovation test"): when even the best Gaussian's normalised
  /// innovation squared exceeds chi2_3(reinit_gate_probability) for reinit_after consecutive
  /// steps, no hypothesis explains the data any more (the true one was pruned while the signal
  /// was at the noise floor): the mixture is re-initialised from the current measurement.
  double reinit_gate_probability = 0.9999;
  std::uint32_t reinit_after = 0;  ///< 0 = never re-initialise (default: measured worse)
  /// Divergence test over a window (seed 001, "innovation test", summed over time): if the sum
  /// of the smallest normalised innovation squared of the last n steps exceeds
  /// chi2_{3n}(reinit_gate_probability), no Gaussian's innovation sequence is consistent with
  /// the noise model (each component's own sum is >= the sum of the per-step minima), i.e. the
  /// mixture has lost the transmitter (locked on a wrong mode while the signal was at the
  /// noise floor). The mixture is then re-initialised from the current measurement, which is
  /// stronger than the first one, so the new ring is narrower. A window, unlike n consecutive
  /// single-step failures, catches a persistent moderate excess (NIS 15-50 every step) that
  /// single-step gates miss half of the time. Neither test re-initialises a converged
  /// mixture (SogStepResult::divergence_ignored). 0 = off.
  std::uint32_t divergence_window = 6;
  /// ... except a converged mixture whose window sum exceeds its gate more than this many times
  /// over (recent_innovation_ratio): that is a lost transmitter, not linearisation, and it is
  /// rebuilt like any other.
  double converged_divergence_ratio = 3.0;
  /// Leap test (issue 12, multiple burials): a converged mixture whose position posterior
  /// leaves the tightest posterior it had (moved with the odometry) by more than
  /// chi2_3(leap_gate_probability), under both covariances, is re-initialised from the current
  /// measurement. A consistent filter's mean stays within its earlier posterior (single burial,
  /// 400 trials: no converged leap above 16); a signal that took another transmitter's pulses
  /// drifts out of it while its radius shrinks, and without the test stood over as a FOUND
  /// between the two (seen: 1.3 m from either victim, stated 95 % radius 0.25 m). 0 = off.
  double leap_gate_probability = 0.999;
  /// Within this range of the receiver a converged mixture's leap is not acted on: there the
  /// linearised update itself moves the mean by more than its posterior (the reason converged
  /// mixtures are exempt from the divergence test), and a ring rebuilt from a near-field
  /// sample converged 1.6 m off a victim (4 victims seed 2, trial 43: leaps at 1.4-2.4 m).
  double leap_min_range_m = 3.0;
  /// What the latest samples say (DipoleWindowFit, window_reaches()): the filter keeps its last
  /// this-many samples, placed where they were taken, and one dipole fitted to them at once
  /// tells how far from the estimate they alone allow the transmitter. A filter collapsed early
  /// on a wrong place near a deep victim was FOUND 1.2 m off with a 0.29 m radius, where its last
  /// 11 samples allowed 1.22 m (docs/estimation/avalanche.md, "What the latest samples say").
  /// 0 = off (no window: it allows nothing).
  std::uint32_t window_fit_samples = 24;
  /// The window's region: where the profile likelihood is within chi2_3 of this of its best.
  double window_region_probability = 0.95;
  /// A converged mixture that has pinned down nothing a transmitter could be (its moment outside
  /// the standard's bounds, or above the receiver) for this many updates in a row is rebuilt
  /// from z_k: it fits the data, so neither the divergence nor the leap test undoes it (seen: a
  /// source 12 m deep with a fifth of the smallest moment, under a rescuer standing 47 m from
  /// the cluster for 500 s; 3 victims, seed 1, trial 88). 0 = off.
  std::uint32_t implausible_rebuild_steps = 20;
  /// Iterated EKF update (Gauss-Newton on each component): within a metre or two of the
  /// transmitter the 1/r^3 field is far from linear over a component's spread, and one EKF step
  /// can leave it off by a metre with a small covariance. After the ordinary step, a component
  /// whose field at the updated state differs from the linear prediction by more than
  /// relinearise_threshold_sigmas (Mahalanobis, measurement noise) is re-linearised at that
  /// state, up to this many times. Its weight stays the prior-linearised likelihood. 0 = off.
  std::uint32_t iterated_update_max = 4;
  double relinearise_threshold_sigmas = 0.5;
  // --- negative information (issue 12): a pulse due and not heard ---
  /// A FieldMeasurement with valid_axes = 0 says a whole pulse of this signal was due in the
  /// window and nothing was detected on its carrier or over it (SignalSeparator). Each Gaussian
  /// is weighted by P(not detected | it) (DetectionCurve). false: such samples are ignored.
  bool negative_information = true;
  /// The detector's threshold on its statistic for a tracked carrier over the longest window a
  /// device listens (2 s: 41.3 at the detector's defaults; 39.8 for 1 s). Higher says less.
  double miss_detection_statistic = 41.5;
  /// The predicted pulse power (noncentrality) is multiplied by this: what the model leaves out
  /// (a moment estimate too large, the device's gain errors) makes a miss tell less, never more.
  double miss_power_margin = 0.5;
  /// No single miss lowers a Gaussian's weight by more than this factor: a miss the model did
  /// not foresee (a pulse lost to interference) cannot erase the transmitter's hypothesis.
  double miss_weight_floor = 1e-3;
  // --- mixture management ---
  double prune_log_weight = 14.0;   ///< drop components with log w < max log w - this
  std::uint32_t merge_interval = 1; ///< merge near-duplicates every n steps (0 = never)
  double merge_cell_m = 0.5;        ///< spatial-hash cell size for merge candidates
  double merge_mahalanobis = 1.0;   ///< merge j into i when (x_j-x_i)^T P_i^-1 (x_j-x_i) < this
  std::uint32_t max_components = 20000;  ///< hard cap on the initial mixture size
  double converged_radius_m = 2.0;  ///< estimate() reports kConverged below this 95 % radius

  /// Throws ConfigError "sog.<key> = value: rule".
  void validate() const;
};

struct SogComponent {
  StateVec x = StateVec::Zero();
  StateCov P = StateCov::Identity();
  /// Cov(x, E): how the state's error is tied to the receiver's calibration errors
  /// (SogConfig::calibration_gain_sigma); zero when the filter carries none.
  CalibrationCross calibration_cross = CalibrationCross::Zero();
  double log_weight = 0.0;  ///< normalised: log-sum-exp over components = 0
  /// log P(the priors: transmitter below the snow surface, moment within the standard) already
  /// folded into log_weight (SogConfig::surface_constraint, moment_constraint); kept so that each
  /// step applies only the change.
  double log_support = 0.0;
};

struct SogStepResult {
  bool initialised_now = false;        ///< this measurement initialised the mixture
  std::size_t components_before = 0;
  std::size_t components_after = 0;
  std::size_t dropped_numerical = 0;   ///< components removed: non-finite or non-PD covariance
  std::size_t merged = 0;
  double log_likelihood = 0.0;         ///< log p(z_k | Z^{k-1}) up to a constant
  double min_nis = 0.0;                ///< smallest normalised innovation squared (3 dof)
  bool reinitialised = false;          ///< innovation gate failed: mixture rebuilt from z_k
  /// The gate failed on a converged mixture (95 % radius <= converged_radius_m): taken for
  /// near-field linearisation error, not a lost transmitter, so the mixture is kept.
  bool divergence_ignored = false;
  /// A pulse due and not heard (valid_axes = 0) reweighted the mixture; log_likelihood is then
  /// log P(not detected | everything so far), up to the same constant.
  bool miss = false;
  /// Squared Mahalanobis distance (3 dof) of the position posterior from the tightest one
  /// before it, moved with the odometry, under both covariances: a consistent filter's mean
  /// never leaves its earlier posterior by much; a signal that took another transmitter's pulses does.
  double leap_d2 = 0.0;
  /// leap_d2 failed the leap gate on a converged mixture at least leap_min_range_m away: the
  /// mixture was rebuilt from z_k.
  bool leapt = false;
  /// Converged on no plausible transmitter for implausible_rebuild_steps updates: rebuilt from z_k.
  bool rebuilt_implausible = false;
};

class SogFilter : public TransmitterFilter {
 public:
  explicit SogFilter(SogConfig config = {}, std::string rescuer_id = {},
                     std::uint32_t signal_id = 0);

  std::string kind() const override { return "sog"; }
  /// Odometry of this rescuer; accumulated until the next field measurement.
  void add_odometry(const Odometry& odometry) override;
  /// Unmeasured motion since the last measurement (OdometryAccumulator::add_unknown).
  void add_unknown_motion(const DispCov& covariance) { odometry_.add_unknown(covariance); }
  /// One field measurement: initialises on the first call, then Algorithm 1. One with no valid
  /// axis is a pulse due and not heard: it moves the mixture to this sample's frame and weights
  /// each Gaussian by P(not detected) (SogConfig::negative_information); before the first
  /// measurement it only advances the sequence.
  /// Throws InputError for unusable input (non-finite, absurd, non-PD, out of order).
  SogStepResult process(const FieldMeasurement& measurement);
  /// process() as the filter interface reports it.
  FilterStepResult update(const FieldMeasurement& measurement) override;

  bool initialised() const override { return !components_.empty(); }
  /// Evidence that conflicts: `other`, a filter of the same signal given the same odometry up to
  /// the same latest sample (so in the same frame), holds the other half of the mixture from now
  /// on; the samples to come decide between them. Returns false (nothing changed) unless both are
  /// initialised at the same stamp.
  bool add_hypotheses(const SogFilter& other);
  /// The innovation record of the current mixture: its window is divergence_window, its gates
  /// chi2_{3n}(reinit_gate_probability).
  const InnovationRecord& innovations() const override { return record_; }
  /// The mixture's moment magnitude within the transmitter standard's bounds (moment_margin
  /// wider, 2 sigma): an estimate needing a transmitter the standard does not allow is wrong
  /// (seen: a FOUND 1.8 m off with |m| 8x the largest allowed, and one at the antenna with 1.4x).
  bool moment_plausible() const override;
  std::size_t size() const override { return components_.size(); }
  FieldNoiseModel noise() const override { return config_.noise(); }
  double converged_radius_m() const override { return config_.converged_radius_m; }
  const std::vector<SogComponent>& components() const { return components_; }
  const SogConfig& config() const { return config_; }
  std::uint64_t steps() const { return steps_; }
  /// Field samples the current mixture was built from and updated with (1 after a rebuild): a
  /// rebuilt mixture is a new guess, and a guess converged in a few near-field samples next to a
  /// cluster is no victim (SearchConfig::confirm_min_samples counts these).
  std::uint64_t mixture_samples() const override { return mixture_samples_; }
  /// Whether the window's samples alone allow the transmitter `distance` (m) or farther from the
  /// mixture's mean: a point of their 95 % region (SogConfig::window_region_probability) that far
  /// out along the window fit's principal axes or the line to the mean (8 directions: a curved
  /// region may reach farther between them). false with fewer than 10 samples in the window (or
  /// window_fit_samples, if fewer); true when no dipole fits them. Remembered for the update it was
  /// asked on (a dozen small fits: about a millisecond).
  bool window_reaches(double distance) const override;

  /// Eq. (18) over the full state (angles averaged relative to the heaviest component).
  MixtureMoments moments() const override;
  /// moments() moved by the odometry received since the last measurement (composition of
  /// eq. (9) on the mixture mean, no update): where the transmitter is relative to the receiver
  /// now, for guidance when this signal was not heard. Position covariance grows by the step's.
  MixtureMoments predicted_moments() const override;
  /// Where the antenna was at the last measurement with a pulse heard, relative to the receiver
  /// now (same composition on the mixture's attitude): the place the signal was last heard.
  Vec3 predicted_last_measurement_position() const override;
  /// Reduced mixture: position moments (eq. (18)), the top_k components, the mean moment.
  /// status is kInitialising, kMultimodal or kConverged; SearchController::assess() refines it.
  VictimEstimate estimate(std::size_t top_k = 5) const override;
  /// The components' means with their weights.
  std::vector<TransmitterHypothesis> hypotheses() const override;

  /// How well a sample would fit this signal's transmitter, the odometry received since the
  /// last measurement applied, without updating: log p(field | everything so far), up to a
  /// constant common to every filter, and the best component's NIS (field_fit.hpp). The
  /// receiver's separation asks it. nullopt before initialisation or for bad input.
  std::optional<FieldFit> predictive_fit(const Vec3& field, const Vec3& noise, std::uint8_t axes) const;

  /// Per-axis noise floor the filter applies to `m`: max(config floor, m.noise_stddev).

  /// Initialise directly from a measurement (normally done by the first process()).
  void initialise(const FieldMeasurement& measurement);

  /// Where the first sample puts the transmitter (seed 000, section III-B): a cylinder ring
  /// around the receiver, r_min..r_max from |z_1| and the standard's moments, down to the burial
  /// depth the near field asks for. The ring initialise() covers with Gaussians, and the grid
  /// filter with cells. Throws InputError as process() does.
  struct InitialRing {
    Vec3 field = Vec3::Zero();       ///< z_1, invalid axes zeroed (receiver frame)
    Vec3 field_g = Vec3::Zero();     ///< R(Psi_1) z_1
    Vec3 attitude = Vec3::Zero();    ///< Psi_1: the attitude reading, or 0
    Mat3 attitude_covariance = Mat3::Identity();
    Vec3 sigma_axis = Vec3::Zero();  ///< noise of z_1 per axis (censored axes: their bound)
    double moment_min = 0.0;         ///< the standard's bounds widened by moment_margin
    double moment_max = 0.0;
    double r_min_m = 0.0;
    double r_max_m = 0.0;
    double depth_m = 0.0;            ///< below the antenna height
    std::uint32_t layers = 1;
    double rho_min_m = 0.0;          ///< horizontal radii of the ring
    double rho_max_m = 0.0;
  };
  InitialRing initial_ring(const FieldMeasurement& measurement) const;

 private:
  void update_field(const Vec3& z, const Vec3& floor, std::uint8_t axes, const Displacement& disp,
                    const OrientationObservation* orientation, SogStepResult& r);
  /// log P(transmitter of c below the snow surface) (SogConfig::surface_constraint) + log P(its
  /// moment within the standard) (SogConfig::moment_constraint); 0 for each that is off.
  double prior_log_support(const SogComponent& c) const;
  void apply_priors();
  /// Below the receiver (2 sigma) with a moment the standard allows: a converged mixture that
  /// may have pinned down a transmitter, whose innovation excess the divergence test forgives.
  bool pinned_down_plausibly() const;
  void normalise_and_prune();
  /// The miss update (see process()); returns its log-likelihood.
  double apply_miss(const Vec3& floor);
  std::size_t merge();

  SogConfig config_;
  std::string rescuer_id_;
  std::uint32_t signal_id_ = 0;
  std::vector<SogComponent> components_;
  OdometryAccumulator odometry_;
  DetectionCurve detection_;
  std::optional<std::uint64_t> last_sequence_;
  TimestampNs last_stamp_ = 0;
  /// Where the last pulse was heard, in the current frame: 0 unless misses moved the frame since.
  Vec3 heard_at_ = Vec3::Zero();
  /// The tightest position posterior so far, moved with the odometry (its noise added).
  struct PositionAnchor {
    Vec3 position = Vec3::Zero();
    Mat3 covariance = Mat3::Zero();
  };
  std::optional<PositionAnchor> anchor_;
  void move_anchor(const Displacement& disp);
  /// The window's samples moved to the frame after `disp` on the attitude of `mm` (the
  /// mixture's moments before it), their position variance grown by it.
  void move_window(const MixtureMoments& mm, const Displacement& disp);
  /// This sample (already composed into the current frame) joins the window.
  void remember_sample(const Vec3& field, const Vec3& floor, std::uint8_t axes);
  std::deque<WindowSample> window_;
  std::uint64_t updates_ = 0;  ///< process() calls: what window_reaches()'s cache is keyed on
  struct ReachCache {
    std::uint64_t update = 0;
    double distance = 0.0;
    bool reaches = false;
  };
  mutable std::optional<ReachCache> reach_cache_;
  /// The mixture re-initialised from this measurement (divergence or leap).
  void rebuild(const FieldMeasurement& measurement, SogStepResult& result);
  /// Squared Mahalanobis distance of the position posterior from the anchor; tightens it.
  double leap_from_anchor();
  std::uint64_t steps_ = 0;
  std::uint64_t mixture_samples_ = 0;
  std::uint32_t gate_failures_ = 0;
  std::uint32_t implausible_steps_ = 0;  ///< updates in a row converged on no plausible transmitter
  InnovationRecord record_;
  double nis_gate_ = 0.0;
  double leap_gate_ = 0.0;          ///< chi2_3(leap_gate_probability); 0 = off
};

}  // namespace sarloc::avalanche
