#include "sarloc/core/avalanche/sog_filter.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <bitset>
#include <cmath>
#include <limits>
#include <sstream>
#include <unordered_map>

#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"
#include "sarloc/core/common/gaussian.hpp"

namespace sarloc::avalanche {
namespace {

template <typename T>
[[noreturn]] void config_fail(const char* key, const T& value, const char* rule) {
  detail::throw_config_error(std::string("sog.") + key, config_value(static_cast<double>(value)), rule);
}

[[noreturn]] void config_fail(const char* key, const std::string& value_text, const char* rule) {
  detail::throw_config_error(std::string("sog.") + key, value_text, rule);
}

[[noreturn]] void input_fail(const std::string& field, const std::string& value,
                             const std::string& rule) {
  throw InputError("field_measurement." + field + " = " + value + ": " + rule);
}

std::string fmt(const Vec3& v) {
  std::ostringstream os;
  os << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return os.str();
}

bool finite_positive(double v) { return std::isfinite(v) && v > 0.0; }

// A ring heard from a few metres needs no thinner layers than this (0.25 m over 5 m).
constexpr double kMaxNearFieldLayers = 20.0;

// x with its angles re-expressed next to ref's, so that averaging never crosses +-pi.
StateVec near_angles(StateVec x, const StateVec& ref) {
  for (int k = 0; k < 3; ++k)
    x[idx::kAtt + k] = ref[idx::kAtt + k] + wrap_angle(x[idx::kAtt + k] - ref[idx::kAtt + k]);
  return x;
}

// F_x P F_x^T + F_d Q F_d^T of the composition (eq. (9), (15)), block by block: the covariance
// of a component moved by a displacement before any measurement's correction.
StateCov composed_covariance(const StateCov& p, const CompositionJacobians& f, const DispCov& q) {
  // F_x P F_x^T: apply F_x on the left twice.
  auto apply_f = [&](const StateCov& m) {
    StateCov fm = m;
    fm.middleRows<3>(idx::kAtt) = f.att_att * m.middleRows<3>(idx::kAtt);
    fm.middleRows<3>(idx::kPos) += f.pos_att * m.middleRows<3>(idx::kAtt);
    return fm;
  };
  const StateCov fp = apply_f(p);
  StateCov p_new = apply_f(fp.transpose());
  // F_d Q F_d^T: rows Psi <- dPsi (D), rows p <- t (T).
  const Mat3 q_tt = q.block<3, 3>(idx::kTrans, idx::kTrans);
  const Mat3 q_tr = q.block<3, 3>(idx::kTrans, idx::kRot);
  const Mat3 q_rr = q.block<3, 3>(idx::kRot, idx::kRot);
  const Mat3 psi_psi = f.att_rot * q_rr * f.att_rot.transpose();
  const Mat3 psi_pos = f.att_rot * q_tr.transpose() * f.pos_trans.transpose();
  p_new.block<3, 3>(idx::kAtt, idx::kAtt) += psi_psi;
  p_new.block<3, 3>(idx::kAtt, idx::kPos) += psi_pos;
  p_new.block<3, 3>(idx::kPos, idx::kAtt) += psi_pos.transpose();
  p_new.block<3, 3>(idx::kPos, idx::kPos) += f.pos_trans * q_tt * f.pos_trans.transpose();
  return p_new;
}

// Index list 0 .. n-1 (every component) for moments_of.
struct AllIndices {
  std::size_t n;
  std::size_t size() const { return n; }
  std::size_t operator[](std::size_t k) const { return k; }
};

// Eq. (18) over the listed components, in list order, angles relative to ref; the weights are
// exp(log_weight - log_base). The one moment match of the filter: moments() and merge().
template <typename Indices>
GaussianMoments<idx::kStateDim> moments_of(const std::vector<SogComponent>& components,
                                           const Indices& members, const StateVec& ref,
                                           double log_base) {
  return match_moments<idx::kStateDim>(
      members.size(),
      [&](std::size_t k) {
        const SogComponent& c = components[members[k]];
        return WeightedGaussianRef<idx::kStateDim>{c.log_weight, near_angles(c.x, ref), c.P};
      },
      log_base);
}

}  // namespace

void SogConfig::validate() const {
  if (initial_components == 0) config_fail("initial_components", initial_components, "must be > 0");
  if (initial_components > max_components)
    config_fail("initial_components", initial_components, "must be <= max_components");
  if (max_components == 0) config_fail("max_components", max_components, "must be > 0");
  standard.validate("sog.standard");
  if (!std::isfinite(antenna_height_m) || antenna_height_m < 0.0 || antenna_height_m > 10.0)
    config_fail("antenna_height_m", antenna_height_m, "must be in [0, 10]");
  if (!finite_positive(max_burial_depth_m) || max_burial_depth_m > 20.0)
    config_fail("max_burial_depth_m", max_burial_depth_m, "must be in (0, 20]");
  if (depth_layers == 0 || depth_layers > 20)
    config_fail("depth_layers", depth_layers, "must be in [1, 20]");
  if (!finite_positive(depth_sigma_factor) || depth_sigma_factor > 5.0)
    config_fail("depth_sigma_factor", depth_sigma_factor, "must be in (0, 5]");
  if (!std::isfinite(near_field_depth_sigma_per_range) || near_field_depth_sigma_per_range < 0.0 ||
      near_field_depth_sigma_per_range > 1.0)
    config_fail("near_field_depth_sigma_per_range", near_field_depth_sigma_per_range, "must be in [0, 1]");
  if (!finite_positive(near_field_burial_depth_m) || near_field_burial_depth_m > 20.0)
    config_fail("near_field_burial_depth_m", near_field_burial_depth_m, "must be in (0, 20]");
  if (!finite_positive(horizontal_overlap) || horizontal_overlap > 5.0)
    config_fail("horizontal_overlap", horizontal_overlap, "must be in (0, 5]");
  if (!finite_positive(max_range_m) || max_range_m > 500.0)
    config_fail("max_range_m", max_range_m, "must be in (0, 500]");
  if (!std::isfinite(range_noise_sigmas) || range_noise_sigmas < 0.0 || range_noise_sigmas > 10.0)
    config_fail("range_noise_sigmas", range_noise_sigmas, "must be in [0, 10]");
  if (!std::isfinite(moment_margin) || moment_margin < 0.0 || moment_margin >= 1.0)
    config_fail("moment_margin", moment_margin, "must be in [0, 1)");
  for (int i = 0; i < 3; ++i) {
    if (!finite_positive(attitude_prior_sigma_rad[i]) || attitude_prior_sigma_rad[i] > kPi)
      config_fail("attitude_prior_sigma_rad", fmt(attitude_prior_sigma_rad),
                  "each must be in (0, pi]");
  }
  if (!std::isfinite(noise_relative) || noise_relative < 0.0 || noise_relative > 1.0)
    config_fail("noise_relative", noise_relative, "must be in [0, 1]");
  if (!finite_positive(censored_axis_sigmas) || censored_axis_sigmas > 20.0)
    config_fail("censored_axis_sigmas", censored_axis_sigmas, "must be in (0, 20]");
  if (!finite_positive(noise_floor_A_per_m) || noise_floor_A_per_m > 1e-3)
    config_fail("noise_floor_A_per_m", noise_floor_A_per_m, "must be in (0, 1e-3]");
  if (!finite_positive(idle_translation_sigma_m) || idle_translation_sigma_m > 10.0)
    config_fail("idle_translation_sigma_m", idle_translation_sigma_m, "must be in (0, 10]");
  if (!finite_positive(idle_rotation_sigma_rad) || idle_rotation_sigma_rad > kPi)
    config_fail("idle_rotation_sigma_rad", idle_rotation_sigma_rad, "must be in (0, pi]");
  if (!finite_positive(prune_log_weight) || prune_log_weight > 700.0)
    config_fail("prune_log_weight", prune_log_weight, "must be in (0, 700]");
  if (!finite_positive(merge_cell_m) || merge_cell_m > 100.0)
    config_fail("merge_cell_m", merge_cell_m, "must be in (0, 100]");
  if (!std::isfinite(merge_mahalanobis) || merge_mahalanobis < 0.0 || merge_mahalanobis > 100.0)
    config_fail("merge_mahalanobis", merge_mahalanobis, "must be in [0, 100]");
  if (!(reinit_gate_probability > 0.5 && reinit_gate_probability < 1.0))
    config_fail("reinit_gate_probability", reinit_gate_probability, "must be in (0.5, 1)");
  if (iterated_update_max > 20)
    config_fail("iterated_update_max", iterated_update_max, "must be in [0, 20]");
  if (!finite_positive(relinearise_threshold_sigmas) || relinearise_threshold_sigmas > 100.0)
    config_fail("relinearise_threshold_sigmas", relinearise_threshold_sigmas, "must be in (0, 100]");
  if (!(leap_gate_probability == 0.0 || (leap_gate_probability > 0.5 && leap_gate_probability < 1.0)))
    config_fail("leap_gate_probability", leap_gate_probability, "must be 0 (off) or in (0.5, 1)");
  if (!std::isfinite(leap_min_range_m) || leap_min_range_m < 0.0 || leap_min_range_m > 100.0)
    config_fail("leap_min_range_m", leap_min_range_m, "must be in [0, 100]");
  if (implausible_rebuild_steps > 10000)
    config_fail("implausible_rebuild_steps", implausible_rebuild_steps, "must be in [0, 10000]");
  if (!(converged_divergence_ratio >= 1.0 && converged_divergence_ratio <= 1e6))
    config_fail("converged_divergence_ratio", converged_divergence_ratio, "must be in [1, 1e6]");
  if (divergence_window > 100)
    config_fail("divergence_window", divergence_window, "must be in [0, 100]");
  if (!finite_positive(converged_radius_m) || converged_radius_m > 1000.0)
    config_fail("converged_radius_m", converged_radius_m, "must be in (0, 1000]");
  if (!finite_positive(miss_detection_statistic) || miss_detection_statistic > 1e4)
    config_fail("miss_detection_statistic", miss_detection_statistic, "must be in (0, 1e4]");
  if (!finite_positive(miss_power_margin) || miss_power_margin > 1.0)
    config_fail("miss_power_margin", miss_power_margin, "must be in (0, 1] (a miss never tells more than the model)");
  if (!finite_positive(miss_weight_floor) || miss_weight_floor > 1.0)
    config_fail("miss_weight_floor", miss_weight_floor, "must be in (0, 1]");
}

void validate_field_measurement(const FieldMeasurement& m) {
  if (!m.field.allFinite()) input_fail("field", fmt(m.field), "must be finite");
  if (m.field.norm() > 10.0) input_fail("field", fmt(m.field), "|field| must be <= 10 A/m");
  if (!m.noise_stddev.allFinite() || m.noise_stddev.minCoeff() < 0.0 ||
      m.noise_stddev.maxCoeff() > 1.0)
    input_fail("noise_stddev", fmt(m.noise_stddev), "must be finite and in [0, 1] A/m");
  if (m.valid_axes > kAllAxes)
    input_fail("valid_axes", std::to_string(m.valid_axes), "must be a mask of axes 0-2 (0..7; 0: a pulse due, not heard)");
  if (m.orientation) {
    const auto& o = *m.orientation;
    if (!o.rpy.allFinite() || o.rpy.cwiseAbs().maxCoeff() > kPi + 1e-9)
      input_fail("orientation.rpy", fmt(o.rpy), "must be finite and within [-pi, pi]");
    if (std::fabs(o.rpy.y()) > 1.4)
      input_fail("orientation.rpy", fmt(o.rpy), "|pitch| must be <= 1.4 rad (Euler singularity)");
    if (!o.covariance.allFinite() || !o.covariance.isApprox(o.covariance.transpose(), 1e-9))
      input_fail("orientation.covariance", "non-finite or asymmetric", "must be symmetric");
    Eigen::LLT<Mat3> llt(o.covariance);
    if (llt.info() != Eigen::Success || o.covariance.diagonal().minCoeff() <= 0.0)
      input_fail("orientation.covariance", "diag " + fmt(o.covariance.diagonal()),
                 "must be positive definite");
  }
}

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
  const double radius95_before = radius95_3d(moments().covariance.block<3, 3>(idx::kPos, idx::kPos));
  const Displacement disp = odometry_.take();
  move_anchor(disp);
  const OrientationObservation* orientation =
      measurement.orientation && config_.use_orientation ? &*measurement.orientation : nullptr;
  update_field(measurement.field, config_.noise().floor(measurement.noise_stddev), measurement.valid_axes, disp,
               orientation, result);
  record_.add(result.min_nis, static_cast<int>(std::bitset<3>(measurement.valid_axes).count()), radius95_before);
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
  return true;
}

void SogFilter::rebuild(const FieldMeasurement& measurement, SogStepResult& result) {
  initialise(measurement);  // a new ring, a new innovation history, no anchor
  result.reinitialised = true;
  result.components_after = components_.size();
}

void SogFilter::move_anchor(const Displacement& disp) {
  if (!anchor_ || disp.samples == 0) return;
  const Vec3 before = anchor_->position;
  anchor_->position = moved_point(moments(), before, disp.mean);
  // The step's translation noise, and its heading noise turning the anchor about the rescuer.
  const double yaw_var = disp.covariance(idx::kRot + 2, idx::kRot + 2);
  anchor_->covariance += disp.covariance.block<3, 3>(idx::kTrans, idx::kTrans);
  anchor_->covariance.topLeftCorner<2, 2>() += yaw_var * before.head<2>().squaredNorm() * Eigen::Matrix2d::Identity();
}

double SogFilter::leap_from_anchor() {
  const MixtureMoments mm = moments();
  const Vec3 mean = mm.mean.segment<3>(idx::kPos);
  const Mat3 cov = mm.covariance.block<3, 3>(idx::kPos, idx::kPos);
  double d2 = 0.0;
  if (anchor_) {
    const Vec3 d = mean - anchor_->position;
    d2 = d.dot((anchor_->covariance + cov).ldlt().solve(d));
  }
  if (!anchor_ || cov.trace() < 0.5 * anchor_->covariance.trace()) anchor_ = PositionAnchor{mean, cov};
  return d2;
}

double SogFilter::apply_miss(const Vec3& floor) {
  // Move every Gaussian, and the place the signal was last heard, to where the rescuer stands
  // now (composition, no correction).
  const Displacement disp = odometry_.take();
  heard_at_ = moved_point(moments(), heard_at_, disp.mean);
  move_anchor(disp);
  for (auto& c : components_) {
    CompositionJacobians f;
    const StateVec x = CompositionModel::f(c.x, disp.mean, &f);
    c.P = composed_covariance(c.P, f, disp.covariance);
    c.P = 0.5 * (c.P + c.P.transpose()).eval();
    c.x = x;
  }
  // P(not detected | Gaussian): averaged over its sigma points in position and moment (kappa = 0,
  // 2n equal weights). One wide Gaussian spans ranges whose fields differ by orders of magnitude;
  // its mean alone would make it all heard or all unheard.
  const MeasurementModel here(DispVec::Zero());
  const Vec3 weight = floor.cwiseAbs2().cwiseInverse() * config_.miss_power_margin;
  auto p_miss = [&](const StateVec& x) {
    const Vec3 h = here.h(x);
    return 1.0 - detection_.probability(h.cwiseAbs2().dot(weight));
  };
  constexpr int kDim = 6;  // p and m, adjacent in the state
  static_assert(idx::kMom == idx::kPos + 3);
  double max_log_weight = -std::numeric_limits<double>::infinity();
  for (const auto& c : components_) max_log_weight = std::max(max_log_weight, c.log_weight);
  double evidence = 0.0;  // P(not detected | everything so far), relative to the heaviest Gaussian
  for (auto& c : components_) {
    const Eigen::LLT<Eigen::Matrix<double, kDim, kDim>> llt(c.P.block<kDim, kDim>(idx::kPos, idx::kPos));
    double p = 0.0;
    if (llt.info() != Eigen::Success) {
      p = p_miss(c.x);  // no spread to average over: its mean
    } else {
      const Eigen::Matrix<double, kDim, kDim> spread = std::sqrt(static_cast<double>(kDim)) * llt.matrixL().toDenseMatrix();
      for (int j = 0; j < kDim; ++j) {
        for (double side : {-1.0, 1.0}) {
          StateVec x = c.x;
          x.segment<kDim>(idx::kPos) += side * spread.col(j);
          p += p_miss(x);
        }
      }
      p /= 2.0 * kDim;
    }
    evidence += std::exp(c.log_weight - max_log_weight) * p;
    c.log_weight += std::log(std::max(p, config_.miss_weight_floor));
  }
  normalise_and_prune();
  return std::log(std::max(evidence, std::numeric_limits<double>::min())) + max_log_weight;
}

bool SogFilter::pinned_down_plausibly() const {
  const MixtureMoments mm = moments();
  const double z = mm.mean[idx::kPos + 2];
  const double sd_z = std::sqrt(std::max(0.0, mm.covariance(idx::kPos + 2, idx::kPos + 2)));
  return z + 2.0 * sd_z < 0.0 && moment_plausible();
}

bool SogFilter::moment_plausible() const {
  return !components_.empty() && moment_plausible_from(moments(), config_.standard, config_.moment_margin);
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

SogFilter::InitialRing SogFilter::initial_ring(const FieldMeasurement& meas) const {
  validate_field_measurement(meas);
  if (meas.valid_axes == 0) throw InputError("field_measurement.valid_axes = 0: a pulse not heard initialises nothing");
  InitialRing ring;
  // An invalid axis is below the receiver's detection threshold: the ring is built with it at
  // 0 +- censored_axis_sigmas times its noise (what "not detected" says), never dropped, since
  // the moment of each hypothesis needs all three components.
  Vec3 z = meas.field;
  const Vec3 floor = config_.noise().floor(meas.noise_stddev);
  Vec3 censored = Vec3::Zero();
  for (int a = 0; a < 3; ++a) {
    if ((meas.valid_axes & (1U << a)) != 0) continue;
    z[a] = 0.0;
    censored[a] = config_.censored_axis_sigmas * floor[a];
  }
  const double zn = z.norm();
  if (!(zn > 0.0)) input_fail("field", fmt(z), "first measurement must be non-zero on a valid axis");
  Vec3 psi0 = Vec3::Zero();
  Mat3 p_psi = config_.attitude_prior_sigma_rad.cwiseAbs2().asDiagonal();
  if (meas.orientation && config_.use_orientation) {
    psi0 = meas.orientation->rpy;
    p_psi = meas.orientation->covariance;
  }
  Vec3 sigma_axis = config_.noise().sigma(zn, floor);
  for (int a = 0; a < 3; ++a)
    if (censored[a] > 0.0) sigma_axis[a] = censored[a];
  const double sigma_norm = sigma_axis.norm();
  const double m_lo = config_.standard.moment_min() * (1.0 - config_.moment_margin);
  const double m_hi = config_.standard.moment_max() * (1.0 + config_.moment_margin);
  // Seed 000, section III-B: r_min = (m_min / (4 pi |z|))^(1/3), r_max = (2 m_max / (4 pi |z|))^(1/3),
  // evaluated at |z| +- k sigma so that noise cannot push the truth outside the ring.
  const double z_hi = zn + config_.range_noise_sigmas * sigma_norm;
  const double z_lo = zn - config_.range_noise_sigmas * sigma_norm;
  const double r_min = std::cbrt(m_lo / (4.0 * kPi * z_hi));
  const double r_max =
      z_lo > 0.0 ? std::min(config_.max_range_m, std::cbrt(2.0 * m_hi / (4.0 * kPi * z_lo)))
                 : config_.max_range_m;
  const double h = config_.antenna_height_m;
  double depth = config_.max_burial_depth_m;
  std::uint32_t layers = config_.depth_layers;
  const double sigma_z_cap = config_.near_field_depth_sigma_per_range * r_min;
  if (config_.depth_sigma_factor * depth / layers > sigma_z_cap && sigma_z_cap > 0.0) {
    depth = std::max(depth, config_.near_field_burial_depth_m);
    layers = std::max(layers, static_cast<std::uint32_t>(std::min(
                                  kMaxNearFieldLayers, std::ceil(config_.depth_sigma_factor * depth / sigma_z_cap))));
  }
  const double deepest = h + depth;
  ring.field = z;
  ring.attitude = psi0;
  ring.attitude_covariance = p_psi;
  ring.field_g = rotation_from_rpy(psi0) * z;
  ring.sigma_axis = sigma_axis;
  ring.moment_min = m_lo;
  ring.moment_max = m_hi;
  ring.r_min_m = r_min;
  ring.r_max_m = r_max;
  ring.depth_m = depth;
  ring.layers = layers;
  ring.rho_min_m = std::sqrt(std::max(0.0, r_min * r_min - deepest * deepest));
  ring.rho_max_m = std::max(r_max, ring.rho_min_m + 0.5);
  return ring;
}

void SogFilter::initialise(const FieldMeasurement& meas) {
  validate_field_measurement(meas);
  if (meas.valid_axes == 0) throw InputError("field_measurement.valid_axes = 0: a pulse not heard initialises nothing");
  heard_at_ = Vec3::Zero();
  anchor_.reset();
  gate_failures_ = 0;  // a new mixture starts a new innovation history
  implausible_steps_ = 0;
  mixture_samples_ = 1;
  record_.clear();
  const InitialRing ring = initial_ring(meas);
  const Vec3& z = ring.field;
  const Vec3& psi0 = ring.attitude;
  const Mat3& p_psi = ring.attitude_covariance;
  const Mat3 r_g = rotation_from_rpy(psi0);
  const Vec3& h_g = ring.field_g;
  const Vec3& sigma_axis = ring.sigma_axis;
  const double m_lo = ring.moment_min;
  const double m_hi = ring.moment_max;
  const double h = config_.antenna_height_m;
  const double depth = ring.depth_m;
  const std::uint32_t layers = ring.layers;
  const double rho_min = ring.rho_min_m;
  const double rho_max = ring.rho_max_m;
  const double thickness = depth / layers;
  const double sigma_z = config_.depth_sigma_factor * thickness;

  struct Candidate {
    Vec3 p;
    Vec3 m;
  };
  auto generate = [&](double s, bool check_moment, std::vector<Candidate>* out) {
    std::size_t count = 0;
    const double dy = s * std::sqrt(3.0) / 2.0;
    const int ny = static_cast<int>(std::ceil(rho_max / dy));
    for (int j = -ny; j <= ny; ++j) {
      const double y = j * dy;
      const double off = (j & 1) != 0 ? 0.5 * s : 0.0;
      const int nx = static_cast<int>(std::ceil(rho_max / s)) + 1;
      for (int i = -nx; i <= nx; ++i) {
        const double x = i * s + off;
        const double rho = std::hypot(x, y);
        if (rho > rho_max || rho < rho_min) continue;
        for (std::uint32_t l = 0; l < layers; ++l) {
          const Vec3 p(x, y, -(h + (l + 0.5) * thickness));
          const Vec3 m = DipoleField::moment(-p, h_g);
          if (check_moment) {
            const double mn = m.norm();
            if (mn < m_lo || mn > m_hi) continue;
          }
          ++count;
          if (out != nullptr) out->push_back({p, m});
        }
      }
    }
    return count;
  };
  const double target = config_.initial_components;
  const double area = kPi * (rho_max * rho_max - rho_min * rho_min);
  double s = std::sqrt(area * layers / target / (std::sqrt(3.0) / 2.0));
  bool check = true;
  std::size_t count = 0;
  for (int it = 0; it < 8; ++it) {
    count = generate(s, check, nullptr);
    if (count == 0) {
      if (!check) break;
      check = false;  // |z_1| inconsistent with the standard: fall back to the plain ring
      continue;
    }
    const double ratio = static_cast<double>(count) / target;
    if (std::fabs(ratio - 1.0) < 0.02) break;
    s *= std::sqrt(ratio);
  }
  // Never exceed the cap; shrink spacing only upward if needed.
  while (count > config_.max_components) {
    s *= 1.05;
    count = generate(s, check, nullptr);
  }
  std::vector<Candidate> cands;
  cands.reserve(count);
  generate(s, check, &cands);
  if (cands.empty()) input_fail("field", fmt(z), "no transmitter hypothesis fits this field");

  const double sigma_h = config_.horizontal_overlap * s;
  Mat3 p_pp = Mat3::Zero();
  p_pp.diagonal() << sigma_h * sigma_h, sigma_h * sigma_h, sigma_z * sigma_z;
  const Mat3 r_z = sigma_axis.cwiseAbs2().asDiagonal();
  const Mat3 dhg_dpsi = -skew(h_g) * euler_rate_to_world(psi0);

  components_.clear();
  components_.reserve(cands.size());
  for (const auto& c : cands) {
    Mat3 j_m_r, j_m_h;
    const Vec3 m = DipoleField::moment(-c.p, h_g, &j_m_r, &j_m_h);
    // m = g(Psi, p, z): linearised joint covariance (r = -p, h_G = R(Psi) z).
    const Mat3 g_p = -j_m_r;
    const Mat3 g_psi = j_m_h * dhg_dpsi;
    const Mat3 g_z = j_m_h * r_g;
    SogComponent comp;
    comp.x.segment<3>(idx::kAtt) = psi0;
    comp.x.segment<3>(idx::kPos) = c.p;
    comp.x.segment<3>(idx::kMom) = m;
    comp.P.setZero();
    comp.P.block<3, 3>(idx::kAtt, idx::kAtt) = p_psi;
    comp.P.block<3, 3>(idx::kPos, idx::kPos) = p_pp;
    comp.P.block<3, 3>(idx::kMom, idx::kMom) = g_p * p_pp * g_p.transpose() +
                                             g_psi * p_psi * g_psi.transpose() +
                                             g_z * r_z * g_z.transpose();
    comp.P.block<3, 3>(idx::kMom, idx::kPos) = g_p * p_pp;
    comp.P.block<3, 3>(idx::kPos, idx::kMom) = (g_p * p_pp).transpose();
    comp.P.block<3, 3>(idx::kMom, idx::kAtt) = g_psi * p_psi;
    comp.P.block<3, 3>(idx::kAtt, idx::kMom) = (g_psi * p_psi).transpose();
    // Change of variables z -> m: p(p | z_1) ~ p_m(m(p)) |det dm/dz| ~ r^9 / |m|^2.
    comp.log_weight = config_.jacobian_initial_weights
                          ? 9.0 * std::log(c.p.norm()) - 2.0 * std::log(m.norm())
                          : 0.0;
    components_.push_back(comp);
  }
  apply_priors();
  normalise_and_prune();
}

namespace {

// Linear Kalman update of Psi with an attitude-sensor reading (H = [I 0 0]); returns the
// log-likelihood of the reading (eq. (17) for this extra observation).
double orientation_update(SogComponent& c, const OrientationObservation& o) {
  Vec3 nu = o.rpy - c.x.segment<3>(idx::kAtt);
  for (int k = 0; k < 3; ++k) nu[k] = wrap_angle(nu[k]);
  const Mat3 s = c.P.block<3, 3>(idx::kAtt, idx::kAtt) + o.covariance;
  const Mat3 s_inv = s.inverse();
  const Jacobian<idx::kStateDim, 3> pht = c.P.middleCols<3>(idx::kAtt);
  const Jacobian<idx::kStateDim, 3> k = pht.lazyProduct(s_inv);
  c.x += k * nu;
  c.P.noalias() -= k.lazyProduct(pht.transpose());
  c.P = 0.5 * (c.P + c.P.transpose()).eval();
  c.x[idx::kAtt + 2] = wrap_angle(c.x[idx::kAtt + 2]);
  return -0.5 * (nu.dot(s_inv * nu) + std::log(s.determinant()));
}

// The estimation step of eq. (14) for one component on x* = [x; d], P* = blkdiag(P, Q), with the
// sign-invariant likelihood: what the update and the predictive likelihood share.
struct Innovation {
  Jacobian<idx::kStateDim, 3> pht;
  Jacobian<idx::kDispDim, 3> qht;
  Mat3 s_inv;
  Vec3 s_inv_nu;
  double sign = 1.0; ///< the sign of z that explains it best
  double nis = 0.0;  ///< the better sign's NIS
  double ll = 0.0;   ///< log p(z | component), common constants dropped
};

// h and its Jacobians at (x, d) with the invalid axes' rows zeroed, and the per-axis noise.
struct Linearisation {
  Vec3 h;
  Jacobian<3, idx::kStateDim> h_x;
  Jacobian<3, idx::kDispDim> h_d;
  Vec3 sigma;
};

Linearisation linearise(const StateVec& x, const MeasurementModel& measurement, const Vec3& floor, std::uint8_t axes,
                        const FieldNoiseModel& noise) {
  Linearisation l;
  l.h = measurement.h(x, &l.h_x, &l.h_d);
  l.sigma = noise.sigma(l.h.norm(), floor);
  // An invalid axis is no observation: its rows of h, H_x and H_d are zeroed and its
  // innovation variance set to 1, so S is block-diagonal, the axis's innovation is 0 and
  // the update, the NIS and the weights (up to a constant) are those of the valid axes.
  for (int a = 0; a < 3; ++a) {
    if ((axes & (1U << a)) != 0) continue;
    l.h[a] = 0.0;
    l.h_x.row(a).setZero();
    l.h_d.row(a).setZero();
  }
  return l;
}

// S = H_x P H_x^T + H_d Q H_d^T + R and the gains' P H^T, Q H^T; false if S is not positive.
bool innovation_covariance(const Linearisation& l, const StateCov& p, const DispCov& q, std::uint8_t axes,
                           Innovation& in, double& det) {
  in.pht = p.lazyProduct(l.h_x.transpose());
  in.qht = q.lazyProduct(l.h_d.transpose());
  Mat3 s = l.h_x * in.pht + l.h_d * in.qht;
  for (int a = 0; a < 3; ++a) s(a, a) += (axes & (1U << a)) != 0 ? l.sigma[a] * l.sigma[a] : 1.0;
  det = s.determinant();
  if (!(det > 0.0) || !std::isfinite(det)) return false;
  in.s_inv = s.inverse();
  return true;
}

// The innovation of component c linearised at its mean (l = linearise(c.x, ...)).
std::optional<Innovation> innovate(const SogComponent& c, const Linearisation& l, const Vec3& z_valid,
                                   std::uint8_t axes, const DispCov& q) {
  Innovation in;
  double det = 0.0;
  if (!innovation_covariance(l, c.P, q, axes, in, det)) return std::nullopt;
  // Sign-invariant likelihood: the receiver measures +-h, p(z) = (N(z; h, S) + N(-z; h, S)) / 2.
  // The component is updated with the sign that explains z best (zeta = z^T S^-1 h decides:
  // NIS(+-) = z^T S^-1 z + h^T S^-1 h -+ 2 zeta); its weight takes both terms.
  const double zeta = z_valid.dot(in.s_inv * l.h);
  in.sign = zeta >= 0.0 ? 1.0 : -1.0;
  const Vec3 nu = in.sign * z_valid - l.h;
  in.s_inv_nu = in.s_inv * nu;
  in.nis = nu.dot(in.s_inv_nu);
  const double nis_other = in.nis + 4.0 * std::fabs(zeta);
  // eq. (17) in log space (the common -1.5 log(2 pi) and log 1/2 are dropped).
  in.ll = -0.5 * (in.nis + std::log(det)) + std::log1p(std::exp(-0.5 * (nis_other - in.nis)));
  return in;
}

// Iterated EKF (Gauss-Newton on the augmented state [x; d]): re-linearise at the updated state
// while the field there differs from the linear prediction by more than threshold_sigmas.
// x_{i+1} = x0 + P H_i^T S_i^-1 (z - h(x_i) - H_i (x0 - x_i)); the returned gains and S^-1
// are those of the last linearisation (the posterior covariance uses them), nis and ll stay
// the prior-linearised ones (the component's weight is the predictive likelihood).
Innovation iterate(const SogComponent& c, const Linearisation& at_prior, const Innovation& first, const Vec3& z_valid,
                   const Vec3& floor, std::uint8_t axes, const DispVec& d0, const DispCov& q, const FieldNoiseModel& noise,
                   std::uint32_t max_iterations, double threshold_sigmas) {
  Innovation in = first;
  const Vec3 z = in.sign * z_valid;
  StateVec x_i = c.x + in.pht * in.s_inv_nu;
  DispVec d_i = d0 + in.qht * in.s_inv_nu;
  Linearisation l_prev = at_prior;
  StateVec x_prev = c.x;
  DispVec d_prev = d0;
  for (std::uint32_t it = 0; it < max_iterations; ++it) {
    const Linearisation l = linearise(x_i, MeasurementModel(d_i), floor, axes, noise);
    // How far the field at x_i is from what the last linearisation predicted there.
    const Vec3 linear = l_prev.h + l_prev.h_x * (x_i - x_prev) + l_prev.h_d * (d_i - d_prev);
    const Vec3 gap = (l.h - linear).cwiseQuotient(l.sigma);
    if (gap.squaredNorm() <= threshold_sigmas * threshold_sigmas) break;
    Innovation next = in;
    double det = 0.0;
    if (!innovation_covariance(l, c.P, q, axes, next, det)) break;
    const Vec3 nu = z - l.h - l.h_x * (c.x - x_i) - l.h_d * (d0 - d_i);
    next.s_inv_nu = next.s_inv * nu;
    const StateVec x_next = c.x + next.pht * next.s_inv_nu;
    const DispVec d_next = d0 + next.qht * next.s_inv_nu;
    if (!x_next.allFinite() || !d_next.allFinite()) break;
    in = next;
    l_prev = l;
    x_prev = x_i;
    d_prev = d_i;
    x_i = x_next;
    d_i = d_next;
  }
  return in;
}

}  // namespace

std::optional<FieldFit> SogFilter::predictive_fit(const Vec3& field, const Vec3& noise, std::uint8_t axes) const {
  if (components_.empty() || axes == 0 || axes > kAllAxes || !field.allFinite() || !noise.allFinite())
    return std::nullopt;
  const Displacement disp = odometry_.pending_displacement();
  const MeasurementModel measurement(disp.mean);
  const Vec3 floor = config_.noise().floor(noise);
  const Vec3 z_valid = valid_axes_only(field, axes);
  // log sum_i w_i p(z | i), accumulated stably; the log weights are normalised (every update
  // ends in normalise_and_prune, merging keeps the sum).
  double max_term = -std::numeric_limits<double>::infinity();
  double sum = 0.0;
  double min_nis = std::numeric_limits<double>::infinity();
  for (const SogComponent& c : components_) {
    const auto in = innovate(c, linearise(c.x, measurement, floor, axes, config_.noise()), z_valid, axes,
                             disp.covariance);
    if (!in) continue;
    min_nis = std::min(min_nis, in->nis);
    const double term = c.log_weight + in->ll;
    if (term > max_term) {
      sum = sum * std::exp(max_term - term) + 1.0;
      max_term = term;
    } else {
      sum += std::exp(term - max_term);
    }
  }
  if (sum == 0.0) return std::nullopt;
  return FieldFit{max_term + std::log(sum), min_nis};
}

void SogFilter::update_field(const Vec3& z, const Vec3& floor, std::uint8_t axes,
                             const Displacement& disp, const OrientationObservation* orientation,
                             SogStepResult& result) {
  const DispCov& q = disp.covariance;
  // h of eq. (14) linearised at the odometry mean: R(dPsi), E_w(dPsi) shared by every component.
  const MeasurementModel measurement(disp.mean);
  const FieldNoiseModel noise = config_.noise();
  const Vec3 z_valid = valid_axes_only(z, axes);
  double max_ll = -std::numeric_limits<double>::infinity();
  double min_nis = std::numeric_limits<double>::infinity();

  std::size_t out = 0;
  for (std::size_t i = 0; i < components_.size(); ++i) {
    SogComponent& c = components_[i];
    const StateCov& p = c.P;
    const Linearisation at_prior = linearise(c.x, measurement, floor, axes, noise);
    const auto innovation = innovate(c, at_prior, z_valid, axes, q);
    if (!innovation) {
      ++result.dropped_numerical;
      continue;
    }
    const Innovation updated = config_.iterated_update_max > 0
                                   ? iterate(c, at_prior, *innovation, z_valid, floor, axes, disp.mean, q, noise,
                                             config_.iterated_update_max, config_.relinearise_threshold_sigmas)
                                   : *innovation;
    const auto& [pht, qht, s_inv, s_inv_nu, sign, nis, ll] = updated;
    min_nis = std::min(min_nis, nis);
    const StateVec x_post = c.x + pht * s_inv_nu;
    const DispVec d_post = disp.mean + qht * s_inv_nu;

    // --- Composition step (eq. (9), (15)) evaluated at the posterior ---
    // F_x = [[A,0,0],[C,I,0],[0,0,I]], F_d = [[0,D],[T,0],[0,0]] (CompositionJacobians).
    CompositionJacobians f;
    const StateVec x_new = CompositionModel::f(x_post, d_post, &f);

    StateCov p_new = composed_covariance(p, f, q);
    // M = F_x P H_x^T + F_d Q H_d^T.
    Jacobian<idx::kStateDim, 3> mm = pht;
    mm.middleRows<3>(idx::kAtt) = f.att_att * pht.middleRows<3>(idx::kAtt) +
                                  f.att_rot * qht.middleRows<3>(idx::kRot);
    mm.middleRows<3>(idx::kPos) += f.pos_att * pht.middleRows<3>(idx::kAtt) +
                                   f.pos_trans * qht.middleRows<3>(idx::kTrans);
    const Jacobian<idx::kStateDim, 3> mm_s = mm.lazyProduct(s_inv);
    p_new.noalias() -= mm_s.lazyProduct(mm.transpose());
    p_new = 0.5 * (p_new + p_new.transpose()).eval();

    if (!p_new.allFinite() || !(p_new.diagonal().minCoeff() > 0.0) || !x_post.allFinite()) {
      ++result.dropped_numerical;
      continue;
    }
    SogComponent& dst = components_[out++];
    dst.x = x_new;
    dst.P = p_new;
    dst.log_weight = c.log_weight + ll;
    max_ll = std::max(max_ll, ll);
    // Optional attitude-sensor update on the composed state (same component, still in cache).
    if (orientation != nullptr) dst.log_weight += orientation_update(dst, *orientation);
  }
  components_.resize(out);
  result.log_likelihood = max_ll;
  result.min_nis = min_nis;
  if (components_.empty())
    throw InputError("field_measurement.field = " + fmt(z) +
                     ": every hypothesis became numerically invalid");
}

double SogFilter::prior_log_support(const SogComponent& c) const {
  double support = 0.0;
  if (config_.surface_constraint) {
    // log P(p_z <= surface) = log Phi((surface - mu_z) / sigma_z), surface = -antenna height.
    const double mu = c.x[idx::kPos + 2];
    const double sd = std::sqrt(c.P(idx::kPos + 2, idx::kPos + 2));
    support += log_normal_cdf((-config_.antenna_height_m - mu) / sd);
  }
  if (config_.moment_constraint) {
    // log P(lo <= |m| <= hi), |m| ~ N(|m_hat|, u' P_mm u), u = m_hat / |m_hat|; computed from
    // the nearer bound's tail so that it stays finite far outside.
    const Vec3 m = c.x.segment<3>(idx::kMom);
    const double mu = m.norm();
    if (mu > 0.0) {
      const Vec3 u = m / mu;
      const double sd = std::sqrt(std::max(u.dot(c.P.block<3, 3>(idx::kMom, idx::kMom) * u), 1e-30));
      const double a = (config_.standard.moment_min() * (1.0 - config_.moment_margin) - mu) / sd;
      const double b = (config_.standard.moment_max() * (1.0 + config_.moment_margin) - mu) / sd;
      // P = Phi(b) - Phi(a) = Phi(-a) - Phi(-b).
      const double near = a > -b ? log_normal_cdf(-a) : log_normal_cdf(b);
      const double far = a > -b ? log_normal_cdf(-b) : log_normal_cdf(a);
      support += near + std::log1p(-std::min(std::exp(far - near), 1.0 - 1e-16));
    }
  }
  return support;
}

void SogFilter::apply_priors() {
  if (!config_.surface_constraint && !config_.moment_constraint) return;
  for (auto& c : components_) {
    const double log_phi = prior_log_support(c);
    c.log_weight += log_phi - c.log_support;
    c.log_support = log_phi;
  }
}

void SogFilter::normalise_and_prune() {
  if (components_.empty()) return;
  double mx = -std::numeric_limits<double>::infinity();
  for (const auto& c : components_) mx = std::max(mx, c.log_weight);
  double sum = 0.0;
  for (const auto& c : components_) sum += std::exp(c.log_weight - mx);
  const double lse = mx + std::log(sum);
  const double cut = mx - lse - config_.prune_log_weight;
  std::size_t out = 0;
  for (auto& c : components_) {
    c.log_weight -= lse;
    if (c.log_weight >= cut) components_[out++] = c;
  }
  components_.resize(out);
  // Renormalise after pruning.
  sum = 0.0;
  for (const auto& c : components_) sum += std::exp(c.log_weight);
  const double ls = std::log(sum);
  for (auto& c : components_) c.log_weight -= ls;
}

std::size_t SogFilter::merge() {
  if (components_.size() < 2) return 0;
  // Spatial hash on the position mean: only components sharing a cell are compared. The cells
  // are found by sorting (key, index) pairs: O(n log n), no per-bucket allocation.
  const double inv_cell = 1.0 / config_.merge_cell_m;
  std::vector<std::pair<std::int64_t, std::uint32_t>> keyed(components_.size());
  for (std::uint32_t i = 0; i < components_.size(); ++i) {
    const Vec3 p = components_[i].x.segment<3>(idx::kPos) * inv_cell;
    const auto ix = static_cast<std::int64_t>(std::floor(p.x())) & 0x1FFFFF;
    const auto iy = static_cast<std::int64_t>(std::floor(p.y())) & 0x1FFFFF;
    const auto iz = static_cast<std::int64_t>(std::floor(p.z())) & 0x1FFFFF;
    keyed[i] = {(ix << 42) | (iy << 21) | iz, i};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<char> gone(components_.size(), 0);
  std::size_t merged = 0;
  std::vector<std::uint32_t> members;
  for (std::size_t begin = 0; begin < keyed.size();) {
    std::size_t end = begin + 1;
    while (end < keyed.size() && keyed[end].first == keyed[begin].first) ++end;
    if (end - begin < 2) {
      begin = end;
      continue;
    }
    members.clear();
    for (std::size_t k = begin; k < end; ++k) members.push_back(keyed[k].second);
    begin = end;
    std::sort(members.begin(), members.end(), [&](std::uint32_t a, std::uint32_t b) {
      return components_[a].log_weight > components_[b].log_weight;
    });
    for (std::size_t ii = 0; ii < members.size(); ++ii) {
      const std::uint32_t i = members[ii];
      if (gone[i]) continue;
      SogComponent& ci = components_[i];
      Eigen::LLT<StateCov> llt(ci.P);
      if (llt.info() != Eigen::Success) continue;
      std::vector<std::uint32_t> group;
      for (std::size_t jj = ii + 1; jj < members.size(); ++jj) {
        const std::uint32_t j = members[jj];
        if (gone[j]) continue;
        StateVec diff = components_[j].x - ci.x;
        for (int k = 0; k < 3; ++k) diff[idx::kAtt + k] = wrap_angle(diff[idx::kAtt + k]);
        if (diff.dot(llt.solve(diff)) < config_.merge_mahalanobis) group.push_back(j);
      }
      if (group.empty()) continue;
      // Moment-matched merge (eq. (18) restricted to the group), angles relative to i.
      group.push_back(i);
      const double base = ci.log_weight;
      const GaussianMoments<idx::kStateDim> merged_moments =
          moments_of(components_, group, ci.x, base);
      ci.x = merged_moments.mean;
      ci.x[idx::kAtt + 2] = wrap_angle(ci.x[idx::kAtt + 2]);  // a component's yaw is wrapped
      ci.P = 0.5 * (merged_moments.covariance + merged_moments.covariance.transpose());
      ci.log_weight = base + std::log(merged_moments.weight_sum);
      // The members' weights already carry their surface factor: restart the bookkeeping from
      // the merged Gaussian so later steps apply only the change.
      ci.log_support = prior_log_support(ci);
      for (std::size_t g = 0; g + 1 < group.size(); ++g) gone[group[g]] = 1;
      merged += group.size() - 1;
    }
  }
  if (merged == 0) return 0;
  std::size_t out = 0;
  for (std::size_t i = 0; i < components_.size(); ++i)
    if (!gone[i]) components_[out++] = components_[i];
  components_.resize(out);
  return merged;
}

MixtureMoments SogFilter::moments() const {
  MixtureMoments mm;
  if (components_.empty()) return mm;
  std::size_t best = 0;
  for (std::size_t i = 1; i < components_.size(); ++i)
    if (components_[i].log_weight > components_[best].log_weight) best = i;
  // Weights are normalised (log-sum-exp = 0): log_base 0.
  const GaussianMoments<idx::kStateDim> g =
      moments_of(components_, AllIndices{components_.size()}, components_[best].x, 0.0);
  mm.mean = g.mean;
  mm.covariance = g.covariance;
  return mm;
}

VictimEstimate SogFilter::estimate(std::size_t top_k) const {
  VictimEstimate e = estimate_from(
      components_.empty() ? MixtureMoments{} : moments(), components_.size(), config_.converged_radius_m, top_k,
      [&](std::size_t i) { return components_[i].log_weight; },
      [&](std::size_t i) {
        return MixtureComponentSummary{std::exp(components_[i].log_weight), components_[i].x.segment<3>(idx::kPos),
                                       components_[i].P.block<3, 3>(idx::kPos, idx::kPos)};
      });
  e.rescuer_id = rescuer_id_;
  e.signal_id = signal_id_;
  e.stamp = last_stamp_;
  return e;
}

}  // namespace sarloc::avalanche
