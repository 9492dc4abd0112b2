#include "sarloc/core/firefighter/ins_recording.hpp"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/firefighter/stride_matching.hpp"

namespace sarloc::firefighter {
namespace {

// Half a short stride: closer than this, two stance phases stand on one footprint.
constexpr double kSameFootprintM = 0.25;
// Strides each side whose heading offset sets a stride's local frame (footprint_errors).
constexpr std::size_t kStrideNeighbours = 3;

// The reason of an InputError, without the numbers that make each message unique.
std::string reason_of(const std::string& message) {
  const auto colon = message.find(": ");
  std::string reason = colon == std::string::npos ? message : message.substr(colon + 2);
  const auto of = reason.find(" of ");
  if (reason.rfind("gap", 0) == 0 && of != std::string::npos) reason = "gap after the previous sample";
  const auto paren = reason.find(" (");
  if (paren != std::string::npos) reason = reason.substr(0, paren);
  return message.substr(0, message.find(" = ")) + ": " + reason;
}

// The stride NEES of FootprintErrors: each stride (or group, stride_matching.hpp) in a local
// frame, turned by its neighbours' heading offset. Over all stances and footprints: the pairing
// finds where the detector missed or split a footfall.
void stride_consistency(const InsRecording& run, const std::vector<Eigen::Vector2d>& truth, FootprintErrors& f) {
  std::vector<Eigen::Vector2d> track_strides, truth_strides;
  for (std::size_t k = 1; k < run.stances.size(); ++k) track_strides.push_back(run.stances[k].stride.head<2>());
  for (std::size_t k = 1; k < truth.size(); ++k) truth_strides.push_back(truth[k] - truth[k - 1]);
  const std::vector<StridePair> pairs = match_strides(track_strides, truth_strides);
  if (pairs.empty()) return;
  std::vector<Eigen::Vector2d> a(pairs.size(), Eigen::Vector2d::Zero()), b(pairs.size(), Eigen::Vector2d::Zero());
  std::vector<Eigen::Matrix2d> c(pairs.size(), Eigen::Matrix2d::Zero());
  std::vector<double> offset(pairs.size());  // truth heading minus the track's
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    for (std::size_t i = pairs[p].track_begin; i < pairs[p].track_end; ++i) {
      a[p] += track_strides[i];
      c[p] += run.stances[i + 1].stride_covariance.topLeftCorner<2, 2>();
    }
    for (std::size_t j = pairs[p].truth_begin; j < pairs[p].truth_end; ++j) b[p] += truth_strides[j];
    offset[p] = std::remainder(std::atan2(b[p].y(), b[p].x()) - std::atan2(a[p].y(), a[p].x()), 2.0 * kPi);
  }
  double nees_sum = 0.0, excess = 0.0, walked = 0.0, wander2 = 0.0;
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    std::vector<double> around;  // unwrapped about this pair's own offset
    for (std::size_t q = p > kStrideNeighbours ? p - kStrideNeighbours : 0;
         q < std::min(pairs.size(), p + kStrideNeighbours + 1); ++q)
      if (q != p) around.push_back(offset[p] + std::remainder(offset[q] - offset[p], 2.0 * kPi));
    if (around.empty()) around.push_back(offset[p]);
    std::nth_element(around.begin(), around.begin() + around.size() / 2, around.end());
    const Eigen::Matrix2d local = Eigen::Rotation2Dd(around[around.size() / 2]).toRotationMatrix();
    const Eigen::Vector2d e = local * a[p] - b[p];
    const Eigen::Matrix2d cl = local * c[p] * local.transpose();
    nees_sum += e.dot(cl.ldlt().solve(e));
    excess += e.squaredNorm() - cl.trace();
    walked += a[p].norm();
    if (p > 0) wander2 += std::pow(std::remainder(offset[p] - offset[p - 1], 2.0 * kPi), 2);
  }
  const double count = static_cast<double>(pairs.size());
  f.stride_pairs = pairs.size();
  f.stride_groups = static_cast<std::size_t>(std::count_if(pairs.begin(), pairs.end(), [](const StridePair& p) {
    return p.track_end - p.track_begin != 1 || p.truth_end - p.truth_begin != 1;
  }));
  f.stride_nees_mean = nees_sum / count;
  f.stride_nees_lower = chi_square_quantile(0.025, 2.0 * count) / count;
  f.stride_nees_upper = chi_square_quantile(0.975, 2.0 * count) / count;
  f.missing_variance_per_m = walked > 0.0 ? excess / (2.0 * walked) : 0.0;
  f.heading_wander_rad = pairs.size() > 1 ? std::sqrt(wander2 / (count - 1.0)) : 0.0;
  f.mean_stride_m = walked / count;
}

}  // namespace

InsRecording run_ins(const std::vector<ImuSample>& samples, const ZuptInsConfig& config) {
  InsRecording run;
  run.samples = samples.size();
  if (!samples.empty()) run.duration_s = samples.back().t - samples.front().t;
  ZuptIns ins(config);
  double still_since = -1.0;
  bool in_stance = false;
  Eigen::Vector3d stance_sum = Eigen::Vector3d::Zero();
  std::size_t stance_n = 0;
  Stance current;
  auto close_stance = [&] {
    if (stance_n == 0) return;
    current.p = stance_sum / static_cast<double>(stance_n);
    const StepDisplacement d = ins.take_displacement();
    current.stride = d.delta;
    current.stride_covariance = d.covariance;
    // A stance closer than kSameFootprintM to the last footprint is that footprint again (a
    // stance the detector split, a shuffle): one footprint, the later position. Its stride is
    // the sum of the two (their covariances added: the cross terms are left out).
    if (!run.stances.empty() && (current.p - run.stances.back().p).head<2>().norm() < kSameFootprintM) {
      run.stances.back().t1 = current.t1;
      run.stances.back().p = current.p;
      run.stances.back().stride += d.delta;
      run.stances.back().stride_covariance += d.covariance;
      stance_sum.setZero();
      stance_n = 0;
      return;
    }
    if (!run.stances.empty()) run.distance_m += (current.p - run.stances.back().p).norm();
    run.stances.push_back(current);
    stance_sum.setZero();
    stance_n = 0;
  };
  for (const ImuSample& s : samples) {
    try {
      ins.push(s);
    } catch (const InputError& e) {
      ++run.refused[reason_of(e.what())];
      continue;
    }
    if (!ins.aligned()) {
      if (ins.stationary()) {
        if (still_since < 0.0) still_since = s.t;
        run.longest_still_s = std::max(run.longest_still_s, s.t - still_since);
      } else {
        still_since = -1.0;
      }
      continue;
    }
    if (!run.aligned_at_s) {
      run.aligned_at_s = s.t;
      const Eigen::Vector3d euler = ins.nominal().q.toRotationMatrix().eulerAngles(2, 1, 0);
      run.pitch_rad = euler[1];
      run.roll_rad = euler[2];
      // eulerAngles() may return the equivalent (yaw + pi, pi - pitch, roll + pi): fold it.
      if (std::abs(run.roll_rad) > kPi / 2.0) {
        run.roll_rad = wrap_angle(run.roll_rad + kPi);
        run.pitch_rad = wrap_angle(kPi - run.pitch_rad);
      }
      run.gyro_bias = ins.nominal().bg;
      run.rest_noise = ins.rest_noise();
      (void)ins.take_displacement();  // strides are counted from here
    }
    const bool stationary = ins.stationary();
    run.track.push_back({s.t, ins.nominal().p, stationary});
    if (stationary) {
      if (!in_stance) current.t0 = s.t;
      current.t1 = s.t;
      stance_sum += ins.nominal().p;
      ++stance_n;
    } else if (in_stance) {
      close_stance();
    }
    in_stance = stationary;
  }
  if (in_stance) close_stance();
  return run;
}

std::optional<LoopError> loop_error(const InsRecording& run) {
  if (run.stances.size() < 2) return std::nullopt;
  LoopError e;
  e.end = run.stances.back().p - run.stances.front().p;
  e.error_3d_m = e.end.norm();
  e.horizontal_m = e.end.head<2>().norm();
  e.vertical_m = std::abs(e.end.z());
  return e;
}

std::optional<FootprintErrors> footprint_errors(const InsRecording& run, const std::vector<Eigen::Vector2d>& truth) {
  const std::size_t n = std::min(truth.size(), run.stances.size());
  if (n < 2) return std::nullopt;
  FootprintErrors f;
  f.strides_truth = truth.size() - 1;
  f.strides_track = run.stances.size() - 1;
  f.compared = n - 1;
  std::vector<Eigen::Vector2d> track(n);
  for (std::size_t k = 0; k < n; ++k) track[k] = (run.stances[k].p - run.stances[0].p).head<2>();
  for (std::size_t k = 1; k < n; ++k) f.truth_distance_m += (truth[k] - truth[k - 1]).norm();
  auto errors = [&](const std::vector<Eigen::Vector2d>& aligned, double& final_m, double& rms, double& max) {
    double sum = 0.0;
    for (std::size_t k = 1; k < n; ++k) {
      const double e = (aligned[k] - truth[k]).norm();
      sum += e * e;
      max = std::max(max, e);
    }
    rms = std::sqrt(sum / static_cast<double>(n - 1));
    final_m = (aligned[n - 1] - truth[n - 1]).norm();
  };
  // Stride-aligned: start on the start pose, stride 1 turned onto the truth's.
  const Eigen::Vector2d d_track = track[1] - track[0], d_truth = truth[1] - truth[0];
  const double turn = std::atan2(d_truth.y(), d_truth.x()) - std::atan2(d_track.y(), d_track.x());
  const Eigen::Rotation2Dd r(turn);
  f.turn_rad = turn;
  std::vector<Eigen::Vector2d> aligned(n);
  for (std::size_t k = 0; k < n; ++k) aligned[k] = truth[0] + r * track[k];
  errors(aligned, f.final_m, f.rms_m, f.max_m);
  // Rigid: Kabsch in 2-D over every compared footprint.
  Eigen::Vector2d mt = Eigen::Vector2d::Zero(), mg = Eigen::Vector2d::Zero();
  for (std::size_t k = 0; k < n; ++k) {
    mt += track[k];
    mg += truth[k];
  }
  mt /= static_cast<double>(n);
  mg /= static_cast<double>(n);
  Eigen::Matrix2d h = Eigen::Matrix2d::Zero();
  for (std::size_t k = 0; k < n; ++k) h += (track[k] - mt) * (truth[k] - mg).transpose();
  Eigen::JacobiSVD<Eigen::Matrix2d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix2d rot = svd.matrixV() * svd.matrixU().transpose();
  if (rot.determinant() < 0.0) {
    Eigen::Matrix2d v = svd.matrixV();
    v.col(1) *= -1.0;
    rot = v * svd.matrixU().transpose();
  }
  for (std::size_t k = 0; k < n; ++k) aligned[k] = mg + rot * (track[k] - mt);
  errors(aligned, f.rigid_final_m, f.rigid_rms_m, f.rigid_max_m);
  stride_consistency(run, truth, f);
  return f;
}

}  // namespace sarloc::firefighter
