#include "sarloc/core/avalanche/sog_filter.hpp"

#include <bitset>
#include <cmath>

#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/common/chi_square.hpp"

#include "sog_filter_detail.hpp"

namespace sarloc::avalanche {
using namespace sog_detail;  // the shared private helpers (sog_filter_detail.hpp)


SogFilter::SogFilter(SogConfig config, std::string rescuer_id, std::uint32_t signal_id)
    : config_(std::move(config)),
      rescuer_id_(std::move(rescuer_id)),
      signal_id_(signal_id),
      odometry_((config_.validate(), config_.idle_translation_sigma_m),
                config_.idle_rotation_sigma_rad),
      detection_(config_.miss_detection_statistic),
      record_(config_.divergence_window, config_.reinit_gate_probability),
      nis_gate_(chi_square_quantile(config_.reinit_gate_probability, 3.0)),
      leap_gate_(config_.leap_gate_probability > 0.0 ? chi_square_quantile(config_.leap_gate_probability, 3.0) : 0.0) {}

void SogFilter::add_odometry(const Odometry& odometry) {
  if (!rescuer_id_.empty() && !odometry.rescuer_id.empty() && odometry.rescuer_id != rescuer_id_)
    throw InputError("odometry.rescuer_id = " + odometry.rescuer_id + ": filter belongs to " +
                     rescuer_id_);
  odometry_.add(odometry);
}

SogStepResult SogFilter::process(const FieldMeasurement& measurement) {
  check_sample(measurement, rescuer_id_, last_sequence_);
  ++updates_;
  SogStepResult result;
  if (measurement.valid_axes == 0) {
    // A pulse of this signal was due and not heard: nothing to initialise from or update with,
    // but where the transmitter would have been heard it is not.
    last_sequence_ = measurement.sequence;
    if (!initialised() || !config_.negative_information) return result;
    result.components_before = components_.size();
    last_stamp_ = measurement.stamp;  // the mixture moves to this sample's frame
    result.log_likelihood = apply_miss(config_.noise().floor(measurement.noise_stddev));
    result.miss = true;
    result.components_after = components_.size();
    return result;
  }
  if (!initialised()) {
    initialise(measurement);
    odometry_.take();  // motion before the first measurement is irrelevant
    result.initialised_now = true;
    result.components_after = components_.size();
    last_sequence_ = measurement.sequence;
    last_stamp_ = measurement.stamp;
    steps_ = 1;
    return result;
  }
  last_sequence_ = measurement.sequence;
  last_stamp_ = measurement.stamp;
  heard_at_ = Vec3::Zero();
  result.components_before = components_.size();
  const MixtureMoments before = moments();
  const double radius95_before = radius95_3d(before.covariance.block<3, 3>(idx::kPos, idx::kPos));
  const Displacement disp = odometry_.take();
  move_anchor(disp);
  move_window(before, disp);
  const OrientationObservation* orientation =
      measurement.orientation && config_.use_orientation ? &*measurement.orientation : nullptr;
  Vec3 floor = config_.noise().floor(measurement.noise_stddev);
  std::uint8_t axes = measurement.valid_axes;
  Vec3 field = measurement.field;
  if (config_.censored_axes_in_update) {
    // An axis below detection is read as 0 with the detection threshold as its noise floor.
    for (int a = 0; a < 3; ++a) {
      if ((axes & (1U << a)) != 0) continue;
      field[a] = 0.0;
      floor[a] *= config_.censored_axis_sigmas;
    }
    axes = kAllAxes;
  }
  update_field(field, floor, axes, disp, orientation, result);
  record_.add(result.min_nis, static_cast<int>(std::bitset<3>(axes).count()), radius95_before);
  gate_failures_ = result.min_nis > nis_gate_ ? gate_failures_ + 1 : 0;
  bool diverged = config_.reinit_after > 0 && gate_failures_ >= config_.reinit_after;
  diverged = diverged || record_.window_exceeded();
  // A converged mixture is not at the noise floor: an innovation excess there comes from
  // linearising the dipole model within a metre or two of the transmitter, and rebuilding the
  // ring from such a near-field measurement lost a victim already pinned down (measured: found
  // 0.8-1.9 m off, NEES > 700).
  // A converged mixture that pinned down nothing a transmitter could be (a moment outside the
  // standard, or above the receiver: the mirror H(r) = H(-r)) has no such excuse (seen: a
  // mirror 6 m up with |m| near 0, "converged" for 350 steps while the rescuer circled under it).
  // Nor one whose innovations exceed the window's gate several times over: linearisation leaves
  // NIS 20-25 on a sample or two, not 40-400 on every one (seen, multiple burials: a mixture
  // rebuilt from another transmitter's pulse converged 2.6 m off, its NIS 57-67 three samples in a
  // row, its covariance collapsing meanwhile; kept, it crept and was confirmed 0.7 m off with a
  // 0.2 m radius).
  if (diverged && estimate(0).status == EstimatorStatus::kConverged && pinned_down_plausibly() &&
      record_.recent_ratio() <= config_.converged_divergence_ratio) {
    diverged = false;
    result.divergence_ignored = true;
  }
  if (diverged) {
    rebuild(measurement, result);
    ++steps_;
    return result;
  }
  apply_priors();
  normalise_and_prune();
  remember_sample(measurement.field, config_.noise().floor(measurement.noise_stddev), measurement.valid_axes);
  ++steps_;
  ++mixture_samples_;
  if (config_.merge_interval > 0 && steps_ % config_.merge_interval == 0) result.merged = merge();
  result.components_after = components_.size();
  result.leap_d2 = leap_from_anchor();
  // Far out, a ring's moment-matched covariance is a poor summary of it and its mean may jump
  // between modes (single burial: leaps up to 35 at radii of 12-97 m): only a converged mixture
  // is held to its past.
  if (leap_gate_ > 0.0 && result.leap_d2 > leap_gate_) {
    const VictimEstimate now = estimate(0);
    result.leapt = now.status >= EstimatorStatus::kConverged &&
                   now.relative.position.norm() >= config_.leap_min_range_m;
  }
  if (result.leapt) {
    rebuild(measurement, result);
    return result;
  }
  implausible_steps_ = estimate(0).status >= EstimatorStatus::kConverged && !pinned_down_plausibly()
                           ? implausible_steps_ + 1
                           : 0;
  if (config_.implausible_rebuild_steps > 0 && implausible_steps_ >= config_.implausible_rebuild_steps) {
    result.rebuilt_implausible = true;
    rebuild(measurement, result);
  }
  return result;
}

bool SogFilter::add_hypotheses(const SogFilter& other) {
  if (!initialised() || !other.initialised() || other.last_stamp_ != last_stamp_) return false;
  const double half = std::log(0.5);  // both mixtures are normalised: each keeps half the mass
  for (SogComponent& c : components_) c.log_weight += half;
  for (SogComponent c : other.components_) {
    c.log_weight += half;
    components_.push_back(c);
  }
  anchor_.reset();  // a new posterior: the leap test starts from it
  ++updates_;       // and a new reach
  return true;
}

void SogFilter::rebuild(const FieldMeasurement& measurement, SogStepResult& result) {
  initialise(measurement);  // a new ring, a new innovation history, no anchor
  result.reinitialised = true;
  result.components_after = components_.size();
}

std::vector<TransmitterHypothesis> SogFilter::hypotheses() const {
  std::vector<TransmitterHypothesis> out;
  out.reserve(components_.size());
  for (const SogComponent& c : components_)
    out.push_back({c.x.segment<3>(idx::kPos), c.x.segment<3>(idx::kMom), std::exp(c.log_weight)});
  return out;
}

FilterStepResult SogFilter::update(const FieldMeasurement& measurement) {
  const SogStepResult r = process(measurement);
  FilterStepResult out;
  out.initialised_now = r.initialised_now;
  out.reinitialised = r.reinitialised;
  out.miss = r.miss;
  out.hypotheses_after = r.components_after;
  out.min_nis = r.min_nis;
  return out;
}

MixtureMoments SogFilter::predicted_moments() const {
  return moved_moments(moments(), odometry_.peek());
}

Vec3 SogFilter::predicted_last_measurement_position() const {
  const Displacement& d = odometry_.peek();
  if (d.samples == 0) return heard_at_;
  return moved_point(moments(), heard_at_, d.mean);
}

}  // namespace sarloc::avalanche
