#pragma once
// The filter interface of one avalanche transmitter seen by one rescuer: what the search control
// (SearchController), the guidance and the evaluation need, whatever represents the posterior.
// Implementations (docs/estimation/baselines.md):
//   SogFilter          sum of Gaussians, seed 000 Algorithm 1 (the default)
//   ParticleFilter     vanilla (seed 000 Algorithm 2), Rao-Blackwellized (Algorithm 3) and the
//                      improved RBPF, one implementation configured three ways
//   GridFilter         histogram over the transmitter position (seed 001), the reference
// All of them take the same measurements (realistic receiver: sign-invariant likelihood, invalid
// axes left out, pulses due and not heard), the same odometry and attitude readings, and keep
// the same innovation record for the confirmation gates.
//
//   std::unique_ptr<TransmitterFilter> f = make_transmitter_filter(FilterKind::kRbpf, setup, seed);
//   f->add_odometry(odo);
//   FilterStepResult r = f->update(measurement);
//   Guidance g = controller.guide(*f, measurement);
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sarloc/core/avalanche/field_measurement.hpp"
#include "sarloc/core/avalanche/field_noise_model.hpp"
#include "sarloc/core/avalanche/innovation_record.hpp"
#include "sarloc/core/avalanche/responder_types.hpp"
#include "sarloc/core/avalanche/transmitter_hypothesis.hpp"
#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/avalanche/odometry_accumulator.hpp"
#include "sarloc/core/avalanche/transmitter_standard.hpp"

namespace sarloc::avalanche {

/// Moments of the posterior (seed 000 eq. (18) for a mixture) over the full state [Psi, p, m].
struct MixtureMoments {
  StateVec mean = StateVec::Zero();
  StateCov covariance = StateCov::Zero();
};

/// Moments moved by a displacement not yet measured against (composition of eq. (9) on the
/// mean, no update): the position covariance grows by the step's translation, T Q_tt T^T.
MixtureMoments moved_moments(const MixtureMoments& moments, const Displacement& displacement);
/// A point of the current frame moved by displacement d, on the attitude of `moments`.
Vec3 moved_point(const MixtureMoments& moments, const Vec3& point, const DispVec& d);

/// The checks every filter makes on a sample before it touches its posterior: the sample itself
/// (validate_field_measurement), its rescuer (when both are named) and its sequence (above
/// `last_sequence`). Throws InputError naming the field and value.
void check_sample(const FieldMeasurement& measurement, const std::string& rescuer_id,
                  const std::optional<std::uint64_t>& last_sequence);

/// The VictimEstimate every filter reports: `hypotheses` live Gaussians, particles or cells whose
/// moments are `moments` (none: kInitialising), kConverged below `converged_radius_m` (95 %,
/// 3-D), and the top_k heaviest of them, summary_of(i) for hypothesis i of weight weight_of(i).
VictimEstimate estimate_from(const MixtureMoments& moments, std::size_t hypotheses, double converged_radius_m,
                             std::size_t top_k, const std::function<double(std::size_t)>& weight_of,
                             const std::function<MixtureComponentSummary(std::size_t)>& summary_of);

/// TransmitterFilter::moment_plausible for a filter whose posterior has `moments`: the mean moment
/// and its spread allowed by `standard` within `margin`.
bool moment_plausible_from(const MixtureMoments& moments, const TransmitterStandard& standard, double margin);

/// What every filter reports about one update.
struct FilterStepResult {
  bool initialised_now = false;  ///< this measurement initialised the filter
  bool reinitialised = false;    ///< the filter was rebuilt from this measurement
  bool miss = false;             ///< a pulse due and not heard reweighted the posterior
  bool resampled = false;        ///< particle filters: the effective sample size fell below its threshold
  std::size_t hypotheses_after = 0;  ///< Gaussians, particles or live cells after the update
  /// NIS of the sample: the smallest over the Gaussians (SOG: each carries its covariance); of the
  /// moment-matched predictive for point particles and cells (PredictiveMoments).
  double min_nis = 0.0;
};

class TransmitterFilter {
 public:
  virtual ~TransmitterFilter() = default;

  /// "sog", "pf", "rbpf", "rbpf-improved" or "grid".
  virtual std::string kind() const = 0;
  /// Odometry of this rescuer; accumulated until the next field measurement.
  virtual void add_odometry(const Odometry& odometry) = 0;
  /// One field measurement: the first with a valid axis initialises; one with none is a pulse
  /// due and not heard. Throws InputError for unusable input (validate_field_measurement).
  virtual FilterStepResult update(const FieldMeasurement& measurement) = 0;

  virtual bool initialised() const = 0;
  /// Gaussians, particles or live cells.
  virtual std::size_t size() const = 0;
  virtual MixtureMoments moments() const = 0;
  /// moments() moved by the odometry received since the last measurement (no update).
  virtual MixtureMoments predicted_moments() const = 0;
  /// Where the antenna was at the last sample heard, relative to the receiver now.
  virtual Vec3 predicted_last_measurement_position() const = 0;
  /// Position moments, status kInitialising / kMultimodal / kConverged, the top_k hypotheses.
  virtual VictimEstimate estimate(std::size_t top_k = 5) const = 0;
  /// The posterior as weighted hypotheses (weights sum to 1), for the opening heading.
  virtual std::vector<TransmitterHypothesis> hypotheses() const = 0;

  /// The innovation history of the current posterior (the confirmation gates read it).
  virtual const InnovationRecord& innovations() const = 0;
  /// Samples the current posterior was built from and updated with (1 after a rebuild).
  virtual std::uint64_t mixture_samples() const = 0;
  /// The posterior's moment magnitude within the transmitter standard's bounds (2 sigma).
  virtual bool moment_plausible() const = 0;
  /// Whether the filter's latest samples alone allow the transmitter `distance` (m) or farther
  /// from the estimate (95 %): a filter's confidence may come from a history that was wrong
  /// (SogFilter::window_reaches). false for a filter that keeps no window of samples (the
  /// particle and grid baselines).
  virtual bool window_reaches(double /*distance*/) const { return false; }

  /// The field noise model the filter applies (field_noise_model.hpp).
  virtual FieldNoiseModel noise() const = 0;
  /// estimate() reports kConverged below this 95 % radius.
  virtual double converged_radius_m() const = 0;
};

}  // namespace sarloc::avalanche
