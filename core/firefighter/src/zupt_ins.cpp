#include "sarloc/core/firefighter/zupt_ins.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <string>
#include <utility>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/skew.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::firefighter {
namespace {

using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

constexpr double kMaxSpecificForce = 16.0 * kGravity;         // the MTi-3's range
constexpr double kMaxAngularRate = 2000.0 * kPi / 180.0;
// A footfall for the level floor lasts at least this (a walking stance: 0.15-0.4 s).
constexpr double kLevelMinStanceS = 0.08;
// A footfall sample turning slower than this many ZARU sigmas reads its bias too.
constexpr double kZaruGate = 5.0;

Eigen::Quaterniond exp_q(const Vec3& phi) {
  const double a = phi.norm();
  if (a < 1e-12) return Eigen::Quaterniond(1.0, 0.5 * phi.x(), 0.5 * phi.y(), 0.5 * phi.z()).normalized();
  return Eigen::Quaterniond(Eigen::AngleAxisd(a, phi / a));
}

Vec3 log_q(const Eigen::Quaterniond& q) {
  const Eigen::AngleAxisd aa(q.normalized());
  double a = aa.angle();
  Vec3 axis = aa.axis();
  if (a > kPi) a -= 2.0 * kPi;
  return a * axis;
}

// Right Jacobian of SO(3): Exp(phi + d) ~ Exp(phi) Exp(Jr(phi) d).
Mat3 right_jacobian(const Vec3& phi) {
  const double a = phi.norm();
  if (a < 1e-8) return Mat3::Identity() - 0.5 * skew(phi);
  const Mat3 K = skew(phi);
  return Mat3::Identity() - (1.0 - std::cos(a)) / (a * a) * K + (a - std::sin(a)) / (a * a * a) * K * K;
}

double yaw_of(const Eigen::Quaterniond& q) {
  const Mat3 R = q.toRotationMatrix();
  return std::atan2(R(1, 0), R(0, 0));
}

// The `count` consecutive samples whose angular rates vary least: a boot that a detector calls
// still sways at a few deg/s (the GX5 walks' first second), and a sway's mean is a net rotation,
// not the gyros' bias. Returns the first of them.
std::size_t stillest_run(const std::deque<ImuSample>& samples, std::size_t count) {
  std::size_t best_begin = 0;
  double best_spread = std::numeric_limits<double>::infinity();
  for (std::size_t begin = 0; begin + count <= samples.size(); ++begin) {
    Vec3 mean = Vec3::Zero();
    for (std::size_t k = begin; k < begin + count; ++k) mean += samples[k].angular_rate;
    mean /= static_cast<double>(count);
    double spread = 0.0;
    for (std::size_t k = begin; k < begin + count; ++k) spread += (samples[k].angular_rate - mean).squaredNorm();
    if (spread < best_spread) {
      best_spread = spread;
      best_begin = begin;
    }
  }
  return best_begin;
}

// The mean of `field` over samples [begin, begin + count) and the white-noise density its spread
// implies at `rate_hz`, averaged over the three axes: a density N sampled at f has a standard
// deviation N sqrt(f), the convention of the process noise (N^2 dt a sample) and of the simulator.
template <typename Field>
std::pair<Vec3, double> mean_and_density(const std::deque<ImuSample>& samples, std::size_t begin, std::size_t count,
                                         Field field, double rate_hz) {
  Vec3 mean = Vec3::Zero();
  for (std::size_t k = begin; k < begin + count; ++k) mean += field(samples[k]);
  mean /= static_cast<double>(count);
  double variance = 0.0;
  for (std::size_t k = begin; k < begin + count; ++k) variance += (field(samples[k]) - mean).squaredNorm();
  variance /= 3.0 * static_cast<double>(std::max<std::size_t>(count - 1, 1));
  return {mean, std::sqrt(variance / rate_hz)};
}

}  // namespace

void ZuptInsConfig::validate() const {
  auto check = [](const char* key, double v, double lo, double hi) { check_range("ins", key, v, lo, hi); };
  check("rate_hz", rate_hz, 20.0, 2000.0);
  check("alignment_s", alignment_s, 0.1, 600.0);
  check("alignment_min_s", alignment_min_s, 0.01, alignment_s);
  check("alignment_bias_s", alignment_bias_s, 0.01, alignment_s);
  check("zaru_sigma_radps", zaru_sigma_radps, 0.0, 1.0);
  check("zaru_after_s", zaru_after_s, 0.0, 60.0);
  check("level_step_m", level_step_m, 0.0, 1.0);
  check("level_sigma_m", level_sigma_m, 1e-4, 1.0);
  check("stride_noise_m2_per_m", stride_noise_m2_per_m, 0.0, 1.0);
  check("initial_yaw_rad", initial_yaw_rad, -10.0, 10.0);
  check("accel_noise_density", accel_noise_density, 1e-6, 1.0);
  check("gyro_noise_density", gyro_noise_density, 1e-7, 0.1);
  check("accel_bias_walk", accel_bias_walk, 0.0, 1.0);
  check("gyro_bias_walk", gyro_bias_walk, 0.0, 0.1);
  check("initial_accel_bias_sigma", initial_accel_bias_sigma, 1e-6, 10.0);
  check("initial_gyro_bias_sigma", initial_gyro_bias_sigma, 1e-7, 1.0);
  check("initial_tilt_sigma_rad", initial_tilt_sigma_rad, 1e-6, 1.0);
  check("initial_yaw_sigma_rad", initial_yaw_sigma_rad, 1e-6, 3.2);
  check("zupt_sigma_mps", zupt_sigma_mps, 1e-4, 1.0);
  check("zupt_rotation_lever_m", zupt_rotation_lever_m, 0.0, 0.5);
  check("landing_speed_max_mps", landing_speed_max_mps, 0.0, 20.0);
  check("swing_pause_max_s", swing_pause_max_s, 0.0, 1.0);
  check("swing_max_s", swing_max_s, 0.1, 10.0);
  check("detector_window", detector_window, 1.0, 100.0);
  check("detector_sigma_accel", detector_sigma_accel, 1e-5, 10.0);
  check("detector_sigma_gyro", detector_sigma_gyro, 1e-6, 1.0);
  check("detector_threshold", detector_threshold, 1.0, 1e9);
  check("stance_votes", stance_votes, 2.0, 3.0);
  check("motionless_after_s", motionless_after_s, 1.0, 3600.0);
}

namespace {

StanceThresholdConfig adapted_stance(const ZuptInsConfig& config) {
  StanceThresholdConfig c = config.stance;
  c.floor = config.detector_threshold;
  c.ceiling = std::max(c.ceiling, c.floor);
  return c;
}

}  // namespace

ZuptIns::ZuptIns(ZuptInsConfig config)
    : config_((config.validate(), config)),
      stance_threshold_(adapted_stance(config_)),
      ared_threshold_(adapted_stance(config_)),
      amvd_threshold_(adapted_stance(config_)) {}

double ZuptIns::yaw() const { return yaw_of(x_.q); }

ZuptIns::Nominal ZuptIns::propagate(const Nominal& x, const ImuSample& s0, const ImuSample& s1, double dt) {
  Nominal y = x;
  const Vec3 w = 0.5 * (s0.angular_rate + s1.angular_rate) - x.bg;
  y.q = (x.q * exp_q(w * dt)).normalized();
  const Vec3 a = 0.5 * (x.q * (s0.specific_force - x.ba) + y.q * (s1.specific_force - x.ba)) - kGravity * Vec3::UnitZ();
  y.v = x.v + a * dt;
  y.p = x.p + 0.5 * (x.v + y.v) * dt;
  return y;
}

Eigen::Matrix<double, 15, 15> ZuptIns::transition(const Nominal& x, const ImuSample& s0, const ImuSample& s1,
                                                  double dt) {
  using F15 = Eigen::Matrix<double, 15, 15>;
  F15 F = F15::Identity();
  const Vec3 phi = (0.5 * (s0.angular_rate + s1.angular_rate) - x.bg) * dt;
  const Mat3 R0 = x.q.toRotationMatrix();
  const Mat3 R1 = (x.q * exp_q(phi)).toRotationMatrix();
  const Vec3 f0 = R0 * (s0.specific_force - x.ba);
  const Vec3 f1 = R1 * (s1.specific_force - x.ba);
  const Mat3 theta_bg = -dt * R1 * right_jacobian(phi);  // d theta1 / d bg
  // d a / d error: a = (R0 f0' + R1 f1') / 2 - g, theta1 = theta + theta_bg bg.
  const Mat3 a_theta = -0.5 * (skew(f0) + skew(f1));
  const Mat3 a_ba = -0.5 * (R0 + R1);
  const Mat3 a_bg = -0.5 * skew(f1) * theta_bg;
  F.block<3, 3>(kV, kTheta) = dt * a_theta;
  F.block<3, 3>(kV, kBa) = dt * a_ba;
  F.block<3, 3>(kV, kBg) = dt * a_bg;
  F.block<3, 3>(kP, kV) = Mat3::Identity() * dt;
  F.block<3, 3>(kP, kTheta) = 0.5 * dt * dt * a_theta;
  F.block<3, 3>(kP, kBa) = 0.5 * dt * dt * a_ba;
  F.block<3, 3>(kP, kBg) = 0.5 * dt * dt * a_bg;
  F.block<3, 3>(kTheta, kBg) = theta_bg;
  return F;
}

ZuptIns::Nominal ZuptIns::inject(const Nominal& x, const Eigen::Matrix<double, 15, 1>& dx) {
  Nominal y = x;
  y.p += dx.segment<3>(kP);
  y.v += dx.segment<3>(kV);
  y.q = (exp_q(dx.segment<3>(kTheta)) * x.q).normalized();
  y.ba += dx.segment<3>(kBa);
  y.bg += dx.segment<3>(kBg);
  return y;
}

Eigen::Matrix<double, 15, 1> ZuptIns::difference(const Nominal& a, const Nominal& b) {
  Eigen::Matrix<double, 15, 1> d;
  d.segment<3>(kP) = a.p - b.p;
  d.segment<3>(kV) = a.v - b.v;
  d.segment<3>(kTheta) = log_q(a.q * b.q.conjugate());
  d.segment<3>(kBa) = a.ba - b.ba;
  d.segment<3>(kBg) = a.bg - b.bg;
  return d;
}

void ZuptIns::push(const ImuSample& s) {
  if (!std::isfinite(s.t)) throw InputError("imu.t = " + std::to_string(s.t) + ": must be finite");
  if (!s.specific_force.allFinite()) throw InputError("imu.specific_force: not finite");
  if (!s.angular_rate.allFinite()) throw InputError("imu.angular_rate: not finite");
  if (s.specific_force.cwiseAbs().maxCoeff() > kMaxSpecificForce) {
    throw InputError("imu.specific_force = " + std::to_string(s.specific_force.cwiseAbs().maxCoeff()) +
                     " m/s^2: beyond the sensor's 16 g");
  }
  if (s.angular_rate.cwiseAbs().maxCoeff() > kMaxAngularRate) {
    throw InputError("imu.angular_rate = " + std::to_string(s.angular_rate.cwiseAbs().maxCoeff()) +
                     " rad/s: beyond the sensor's 2000 deg/s");
  }
  if (have_time_ && !(s.t > t_)) {
    throw InputError("imu.t = " + std::to_string(s.t) + ": not after the previous sample (" + std::to_string(t_) + ")");
  }
  const double dt = have_time_ ? s.t - t_ : 1.0 / config_.rate_hz;
  if (have_time_ && dt > 10.0 / config_.rate_hz) {
    // A gap of more than ten samples: the strapdown integration cannot bridge it honestly.
    throw InputError("imu.t = " + std::to_string(s.t) + ": gap of " + std::to_string(dt) + " s after the previous sample");
  }
  have_time_ = true;
  t_ = s.t;
  window_.push_back(s);
  while (window_.size() > config_.detector_window) window_.pop_front();
  const bool was_stationary = stationary_;
  const bool still = detect();
  still_run_s_ = still ? still_run_s_ + dt : 0.0;
  stationary_ = still && !(aligned_ && !was_stationary && in_swing_pause());
  motionless_s_ = stationary_ ? motionless_s_ + dt : 0.0;

  if (!aligned_) {
    if (!stationary_) {
      // The walk started: a still spell long enough is the first stance, aligned on.
      if (still_s_ >= config_.alignment_min_s && !alignment_.empty()) {
        align();
        // This sample is the first of the swing: propagated from the stance's last.
      } else {
        alignment_.clear();
        still_s_ = 0.0;
        return;
      }
    } else {
      alignment_.push_back(s);
      previous_ = s;
      still_s_ = static_cast<double>(alignment_.size()) / config_.rate_hz;  // samples, as rate_hz paces them
      if (still_s_ + 1e-9 >= config_.alignment_s) align();
      return;
    }
  }
  stance_s_ = stationary_ ? (was_stationary ? stance_s_ + dt : 0.0) : stance_s_;
  if (stationary_ && !was_stationary) level_floor_update();

  const Eigen::Matrix<double, 15, 15> F = transition(x_, previous_, s, dt);
  x_ = propagate(x_, previous_, s, dt);
  previous_ = s;
  StateCov Fa = StateCov::Identity();
  Fa.topLeftCorner<15, 15>() = F;
  StateCov Q = StateCov::Zero();
  const double qa = config_.accel_noise_density * config_.accel_noise_density * dt;
  const double qg = config_.gyro_noise_density * config_.gyro_noise_density * dt;
  Q.block<3, 3>(kV, kV) = Mat3::Identity() * qa;
  Q.block<3, 3>(kP, kP) = Mat3::Identity() * qa * dt * dt / 3.0;
  Q.block<3, 3>(kP, kV) = Mat3::Identity() * qa * dt / 2.0;
  Q.block<3, 3>(kV, kP) = Mat3::Identity() * qa * dt / 2.0;
  Q.block<3, 3>(kTheta, kTheta) = Mat3::Identity() * qg;
  Q.block<3, 3>(kBa, kBa) = Mat3::Identity() * config_.accel_bias_walk * config_.accel_bias_walk * dt;
  Q.block<3, 3>(kBg, kBg) = Mat3::Identity() * config_.gyro_bias_walk * config_.gyro_bias_walk * dt;
  P_ = Fa * P_ * Fa.transpose() + Q;
  if (stationary_) {
    zero_velocity_update(s);
    // Standing, not a walking footfall: a heel-to-toe roll turns the boot at 10-30 deg/s.
    if (stance_s_ >= config_.zaru_after_s || (s.angular_rate - x_.bg).norm() < kZaruGate * config_.zaru_sigma_radps)
      zero_angular_rate_update(s);
  }
  // A stance ends: a real one (not a pause inside a swing) is a footfall on some floor.
  if (!stationary_ && was_stationary) stance_ended_at_ = t_;
  if (!stationary_ && was_stationary && stance_s_ >= kLevelMinStanceS) last_stance_z_ = x_.p.z();
}

bool ZuptIns::in_swing_pause() const {
  return config_.landing_speed_max_mps > 0.0 && x_.v.norm() > config_.landing_speed_max_mps &&
         still_run_s_ + 1e-9 < config_.swing_pause_max_s && t_ - stance_ended_at_ < config_.swing_max_s;
}

bool ZuptIns::detect() {
  Vec3 mean = Vec3::Zero();
  for (const ImuSample& w : window_) mean += w.specific_force;
  mean /= static_cast<double>(window_.size());
  if (mean.norm() < 1e-6) return false;
  const Vec3 g_dir = kGravity * mean.normalized();
  double shoe_accel = 0.0, ared = 0.0, amvd = 0.0;
  const double ia = 1.0 / (config_.detector_sigma_accel * config_.detector_sigma_accel);
  const double ig = 1.0 / (config_.detector_sigma_gyro * config_.detector_sigma_gyro);
  for (const ImuSample& w : window_) {
    shoe_accel += (w.specific_force - g_dir).squaredNorm() * ia;
    ared += w.angular_rate.squaredNorm() * ig;
    amvd += (w.specific_force - mean).squaredNorm() * ia;
  }
  const double n = static_cast<double>(window_.size());
  const double shoe = (shoe_accel + ared) / n;
  const auto stance = [&](StanceThreshold& adaptive, double t) {
    return config_.adaptive_stance ? adaptive.push(t, config_.rate_hz) : t < config_.detector_threshold;
  };
  if (config_.detector == StanceDetector::kShoe) return stance(stance_threshold_, shoe);
  const int votes = (stance(stance_threshold_, shoe) ? 1 : 0) + (stance(ared_threshold_, ared / n) ? 1 : 0) +
                    (stance(amvd_threshold_, amvd / n) ? 1 : 0);
  return votes >= static_cast<int>(config_.stance_votes);
}

void ZuptIns::align() {
  Vec3 f = Vec3::Zero();
  for (const ImuSample& s : alignment_) f += s.specific_force;
  f /= static_cast<double>(alignment_.size());
  const double roll = std::atan2(f.y(), f.z());
  const double pitch = std::atan2(-f.x(), std::hypot(f.y(), f.z()));
  x_.q = Eigen::Quaterniond(Eigen::AngleAxisd(config_.initial_yaw_rad, Vec3::UnitZ()) *
                            Eigen::AngleAxisd(pitch, Vec3::UnitY()) * Eigen::AngleAxisd(roll, Vec3::UnitX()));
  // At rest the gyros read their bias: where the spell is stillest.
  const std::size_t bias_samples = std::clamp<std::size_t>(
      static_cast<std::size_t>(std::lround(config_.alignment_bias_s * config_.rate_hz)), 1, alignment_.size());
  const std::size_t still = stillest_run(alignment_, bias_samples);
  const auto [rate, gyro_density] = mean_and_density(
      alignment_, still, bias_samples, [](const ImuSample& s) { return s.angular_rate; }, config_.rate_hz);
  x_.bg = rate;
  rest_noise_.gyro_density = gyro_density;
  rest_noise_.accel_density =
      mean_and_density(
          alignment_, still, bias_samples, [](const ImuSample& s) { return s.specific_force; }, config_.rate_hz)
          .second;
  // A spell shorter than alignment_s averaged fewer samples (and a stance's small motions).
  const double spell = std::max(still_s_, 1.0 / config_.rate_hz);
  const double bias_sigma = config_.initial_gyro_bias_sigma * std::sqrt(std::max(1.0, config_.alignment_s / spell));
  P_.setZero();
  P_.block<3, 3>(kV, kV) = Mat3::Identity() * config_.zupt_sigma_mps * config_.zupt_sigma_mps;
  P_(kTheta, kTheta) = P_(kTheta + 1, kTheta + 1) = config_.initial_tilt_sigma_rad * config_.initial_tilt_sigma_rad;
  P_(kTheta + 2, kTheta + 2) = config_.initial_yaw_sigma_rad * config_.initial_yaw_sigma_rad;
  P_.block<3, 3>(kBa, kBa) = Mat3::Identity() * config_.initial_accel_bias_sigma * config_.initial_accel_bias_sigma;
  P_.block<3, 3>(kBg, kBg) = Mat3::Identity() * bias_sigma * bias_sigma;
  aligned_ = true;
  alignment_.clear();
  still_s_ = 0.0;
  interval_t0_ = t_;
  interval_p0_ = x_.p;
  interval_yaw0_ = yaw();
}

template <int N>
void ZuptIns::correct(const Eigen::Matrix<double, N, kStates>& H, const Eigen::Matrix<double, N, 1>& r,
                      const Eigen::Matrix<double, N, N>& R) {
  const Eigen::Matrix<double, N, N> S = H * P_ * H.transpose() + R;
  const Eigen::Matrix<double, kStates, N> K = P_ * H.transpose() * S.inverse();
  const Eigen::Matrix<double, kStates, 1> dx = K * r;
  x_ = inject(x_, dx.head<15>());
  // The clone is the start-of-interval position: correct it as well.
  interval_p0_ += dx.segment<3>(kClone);
  const StateCov I_KH = StateCov::Identity() - K * H;
  P_ = I_KH * P_ * I_KH.transpose() + K * R * K.transpose();
}

void ZuptIns::zero_velocity_update(const ImuSample& s) {
  Eigen::Matrix<double, 3, kStates> H = Eigen::Matrix<double, 3, kStates>::Zero();
  H.block<3, 3>(0, kV) = Mat3::Identity();
  // A boot rolling heel to toe in its stance moves the IMU at its rate times the lever.
  const double rolling = (s.angular_rate - x_.bg).norm() * config_.zupt_rotation_lever_m;
  const double variance = config_.zupt_sigma_mps * config_.zupt_sigma_mps + rolling * rolling;
  correct<3>(H, -x_.v, Mat3::Identity() * variance);
}

void ZuptIns::zero_angular_rate_update(const ImuSample& s) {
  if (config_.zaru_sigma_radps <= 0.0) return;
  Eigen::Matrix<double, 3, kStates> H = Eigen::Matrix<double, 3, kStates>::Zero();
  H.block<3, 3>(0, kBg) = Mat3::Identity();
  correct<3>(H, s.angular_rate - x_.bg, Mat3::Identity() * config_.zaru_sigma_radps * config_.zaru_sigma_radps);
}

void ZuptIns::level_floor_update() {
  if (!last_stance_z_ || config_.level_step_m <= 0.0) return;
  const double dz = x_.p.z() - *last_stance_z_;
  if (std::abs(dz) > config_.level_step_m) return;  // a stair (or a step up): no constraint
  Eigen::Matrix<double, 1, kStates> H = Eigen::Matrix<double, 1, kStates>::Zero();
  H(0, kP + 2) = 1.0;
  correct<1>(H, Eigen::Matrix<double, 1, 1>(-dz),
             Eigen::Matrix<double, 1, 1>(config_.level_sigma_m * config_.level_sigma_m));
}

StepDisplacement ZuptIns::take_displacement() {
  StepDisplacement d;
  d.t0 = interval_t0_;
  d.t1 = t_;
  if (!aligned_) return d;
  d.delta = x_.p - interval_p0_;
  d.yaw_at_start = interval_yaw0_;
  d.yaw_change = std::remainder(yaw() - interval_yaw0_, 2.0 * kPi);
  // cov(p1 - p0) from the joint covariance of the position and its clone.
  Eigen::Matrix<double, 3, kStates> J = Eigen::Matrix<double, 3, kStates>::Zero();
  J.block<3, 3>(0, kP) = Mat3::Identity();
  J.block<3, 3>(0, kClone) = -Mat3::Identity();
  d.covariance = J * P_ * J.transpose();
  d.covariance.topLeftCorner<2, 2>() +=
      config_.stride_noise_m2_per_m * d.delta.head<2>().norm() * Eigen::Matrix2d::Identity();
  // New clone: the current position error.
  P_.block<3, kStates>(kClone, 0) = P_.block<3, kStates>(kP, 0);
  P_.block<kStates, 3>(0, kClone) = P_.block<kStates, 3>(0, kP);
  P_.block<3, 3>(kClone, kClone) = P_.block<3, 3>(kP, kP);
  interval_t0_ = t_;
  interval_p0_ = x_.p;
  interval_yaw0_ = yaw();
  return d;
}

}  // namespace sarloc::firefighter
