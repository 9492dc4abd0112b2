#pragma once
// What the SOG filter's source files share (sog_filter.cpp and its sog_*.cpp): the one moment
// match of the mixture, the composition's covariance, and message text. Private to
// core/avalanche/src.
#include <sstream>
#include <string>

#include "sarloc/core/avalanche/field_measurement_check.hpp"
#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/avalanche/sog_filter.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"

namespace sarloc::avalanche::sog_detail {

inline std::string vec_text(const Vec3& v) {
  std::ostringstream os;
  os << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return os.str();
}

[[noreturn]] inline void input_fail(const std::string& field, const std::string& value, const std::string& rule) {
  throw InputError("field_measurement." + field + " = " + value + ": " + rule);
}

// A ring heard from a few metres needs no thinner layers than this (0.25 m over 5 m).
constexpr double kMaxNearFieldLayers = 20.0;

// x with its angles re-expressed next to ref's, so that averaging never crosses +-pi.
inline StateVec near_angles(StateVec x, const StateVec& ref) {
  for (int k = 0; k < 3; ++k)
    x[idx::kAtt + k] = ref[idx::kAtt + k] + wrap_angle(x[idx::kAtt + k] - ref[idx::kAtt + k]);
  return x;
}

// F_x P F_x^T + F_d Q F_d^T of the composition (eq. (9), (15)), block by block: the covariance
// of a component moved by a displacement before any measurement's correction.
inline StateCov composed_covariance(const StateCov& p, const CompositionJacobians& f, const DispCov& q) {
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

// dz/dE of z = (I + E) h, E row-major: row a holds h in E(a, .)'s columns.
inline Jacobian<3, kCalibrationDim> calibration_jacobian(const Vec3& h) {
  Jacobian<3, kCalibrationDim> j = Jacobian<3, kCalibrationDim>::Zero();
  for (int a = 0; a < 3; ++a) j.block<1, 3>(a, 3 * a) = h.transpose();
  return j;
}

// F_x C: the state's cross-covariance with the calibration errors moved by the composition
// (the displacement is independent of them).
inline CalibrationCross composed_cross(const CalibrationCross& c, const CompositionJacobians& f) {
  CalibrationCross fc = c;
  fc.middleRows<3>(idx::kAtt) = f.att_att * c.middleRows<3>(idx::kAtt);
  fc.middleRows<3>(idx::kPos) += f.pos_att * c.middleRows<3>(idx::kAtt);
  return fc;
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

}  // namespace sarloc::avalanche::sog_detail
