#include "sarloc/core/avalanche/particle_filter.hpp"

#include <algorithm>
#include <bitset>
#include <boost/random/normal_distribution.hpp>
#include <cmath>
#include <limits>
#include <numeric>

#include "sarloc/core/avalanche/moment_kalman.hpp"
#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "sarloc/core/common/particle_weights.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::avalanche {
namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6x = Eigen::Matrix<double, 6, 6>;

template <int N>
Eigen::Matrix<double, N, 1> standard_normal(std::mt19937_64& rng) {
  boost::random::normal_distribution<double> n01;
  Eigen::Matrix<double, N, 1> v;
  for (int i = 0; i < N; ++i) v[i] = n01(rng);
  return v;
}

// A lower-triangular square root of a covariance; a diagonal one if it is not positive definite.
template <int N>
Eigen::Matrix<double, N, N> square_root(const Eigen::Matrix<double, N, N>& cov) {
  const Eigen::LLT<Eigen::Matrix<double, N, N>> llt(cov);
  if (llt.info() == Eigen::Success) return llt.matrixL().toDenseMatrix();
  return cov.diagonal().cwiseMax(0.0).cwiseSqrt().asDiagonal();
}

}  // namespace

void ParticleFilterConfig::validate() const {
  check_range("particle", "particles", particles, 10, 1e6);
  check_range("particle", "improved_particles", improved_particles, 10, 1e6);
  check_range("particle", "resample_ess_fraction", resample_ess_fraction, 0.0, 1.0);
  check_range("particle", "moment_noise_relative", moment_noise_relative, 0.0, 1.0);
  check_range("particle", "regularisation_scale", regularisation_scale, 0.0, 2.0);
  check_range("particle", "regularise_below_radius_m", regularise_below_radius_m, 0.0, 1000.0);
}

ParticleFilter::ParticleFilter(FilterKind kind, SogConfig sog, ParticleFilterConfig config, std::uint64_t seed,
                               std::string rescuer_id, std::uint32_t signal_id)
    : kind_(kind),
      sog_((sog.validate(), sog.quasi_static())),
      config_((config.validate(), config)),
      count_(kind == FilterKind::kRbpfImproved ? config.improved_particles : config.particles),
      rescuer_id_(std::move(rescuer_id)),
      signal_id_(signal_id),
      rng_(seed),
      odometry_(sog_.idle_translation_sigma_m, sog_.idle_rotation_sigma_rad),
      detection_(sog_.miss_detection_statistic),
      record_(sog_.divergence_window, sog_.reinit_gate_probability) {
  if (kind != FilterKind::kPf && kind != FilterKind::kRbpf && kind != FilterKind::kRbpfImproved)
    throw ConfigError(std::string("filter = ") + to_string(kind) + ": not a particle filter");
}

void ParticleFilter::add_odometry(const Odometry& odometry) {
  if (!rescuer_id_.empty() && !odometry.rescuer_id.empty() && odometry.rescuer_id != rescuer_id_)
    throw InputError("odometry.rescuer_id = " + odometry.rescuer_id + ": filter belongs to " + rescuer_id_);
  odometry_.add(odometry);
}

FilterStepResult ParticleFilter::update(const FieldMeasurement& measurement) {
  check_sample(measurement, rescuer_id_, last_sequence_);
  last_sequence_ = measurement.sequence;
  FilterStepResult result;
  if (measurement.valid_axes == 0) {
    // A pulse due and not heard: where the transmitter would have been heard it is not.
    if (!initialised() || !sog_.negative_information) return result;
    last_stamp_ = measurement.stamp;
    const Displacement disp = odometry_.take();
    heard_at_ = moved_point(moments(), heard_at_, disp.mean);
    moments_.reset();
    const Mat6x root = square_root<6>(disp.covariance);
    for (Particle& q : particles_) propagate(q, disp.mean + root * standard_normal<6>(rng_));
    weigh_miss(sog_.noise().floor(measurement.noise_stddev));
    result.resampled = normalise_and_resample();
    result.miss = true;
    result.hypotheses_after = particles_.size();
    return result;
  }
  last_stamp_ = measurement.stamp;
  if (!initialised()) {
    initialise(measurement);
    odometry_.take();  // motion before the first measurement is irrelevant
    result.initialised_now = true;
    result.hypotheses_after = particles_.size();
    return result;
  }
  const double radius95_before = radius95_3d(position_covariance());
  const Displacement disp = odometry_.take();
  heard_at_ = Vec3::Zero();
  const OrientationObservation* orientation =
      measurement.orientation && sog_.use_orientation ? &*measurement.orientation : nullptr;
  result.min_nis = propagate_and_weigh(disp, orientation, measurement);
  record_.add(result.min_nis, static_cast<int>(std::bitset<3>(measurement.valid_axes).count()), radius95_before);
  if (kind_ == FilterKind::kRbpfImproved && config_.rebuild_on_divergence && record_.window_exceeded()) {
    initialise(measurement);
    ++rebuilds_;
    result.reinitialised = true;
    result.hypotheses_after = particles_.size();
    return result;
  }
  result.resampled = normalise_and_resample();
  ++mixture_samples_;
  result.hypotheses_after = particles_.size();
  return result;
}

void ParticleFilter::initialise(const FieldMeasurement& measurement) {
  // The SOG filter's ring (seed 000 section III-B) is the prior the particles are drawn from.
  SogFilter ring(sog_);
  ring.initialise(measurement);
  const std::vector<SogComponent>& components = ring.components();
  std::vector<double> log_w(components.size());
  for (std::size_t i = 0; i < components.size(); ++i) log_w[i] = components[i].log_weight;
  const std::vector<std::size_t> drawn = systematic_resample(normalised_weights(log_w), count_, rng_);
  particles_.clear();
  particles_.reserve(count_);
  std::size_t cached = components.size();
  Eigen::Matrix<double, 9, 9> root9 = Eigen::Matrix<double, 9, 9>::Zero();
  Mat6x root6 = Mat6x::Zero();
  Eigen::Matrix<double, 3, 6> gain = Eigen::Matrix<double, 3, 6>::Zero();  // E[m | Psi, p] = m + gain ([Psi, p] - mean)
  Mat3 m_cov = Mat3::Zero();
  for (std::size_t k : drawn) {
    const SogComponent& c = components[k];
    if (k != cached) {  // indices come sorted: each component's factors are found once
      cached = k;
      if (rao_blackwellized()) {
        const Mat6x p_ss = c.P.topLeftCorner<6, 6>();
        root6 = square_root<6>(p_ss);
        const Eigen::Matrix<double, 3, 6> p_ms = c.P.block<3, 6>(idx::kMom, 0);
        gain = p_ss.ldlt().solve(p_ms.transpose()).transpose();
        m_cov = c.P.block<3, 3>(idx::kMom, idx::kMom) - gain * p_ms.transpose();
        m_cov = 0.5 * (m_cov + m_cov.transpose()).eval();
      } else {
        root9 = square_root<9>(c.P);
      }
    }
    Particle q;
    Vec3 psi;
    if (rao_blackwellized()) {
      const Vec6 ds = root6 * standard_normal<6>(rng_);
      psi = c.x.segment<3>(idx::kAtt) + ds.head<3>();
      q.p = c.x.segment<3>(idx::kPos) + ds.tail<3>();
      q.m = c.x.segment<3>(idx::kMom) + gain * ds;
      q.M = m_cov;
    } else {
      const StateVec x = c.x + root9 * standard_normal<9>(rng_);
      psi = x.segment<3>(idx::kAtt);
      q.p = x.segment<3>(idx::kPos);
      q.m = x.segment<3>(idx::kMom);
    }
    q.rotation = rotation_from_rpy(psi);
    q.log_w = -std::log(static_cast<double>(drawn.size()));  // weights are kept normalised
    particles_.push_back(q);
  }
  record_.clear();
  mixture_samples_ = 1;
  heard_at_ = Vec3::Zero();
  moments_.reset();
}

void ParticleFilter::propagate(Particle& q, const DispVec& d) {
  // Algorithm 2-3, first line: each particle samples its own displacement from the odometry.
  CompositionModel::compose_pose(q.rotation, q.p, d);
  if (kind_ == FilterKind::kPf && config_.moment_noise_relative > 0.0) {
    const double sd = config_.moment_noise_relative * q.m.norm();
    q.m += sd * standard_normal<3>(rng_);
  }
}

double ParticleFilter::propagate_and_weigh(const Displacement& disp, const OrientationObservation* orientation,
                                           const FieldMeasurement& measurement) {
  // One pass over the particles: the cloud does not fit in the cache.
  moments_.reset();
  const Mat6x root = square_root<6>(disp.covariance);
  // The attitude reading's residual from the rotation matrices, without Euler angles per particle:
  // R = exp([delta]x) R_obs, delta = vee(R R_obs^T - R_obs R^T) / 2 (small angles: the reading
  // is within degrees), and delta = E_w(Psi_obs) dPsi.
  Mat3 r_obs = Mat3::Identity(), to_rate = Mat3::Identity(), info = Mat3::Zero();
  if (orientation != nullptr) {
    r_obs = rotation_from_rpy(orientation->rpy);
    to_rate = world_to_euler_rate(orientation->rpy);
    info = orientation->covariance.inverse();
  }
  const FieldNoiseModel noise = sog_.noise();
  const Vec3 floor = noise.floor(measurement.noise_stddev);
  const Vec3 z_valid = valid_axes_only(measurement.field, measurement.valid_axes);
  PredictiveMoments predictive;
  for (Particle& q : particles_) {
    const double prior = std::exp(q.log_w);
    propagate(q, disp.mean + root * standard_normal<6>(rng_));
    if (orientation != nullptr) {  // the attitude reading, a likelihood on Psi
      const Mat3 d = q.rotation * r_obs.transpose();
      const Vec3 nu = to_rate * (0.5 * Vec3(d(2, 1) - d(1, 2), d(0, 2) - d(2, 0), d(1, 0) - d(0, 1)));
      q.log_w -= 0.5 * nu.dot(info * nu);
    }
    if (!(q.p.norm() > 1e-3)) {  // on the antenna: no field model there
      q.log_w = -std::numeric_limits<double>::infinity();
      continue;
    }
    const MomentUpdate u = update_moment(moment_gain(q.rotation, q.p), q.m, q.M, z_valid, floor,
                                         measurement.valid_axes, noise);
    if (!u.ok) {
      q.log_w = -std::numeric_limits<double>::infinity();
      continue;
    }
    q.log_w += u.ll;
    predictive.add(prior, u);
  }
  return predictive.nis(z_valid);
}

void ParticleFilter::weigh_miss(const Vec3& floor) {
  // P(not detected | particle) at its moment's mean (DetectionCurve; the SOG filter averages
  // over each Gaussian's spread, a particle is a point).
  const Vec3 weight = floor.cwiseAbs2().cwiseInverse() * sog_.miss_power_margin;
  moments_.reset();
  for (Particle& q : particles_) {
    if (!(q.p.norm() > 1e-3)) continue;
    const Vec3 h = moment_gain(q.rotation, q.p) * q.m;
    const double p = 1.0 - detection_.probability(h.cwiseAbs2().dot(weight));
    q.log_w += std::log(std::max(p, sog_.miss_weight_floor));
  }
}

bool ParticleFilter::normalise_and_resample() {
  std::vector<double> log_w(particles_.size());
  for (std::size_t i = 0; i < particles_.size(); ++i) log_w[i] = particles_[i].log_w;
  moments_.reset();
  std::vector<double> w;
  try {
    w = normalised_weights(log_w);
  } catch (const std::invalid_argument&) {
    // No particle explains the sample at all: keep the cloud at equal weights (the data
    // decide from the next sample on; the innovation record says it did not fit).
    w.assign(particles_.size(), 1.0 / static_cast<double>(particles_.size()));
  }
  for (std::size_t i = 0; i < particles_.size(); ++i) particles_[i].log_w = std::log(w[i]);
  last_ess_ = effective_sample_size(w);
  if (last_ess_ >= config_.resample_ess_fraction * static_cast<double>(particles_.size())) return false;
  const std::vector<std::size_t> drawn = systematic_resample(w, count_, rng_);
  std::vector<Particle> next;
  next.reserve(drawn.size());
  const double equal = -std::log(static_cast<double>(drawn.size()));  // weights are kept normalised
  for (std::size_t k : drawn) {
    next.push_back(particles_[k]);
    next.back().log_w = equal;
  }
  particles_ = std::move(next);
  ++resamplings_;
  if (kind_ == FilterKind::kRbpfImproved && config_.regularisation_scale > 0.0) regularise();
  return true;
}

void ParticleFilter::regularise() {
  // Equal weights after resampling: the cloud's mean and covariance of p. Psi is left to the
  // attitude readings and the odometry noise, which keep it spread (and a 6-D kernel costs
  // a rotation per particle).
  const double n = static_cast<double>(particles_.size());
  Vec3 mean = Vec3::Zero();
  for (const Particle& q : particles_) mean += q.p;
  mean /= n;
  Mat3 cov = Mat3::Zero();
  for (const Particle& q : particles_) cov.noalias() += (q.p - mean) * (q.p - mean).transpose();
  cov /= n;
  if (radius95_3d(cov) > config_.regularise_below_radius_m) return;
  // Silverman's rule for d = 3, h = (4 / (N (d + 2)))^(1 / (d + 4)); the Liu-West shrinkage
  // a = sqrt(1 - h^2) keeps the cloud's mean and covariance, so regularising every resampling
  // does not inflate it.
  const double h = std::min(0.9, config_.regularisation_scale * std::pow(4.0 / (n * 5.0), 1.0 / 7.0));
  const double a = std::sqrt(1.0 - h * h);
  const Mat3 root = square_root<3>(h * h * cov);
  for (Particle& q : particles_) q.p = a * q.p + (1.0 - a) * mean + root * standard_normal<3>(rng_);
}

MixtureMoments ParticleFilter::moments() const {
  if (moments_) return *moments_;
  MixtureMoments mm;
  if (particles_.empty()) return mm;
  // Angles are averaged relative to the heaviest particle (as the SOG filter's eq. (18)).
  std::size_t best = 0;
  for (std::size_t i = 1; i < particles_.size(); ++i)
    if (particles_[i].log_w > particles_[best].log_w) best = i;
  const Vec3 psi_ref = rpy_from_rotation(particles_[best].rotation);
  const Eigen::Index n = static_cast<Eigen::Index>(particles_.size());
  Eigen::Matrix<double, idx::kStateDim, Eigen::Dynamic> x(idx::kStateDim, n);
  Eigen::RowVectorXd w(n);
  Mat3 moment_spread = Mat3::Zero();
  for (Eigen::Index i = 0; i < n; ++i) {
    const Particle& q = particles_[static_cast<std::size_t>(i)];
    Vec3 dpsi = rpy_from_rotation(q.rotation) - psi_ref;
    for (int a = 0; a < 3; ++a) dpsi[a] = wrap_angle(dpsi[a]);
    x.col(i) << dpsi, q.p, q.m;
    w[i] = std::exp(q.log_w);
    moment_spread += w[i] * q.M;
  }
  const StateVec mean = x * w.transpose();
  x.colwise() -= mean;
  StateCov cov = (x.array().rowwise() * w.array()).matrix() * x.transpose();
  cov.block<3, 3>(idx::kMom, idx::kMom) += moment_spread;
  mm.mean = mean;
  mm.mean.segment<3>(idx::kAtt) += psi_ref;
  for (int a = 0; a < 3; ++a) mm.mean[idx::kAtt + a] = wrap_angle(mm.mean[idx::kAtt + a]);
  mm.covariance = 0.5 * (cov + cov.transpose());
  moments_ = mm;
  return mm;
}

Mat3 ParticleFilter::position_covariance() const {
  if (moments_) return moments_->covariance.block<3, 3>(idx::kPos, idx::kPos);
  // The position block alone: a third of the work of moments(), once per update.
  Vec3 mean = Vec3::Zero();
  Mat3 second = Mat3::Zero();
  for (const Particle& q : particles_) {
    const double w = std::exp(q.log_w);
    mean += w * q.p;
    second.noalias() += w * q.p * q.p.transpose();
  }
  return second - mean * mean.transpose();
}

MixtureMoments ParticleFilter::predicted_moments() const { return moved_moments(moments(), odometry_.peek()); }

Vec3 ParticleFilter::predicted_last_measurement_position() const {
  const Displacement& d = odometry_.peek();
  if (d.samples == 0) return heard_at_;
  return moved_point(moments(), heard_at_, d.mean);
}

VictimEstimate ParticleFilter::estimate(std::size_t top_k) const {
  VictimEstimate e = estimate_from(
      particles_.empty() ? MixtureMoments{} : moments(), particles_.size(), sog_.converged_radius_m, top_k,
      [&](std::size_t i) { return particles_[i].log_w; },
      [&](std::size_t i) {
        return MixtureComponentSummary{std::exp(particles_[i].log_w), particles_[i].p, Mat3::Zero()};
      });
  e.rescuer_id = rescuer_id_;
  e.signal_id = signal_id_;
  e.stamp = last_stamp_;
  return e;
}

std::vector<TransmitterHypothesis> ParticleFilter::hypotheses() const {
  std::vector<TransmitterHypothesis> out;
  out.reserve(particles_.size());
  for (const Particle& q : particles_) out.push_back({q.p, q.m, std::exp(q.log_w)});
  return out;
}

bool ParticleFilter::moment_plausible() const {
  return !particles_.empty() && moment_plausible_from(moments(), sog_.standard, sog_.moment_margin);
}

}  // namespace sarloc::avalanche
