#include "sarloc/core/avalanche/grid_filter.hpp"

#include <algorithm>
#include <bitset>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

#include "sarloc/core/avalanche/moment_kalman.hpp"
#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "sarloc/core/common/skew.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::avalanche {

void GridFilterConfig::validate() const {
  check_range("grid", "cell_m", cell_m, 0.05, 10.0);
  check_range("grid", "finest_cell_m", finest_cell_m, 0.01, cell_m);
  check_range("grid", "refine_cells", refine_cells, 1.0, 100.0);
  check_range("grid", "prune_log_weight", prune_log_weight, 1.0, 100.0);
  check_range("grid", "max_cells", max_cells, 1000.0, 1e8);
}

GridFilter::GridFilter(SogConfig sog, GridFilterConfig config, std::string rescuer_id, std::uint32_t signal_id)
    : sog_((sog.validate(), sog.quasi_static())),
      config_((config.validate(), config)),
      rescuer_id_(std::move(rescuer_id)),
      signal_id_(signal_id),
      odometry_(sog_.idle_translation_sigma_m, sog_.idle_rotation_sigma_rad),
      detection_(sog_.miss_detection_statistic),
      record_(sog_.divergence_window, sog_.reinit_gate_probability) {}

void GridFilter::add_odometry(const Odometry& odometry) {
  if (!rescuer_id_.empty() && !odometry.rescuer_id.empty() && odometry.rescuer_id != rescuer_id_)
    throw InputError("odometry.rescuer_id = " + odometry.rescuer_id + ": filter belongs to " + rescuer_id_);
  odometry_.add(odometry);
}

void GridFilter::initialise(const FieldMeasurement& measurement) {
  const SogFilter::InitialRing ring = SogFilter(sog_).initial_ring(measurement);
  receiver_ = Vec3::Zero();
  heard_at_ = Vec3::Zero();
  attitude_ = ring.attitude;
  error_covariance_.setZero();
  error_covariance_.topLeftCorner<3, 3>() = ring.attitude_covariance;
  diffused_ = Vec3::Zero();
  last_field_g_ = ring.field_g;
  const Mat3 r_g = rotation_from_rpy(ring.attitude);
  const Mat3 dhg_dpsi = -skew(ring.field_g) * euler_rate_to_world(ring.attitude);
  const Mat3 r_z = ring.sigma_axis.cwiseAbs2().asDiagonal();
  const double h = sog_.antenna_height_m;
  auto generate = [&](double cell, bool check_moment, std::vector<Cell>* out) {
    std::size_t count = 0;
    const int nxy = static_cast<int>(std::ceil(ring.rho_max_m / cell));
    const int nz = std::max(1, static_cast<int>(std::ceil(ring.depth_m / cell)));
    const Mat3 within = Mat3::Identity() * cell * cell / 12.0;  // a uniform cell's spread
    for (int i = -nxy; i <= nxy; ++i) {
      for (int j = -nxy; j <= nxy; ++j) {
        const double rho = std::hypot(i * cell, j * cell);
        if (rho > ring.rho_max_m || rho < ring.rho_min_m) continue;
        for (int k = 0; k < nz; ++k) {
          const Vec3 p(i * cell, j * cell, -(h + (k + 0.5) * cell));
          Mat3 j_m_r, j_m_h;
          const Vec3 m = DipoleField::moment(-p, ring.field_g, &j_m_r, &j_m_h);
          // m = g(Psi, p, z) linearised, as the SOG filter's components (section III-B).
          const Mat3 g_psi = j_m_h * dhg_dpsi;
          const Mat3 g_z = j_m_h * r_g;
          const Mat3 m_cov = j_m_r * within * j_m_r.transpose() + g_psi * ring.attitude_covariance * g_psi.transpose() +
                             g_z * r_z * g_z.transpose();
          // The standard's bounds on |m|, softened by the moment's own spread (3 sigma): a cell
          // that only a noisy first sample puts outside them is kept.
          const double norm_sigma = m.norm() > 0.0 ? std::sqrt(std::max(0.0, m.dot(m_cov * m)) / m.squaredNorm()) : 0.0;
          if (check_moment && (m.norm() + 3.0 * norm_sigma < ring.moment_min ||
                               m.norm() - 3.0 * norm_sigma > ring.moment_max))
            continue;
          ++count;
          if (out == nullptr) continue;
          Cell c;
          c.centre = p;
          c.m = m;
          c.M = m_cov;
          c.log_w = sog_.jacobian_initial_weights ? 9.0 * std::log(p.norm()) - 2.0 * std::log(m.norm()) : 0.0;
          out->push_back(c);
        }
      }
    }
    return count;
  };
  double cell = config_.cell_m;
  bool check = generate(cell, true, nullptr) > 0;
  while (generate(cell, check, nullptr) > config_.max_cells) cell *= 1.26;
  cells_.clear();
  generate(cell, check, &cells_);
  origin_ = Vec3(0.0, 0.0, -(h + 0.5 * cell));
  if (cells_.empty()) throw InputError("field_measurement.field: no cell of the ring fits this field");
  cell_m_ = cell;
  record_.clear();
  mixture_samples_ = 1;
  normalise_and_prune();
}

void GridFilter::move_receiver(const Displacement& disp) {
  // Eq. (6)-(7) on the mean path, and their Jacobians (the SOG filter's, CompositionModel) on the
  // error: Psi_k = A Psi + D dPsi, s_k = s + C Psi + T t.
  StateVec x = StateVec::Zero();
  x.segment<3>(idx::kAtt) = attitude_;
  CompositionJacobians j;
  const StateVec moved = CompositionModel::f(x, disp.mean, &j);
  receiver_ -= moved.segment<3>(idx::kPos);
  attitude_ = moved.segment<3>(idx::kAtt);
  Eigen::Matrix<double, 6, 6> f = Eigen::Matrix<double, 6, 6>::Identity();
  f.topLeftCorner<3, 3>() = j.att_att;
  f.bottomLeftCorner<3, 3>() = j.pos_att;
  Eigen::Matrix<double, 6, 6> g = Eigen::Matrix<double, 6, 6>::Zero();  // columns: t, dPsi
  g.block<3, 3>(0, idx::kRot) = j.att_rot;
  g.block<3, 3>(3, idx::kTrans) = j.pos_trans;
  error_covariance_ = f * error_covariance_ * f.transpose() + g * disp.covariance * g.transpose();
  error_covariance_ = 0.5 * (error_covariance_ + error_covariance_.transpose()).eval();
}

void GridFilter::read_attitude(const OrientationObservation& o) {
  Vec3 nu = o.rpy - attitude_;
  for (int a = 0; a < 3; ++a) nu[a] = wrap_angle(nu[a]);
  const Mat3 s = error_covariance_.topLeftCorner<3, 3>() + o.covariance;
  const Eigen::Matrix<double, 6, 3> k = error_covariance_.leftCols<3>() * s.inverse();
  const Eigen::Matrix<double, 6, 1> correction = k * nu;
  attitude_ += correction.head<3>();
  for (int a = 0; a < 3; ++a) attitude_[a] = wrap_angle(attitude_[a]);
  // The path was off by s: every relative position p = centre - receiver moves by it.
  receiver_ -= correction.tail<3>();
  error_covariance_ -= k * error_covariance_.topRows<3>();
  error_covariance_ = 0.5 * (error_covariance_ + error_covariance_.transpose()).eval();
}

void GridFilter::diffuse() {
  // Applied once a tenth of a cell's variance has gathered: a coarse grid is not blurred at
  // every step by millimetres, and the delay is a fraction of a cell.
  const double threshold = 0.1 * cell_m_ * cell_m_;
  const double max_pass = 0.5 * cell_m_ * cell_m_;  // the kernel [a, 1 - 2a, a] with a <= 1/4
  for (int axis = 0; axis < 3; ++axis) {
    double pending = error_covariance_(3 + axis, 3 + axis) - diffused_[axis];
    while (pending >= threshold) {
      const double pass = std::min(pending, max_pass);
      diffuse_axis(axis, pass);
      diffused_[axis] += pass;
      pending -= pass;
    }
  }
}

void GridFilter::diffuse_axis(int axis, double variance) {
  // One pass of the kernel [a, 1 - 2a, a] along the axis (variance 2 a cell^2): each cell sends
  // a of its weight to each neighbour, creating the neighbour if it was pruned. Cells that
  // meet are moment-matched (weight, moment mean and covariance), the moment's sign aligned
  // with the receiving cell's first (z is heard without sign, so m and -m are one hypothesis).
  const double a = variance / (2.0 * cell_m_ * cell_m_);
  auto key = [&](const Vec3& centre) {
    const Vec3 i = ((centre - origin_) / cell_m_).array().round();
    auto part = [](double v) { return static_cast<std::uint64_t>(static_cast<std::int64_t>(v) + (1 << 20)) & 0x1fffff; };
    return part(i.x()) | (part(i.y()) << 21) | (part(i.z()) << 42);
  };
  struct Sum {
    Vec3 centre;
    double w = 0.0;
    Vec3 m = Vec3::Zero();
    Mat3 second = Mat3::Zero();  // sum of w (M + m m^T)
    Vec3 sign_ref = Vec3::Zero();
  };
  std::vector<Sum> sums;
  sums.reserve(cells_.size() + cells_.size() / 2);
  std::unordered_map<std::uint64_t, std::size_t> index;
  index.reserve(2 * cells_.size());
  double max_log = -std::numeric_limits<double>::infinity();
  for (const Cell& c : cells_) max_log = std::max(max_log, c.log_w);
  auto add = [&](const Vec3& centre, double w, const Cell& from) {
    const auto [it, inserted] = index.try_emplace(key(centre), sums.size());
    if (inserted) {
      sums.push_back(Sum{centre, 0.0, Vec3::Zero(), Mat3::Zero(), from.m});
    }
    Sum& s = sums[it->second];
    const Vec3 m = from.m.dot(s.sign_ref) >= 0.0 ? from.m : Vec3(-from.m);
    s.w += w;
    s.m += w * m;
    s.second.noalias() += w * (from.M + m * m.transpose());
  };
  Vec3 step = Vec3::Zero();
  step[axis] = cell_m_;
  for (const Cell& c : cells_) {
    const double w = std::exp(c.log_w - max_log);
    add(c.centre, (1.0 - 2.0 * a) * w, c);
    add(c.centre - step, a * w, c);
    add(c.centre + step, a * w, c);
  }
  cells_.clear();
  cells_.reserve(sums.size());
  for (const Sum& s : sums) {
    Cell c;
    c.centre = s.centre;
    c.m = s.m / s.w;
    c.M = s.second / s.w - c.m * c.m.transpose();
    c.M = 0.5 * (c.M + c.M.transpose()).eval();
    c.log_w = std::log(s.w) + max_log;
    cells_.push_back(c);
  }
  normalise_and_prune();
}

FilterStepResult GridFilter::update(const FieldMeasurement& measurement) {
  check_sample(measurement, rescuer_id_, last_sequence_);
  last_sequence_ = measurement.sequence;
  FilterStepResult result;
  if (measurement.valid_axes == 0) {
    if (!initialised() || !sog_.negative_information) return result;
    last_stamp_ = measurement.stamp;
    move_receiver(odometry_.take());
    diffuse();
    moments_.reset();
    // P(not detected | cell) at its moment's mean (DetectionCurve), as the particle filters.
    const Vec3 floor = sog_.noise().floor(measurement.noise_stddev);
    const Vec3 weight = floor.cwiseAbs2().cwiseInverse() * sog_.miss_power_margin;
    const Mat3 r = rotation_from_rpy(attitude_);
    for (Cell& c : cells_) {
      const Vec3 p = c.centre - receiver_;
      if (!(p.norm() > 1e-3)) continue;
      const double miss = 1.0 - detection_.probability((moment_gain(r, p) * c.m).cwiseAbs2().dot(weight));
      c.log_w += std::log(std::max(miss, sog_.miss_weight_floor));
    }
    normalise_and_prune();
    result.miss = true;
    result.hypotheses_after = cells_.size();
    return result;
  }
  last_stamp_ = measurement.stamp;
  if (!initialised()) {
    initialise(measurement);
    odometry_.take();
    result.initialised_now = true;
    result.hypotheses_after = cells_.size();
    return result;
  }
  const double radius95_before = radius95_3d(position_covariance());
  move_receiver(odometry_.take());
  if (measurement.orientation && sog_.use_orientation) read_attitude(*measurement.orientation);
  heard_at_ = receiver_;
  diffuse();
  moments_.reset();
  const Mat3 r = rotation_from_rpy(attitude_);
  last_field_g_ = r * valid_axes_only(measurement.field, measurement.valid_axes);
  // The attitude's spread turns the field: a small rotation delta moves z by delta x z, about
  // |h| sigma_att sqrt(2/3) per axis, independent of the relative noise (added in quadrature).
  const double attitude_variance = std::max(0.0, error_covariance_.topLeftCorner<3, 3>().trace() / 3.0);
  FieldNoiseModel noise = sog_.noise();
  noise.relative = std::sqrt(noise.relative * noise.relative + 2.0 / 3.0 * attitude_variance);
  const Vec3 floor = noise.floor(measurement.noise_stddev);
  const Vec3 z_valid = valid_axes_only(measurement.field, measurement.valid_axes);
  PredictiveMoments predictive;
  for (Cell& c : cells_) {
    const double prior = std::exp(c.log_w);
    const Vec3 p = c.centre - receiver_;
    if (!(p.norm() > 1e-3)) {
      c.log_w = -std::numeric_limits<double>::infinity();
      continue;
    }
    const MomentUpdate u = update_moment(moment_gain(r, p), c.m, c.M, z_valid, floor, measurement.valid_axes,
                                         noise);
    if (!u.ok) {
      c.log_w = -std::numeric_limits<double>::infinity();
      continue;
    }
    c.log_w += u.ll;
    predictive.add(prior, u);
  }
  result.min_nis = predictive.nis(z_valid);
  record_.add(result.min_nis, static_cast<int>(std::bitset<3>(measurement.valid_axes).count()), radius95_before);
  normalise_and_prune();
  refine();
  ++mixture_samples_;
  result.hypotheses_after = cells_.size();
  return result;
}

void GridFilter::normalise_and_prune() {
  moments_.reset();
  double max_log = -std::numeric_limits<double>::infinity();
  for (const Cell& c : cells_) max_log = std::max(max_log, c.log_w);
  if (!std::isfinite(max_log)) {  // no cell explains the sample: keep them all, equal
    for (Cell& c : cells_) c.log_w = 0.0;
    max_log = 0.0;
  }
  const double cut = max_log - config_.prune_log_weight;
  cells_.erase(std::remove_if(cells_.begin(), cells_.end(), [&](const Cell& c) { return !(c.log_w >= cut); }),
               cells_.end());
  double sum = 0.0;
  for (const Cell& c : cells_) sum += std::exp(c.log_w - max_log);
  const double log_norm = max_log + std::log(sum);
  for (Cell& c : cells_) c.log_w -= log_norm;
}

void GridFilter::refine() {
  if (cell_m_ / 2.0 < config_.finest_cell_m) return;
  if (radius95_3d(position_covariance()) > config_.refine_cells * cell_m_) return;
  // Eight children a quarter cell off the centre; each child's moment moved along dm/dp of the
  // last sample (m = 4 pi r^3 (1.5 r r^T / r^2 - I) H, eq. (12)), its spread kept.
  const double q = cell_m_ / 4.0;
  std::vector<Cell> children;
  children.reserve(cells_.size() * 8);
  for (const Cell& c : cells_) {
    Mat3 j_m_r;
    DipoleField::moment(receiver_ - c.centre, last_field_g_, &j_m_r);
    for (int k = 0; k < 8; ++k) {
      const Vec3 offset((k & 1) ? q : -q, (k & 2) ? q : -q, (k & 4) ? q : -q);
      Cell child = c;
      child.centre += offset;
      // The sign of m follows the cell's (the sample's sign is unknown).
      const Vec3 dm = -j_m_r * offset;
      child.m += c.m.dot(DipoleField::moment(receiver_ - c.centre, last_field_g_)) >= 0.0 ? dm : -dm;
      child.log_w -= std::log(8.0);
      children.push_back(child);
    }
  }
  cells_ = std::move(children);
  origin_ -= Vec3::Constant(q);  // the children's lattice: origin - q + (cell / 2) integers
  cell_m_ /= 2.0;
  moments_.reset();
}

Mat3 GridFilter::position_covariance() const {
  if (moments_) return moments_->covariance.block<3, 3>(idx::kPos, idx::kPos);
  Vec3 mean = Vec3::Zero();
  Mat3 second = Mat3::Zero();
  for (const Cell& c : cells_) {
    const double w = std::exp(c.log_w);
    const Vec3 p = c.centre - receiver_;
    mean += w * p;
    second.noalias() += w * p * p.transpose();
  }
  return second - mean * mean.transpose() + Mat3::Identity() * cell_m_ * cell_m_ / 12.0;
}

MixtureMoments GridFilter::moments() const {
  if (moments_) return *moments_;
  MixtureMoments mm;
  if (cells_.empty()) return mm;
  Vec3 p_mean = Vec3::Zero(), m_mean = Vec3::Zero();
  for (const Cell& c : cells_) {
    const double w = std::exp(c.log_w);
    p_mean += w * (c.centre - receiver_);
    m_mean += w * c.m;
  }
  Eigen::Matrix<double, 6, 6> cov = Eigen::Matrix<double, 6, 6>::Zero();
  for (const Cell& c : cells_) {
    const double w = std::exp(c.log_w);
    Eigen::Matrix<double, 6, 1> e;
    e << c.centre - receiver_ - p_mean, c.m - m_mean;
    cov.noalias() += w * e * e.transpose();
    cov.bottomRightCorner<3, 3>() += w * c.M;
  }
  cov.topLeftCorner<3, 3>() += Mat3::Identity() * cell_m_ * cell_m_ / 12.0;
  mm.mean << attitude_, p_mean, m_mean;
  mm.covariance.setZero();
  mm.covariance.block<3, 3>(idx::kAtt, idx::kAtt) = error_covariance_.topLeftCorner<3, 3>();
  mm.covariance.block<6, 6>(idx::kPos, idx::kPos) = 0.5 * (cov + cov.transpose());
  moments_ = mm;
  return mm;
}

MixtureMoments GridFilter::predicted_moments() const { return moved_moments(moments(), odometry_.peek()); }

Vec3 GridFilter::predicted_last_measurement_position() const {
  const Displacement& d = odometry_.peek();
  const Vec3 now = receiver_ + rotation_from_rpy(attitude_) * d.mean.segment<3>(idx::kTrans);
  return heard_at_ - now;
}

VictimEstimate GridFilter::estimate(std::size_t top_k) const {
  VictimEstimate e = estimate_from(
      cells_.empty() ? MixtureMoments{} : moments(), cells_.size(), sog_.converged_radius_m, top_k,
      [&](std::size_t i) { return cells_[i].log_w; },
      [&](std::size_t i) {
        return MixtureComponentSummary{std::exp(cells_[i].log_w), cells_[i].centre - receiver_,
                                       Mat3(Mat3::Identity() * cell_m_ * cell_m_ / 12.0)};
      });
  e.rescuer_id = rescuer_id_;
  e.signal_id = signal_id_;
  e.stamp = last_stamp_;
  return e;
}

std::vector<TransmitterHypothesis> GridFilter::hypotheses() const {
  std::vector<TransmitterHypothesis> out;
  out.reserve(cells_.size());
  for (const Cell& c : cells_) out.push_back({c.centre - receiver_, c.m, std::exp(c.log_w)});
  return out;
}

bool GridFilter::moment_plausible() const {
  return !cells_.empty() && moment_plausible_from(moments(), sog_.standard, sog_.moment_margin);
}

}  // namespace sarloc::avalanche
