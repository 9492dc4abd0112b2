// The SOG filter's ring: the initial mixture from the first heard field (seed 000, Sec. III-D).
#include "sarloc/core/avalanche/sog_filter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sog_filter_detail.hpp"

namespace sarloc::avalanche {
using namespace sog_detail;  // the shared private helpers (sog_filter_detail.hpp)


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
  if (!(zn > 0.0)) input_fail("field", vec_text(z), "first measurement must be non-zero on a valid axis");
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
  // What a receiver resolves at the carrier (DipoleField::major_axis) is the quasi-static field
  // times sqrt(1 + (k r)^2) on the moment's axis (the strongest) and sqrt(1 - (k r)^2 + (k r)^4)
  // across it (the weakest): the ring widens by those factors to the 1/3.
  const double k = config_.wavenumber();
  const double r_min_qs = std::cbrt(m_lo / (4.0 * kPi * z_hi));
  const double kr_min2 = std::pow(k * r_min_qs, 2);
  const double r_min = r_min_qs * std::pow(1.0 - kr_min2 + kr_min2 * kr_min2, 1.0 / 6.0);
  double r_max = config_.max_range_m;
  if (z_lo > 0.0) {
    const double r_max_qs = std::cbrt(2.0 * m_hi / (4.0 * kPi * z_lo));
    r_max = std::min(config_.max_range_m, r_max_qs * std::pow(1.0 + std::pow(k * r_max_qs, 2), 1.0 / 6.0));
  }
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
  window_.clear();     // the window holds the current mixture's samples (this one: below)
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
  const double k = config_.wavenumber();
  // The calibration errors E, when carried: z_1 = (I + E) h, so the moment derived from it shares
  // E's share of z_1's error (Cov(m, E) = G_z H_E Sigma_E) and its variance grows by it.
  const CalibrationVec calibration_variance = config_.calibration_variance();
  const bool calibrated = calibration_variance.any();
  const Jacobian<3, kCalibrationDim> h_e = calibration_jacobian(z);

  struct Candidate {
    Vec3 p;
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
          const Vec3 m = DipoleField::moment_of_major_axis(-p, h_g, k);
          if (check_moment) {
            const double mn = m.norm();
            if (mn < m_lo || mn > m_hi) continue;
          }
          ++count;
          if (out != nullptr) out->push_back({p});
        }
      }
    }
    return count;
  };
  // A layered near-field ring shares its Gaussians among up to 20 layers: it keeps more.
  const double target =
      layers > config_.depth_layers ? config_.near_field_initial_components : config_.initial_components;
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
  if (cands.empty()) input_fail("field", vec_text(z), "no transmitter hypothesis fits this field");

  const double sigma_h = config_.horizontal_overlap * s;
  Mat3 p_pp = Mat3::Zero();
  p_pp.diagonal() << sigma_h * sigma_h, sigma_h * sigma_h, sigma_z * sigma_z;
  Mat3 r_z = sigma_axis.cwiseAbs2().asDiagonal();
  if (calibrated) r_z += h_e * calibration_variance.asDiagonal() * h_e.transpose();
  const Mat3 dhg_dpsi = -skew(h_g) * euler_rate_to_world(psi0);

  components_.clear();
  components_.reserve(cands.size());
  for (const auto& c : cands) {
    Mat3 j_m_r, j_m_h;
    const Vec3 m = DipoleField::moment_of_major_axis(-c.p, h_g, k, &j_m_r, &j_m_h);
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
    if (calibrated) comp.calibration_cross.middleRows<3>(idx::kMom) = g_z * h_e * calibration_variance.asDiagonal();
    // Change of variables z -> m: p(p | z_1) ~ p_m(m(p)) |det dm/dz| ~ r^9 / |m|^2.
    comp.log_weight = config_.jacobian_initial_weights
                          ? 9.0 * std::log(c.p.norm()) - 2.0 * std::log(m.norm())
                          : 0.0;
    components_.push_back(comp);
  }
  apply_priors();
  normalise_and_prune();
  if (initialised()) remember_sample(meas.field, config_.noise().floor(meas.noise_stddev), meas.valid_axes);
}

}  // namespace sarloc::avalanche
