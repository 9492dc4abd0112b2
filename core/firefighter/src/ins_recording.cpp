#include "sarloc/core/firefighter/ins_recording.hpp"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::firefighter {
namespace {

// Half a short stride: closer than this, two stance phases stand on one footprint.
constexpr double kSameFootprintM = 0.25;

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
    // A stance closer than kSameFootprintM to the last footprint is that footprint again (a
    // stance the detector split, a shuffle): one footprint, the later position.
    if (!run.stances.empty() && (current.p - run.stances.back().p).head<2>().norm() < kSameFootprintM) {
      run.stances.back().t1 = current.t1;
      run.stances.back().p = current.p;
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
  return f;
}

}  // namespace sarloc::firefighter
