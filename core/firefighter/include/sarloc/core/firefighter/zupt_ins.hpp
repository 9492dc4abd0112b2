#pragma once
// Foot-mounted, ZUPT-aided inertial navigation (seed 004 section IV-A; Nilsson et al., "Foot-
// mounted inertial navigation made easy", 2014): a strapdown INS on the boot's IMU, an
// error-state Kalman filter, and a SHOE zero-velocity detector (Skog et al., "Zero-velocity
// detection: an algorithm evaluation", 2010) whose stance phases feed zero-velocity updates.
//
// Navigation frame: x, y level, z up, yaw 0 along `initial_yaw_rad` (the frame is the INS's
// own: the map-aided filter estimates its rotation to the map). Error state (global attitude
// error, R_true = Exp(dtheta) R):
//   [dp(3) dv(3) dtheta(3) dba(3) dbg(3) dp_clone(3)]
// dp_clone is the position error at the start of the current odometry interval (stochastic
// cloning), so that the covariance of a displacement is exact, not a difference of variances.
//
//   ZuptIns ins(config);
//   for (const ImuSample& s : samples) ins.push(s);      // InputError on bad samples
//   StepDisplacement d = ins.take_displacement();        // e.g. every 0.5 s (2 Hz)
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <deque>
#include <optional>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/firefighter/imu_sample.hpp"
#include "sarloc/core/firefighter/stance_threshold.hpp"

namespace sarloc::firefighter {

/// The INS's process noise over a sensor's white-noise density: what the model leaves out
/// (scale factors, misalignment, vibration) is not white noise, and is not modelled otherwise.
inline constexpr double kProcessNoiseInflation = 2.0;

/// The white noise of a still IMU, measured over the stillest part of the alignment spell
/// (ZuptInsConfig::alignment_bias_s): densities per axis, averaged over the three, so that a new
/// sensor's source file can declare them. A boot that sways reads more than its noise.
struct RestNoise {
  double accel_density = 0.0;  ///< m/s^2/sqrt(Hz)
  double gyro_density = 0.0;   ///< rad/s/sqrt(Hz)
};

struct ZuptInsConfig {
  double rate_hz = 100.0;
  /// Stand still this long at power-up: roll, pitch and the gyro biases are taken from it.
  double alignment_s = 1.0;
  /// A still spell at least this long that ends before alignment_s (the walk started) aligns on
  /// itself: a recording that starts walking gets a track from its first stance phase, with a
  /// gyro-bias uncertainty widened by sqrt(alignment_s / spell); the ZUPTs refine the tilt.
  double alignment_min_s = 0.15;
  /// The gyro bias is the mean rate over the stillest this-long part of the spell (the least
  /// varying rates): a boot that the detector calls still sways at a few deg/s, whose mean over
  /// the spell is a net rotation (1.6 deg/s on a GX5 walk), not a bias.
  double alignment_bias_s = 0.25;
  double initial_yaw_rad = 0.0;
  // Process noise: the MTi 1-series figures (imu_error_model.hpp), or a source file's declared
  // ones (apply_declared, imu_source.hpp), times kProcessNoiseInflation for the unmodelled.
  double accel_noise_density = kProcessNoiseInflation * 120e-6 * kGravity;
  double gyro_noise_density = kProcessNoiseInflation * 0.007 * kPi / 180.0;
  double accel_bias_walk = 1e-4;  ///< m/s^2/sqrt(s)
  double gyro_bias_walk = 1e-5;   ///< rad/s/sqrt(s)
  double initial_accel_bias_sigma = 0.1;    ///< m/s^2
  double initial_gyro_bias_sigma = 2e-4;    ///< rad/s, after the alignment's averaging
  double initial_tilt_sigma_rad = 0.01;
  double initial_yaw_sigma_rad = 1e-3;
  double zupt_sigma_mps = 0.01;
  /// The zero velocity is the foot's, not the IMU's: a boot rolling heel to toe at rate w moves
  /// an IMU this far from its pivot at w times it, added to zupt_sigma_mps. Held to a still IMU,
  /// the GX5 walks lost each heel-off's rise and ended 0.4-1.8 m below a flat floor.
  double zupt_rotation_lever_m = 0.05;
  /// A foot lands slowly: a still reading that begins while the INS moves faster than this is a
  /// pause inside a swing, not a stance. A boot coasting at constant velocity reads gravity
  /// alone, as in a stance: at 2 m strides the GX5 walks held 9-17 such samples mid-swing, and
  /// each one's ZUPT cut a stride short and dropped the track 0.1-0.4 m. After a missed stance
  /// the INS's own velocity can be wrong by more than this, so a still reading that lasts
  /// swing_pause_max_s, or begins swing_max_s after the last stance (no swing lasts that long),
  /// is a stance at any speed. 0 turns it off.
  double landing_speed_max_mps = 1.0;
  double swing_pause_max_s = 0.1;
  double swing_max_s = 1.0;
  // SHOE detector: stationary when T < threshold, T = 1/W sum over the last W samples of
  // |f - g mean(f)/|mean(f)||^2 / sigma_a^2 + |w|^2 / sigma_g^2. OpenShoe's sigmas; the
  // threshold is a third of OpenShoe's 3e4, so that the slow swings of crawling (about 1 m/s^2,
  // 10 deg/s at their ends) count as motion; at rest T is about 5 with MTi-3 noise.
  std::uint32_t detector_window = 5;
  double detector_sigma_accel = 0.01;                          ///< m/s^2
  double detector_sigma_gyro = 0.1 * kPi / 180.0;  ///< rad/s
  double detector_threshold = 1e4;
  /// Adapts the threshold above detector_threshold (its floor) to the sensor and the gait
  /// (stance_threshold.hpp); off: detector_threshold alone.
  bool adaptive_stance = false;
  StanceThresholdConfig stance;
  StanceDetector detector = StanceDetector::kShoe;
  std::uint32_t stance_votes = 2;  ///< kVote: a stance when this many of the three say so (2 or 3)
  /// Zero angular rate in stance: the gyros read their bias, with this noise (the foot's own
  /// small rotations in a stance included). 0 turns it off.
  double zaru_sigma_radps = 0.5 * kPi / 180.0;
  /// ... once the stance has lasted this long: standing, not a walking footfall, whose heel-to-
  /// toe roll turns the boot at 10-30 deg/s (a ZARU there bent the gait-driven tracks by 2-10 %).
  double zaru_after_s = 0.5;
  /// Level floor: a stance whose height is within level_step_m of the previous stance's is on
  /// the same floor (a stair riser is about 0.17 m, two per stride): one pseudo-observation of
  /// the height difference, zero, with level_sigma_m. 0 turns it off.
  double level_step_m = 0.1;
  double level_sigma_m = 0.005;
  /// Horizontal variance (m^2 per m walked, each axis) added to every displacement's stated
  /// covariance: what the filter's model leaves out on a real boot (the foot rolls in stance,
  /// stance edges, the placement of the foot). The filter's own covariance states 1e2-1e3 times
  /// less than the strides' errors on the gait-driven walks (stride NEES 137-908); with this the
  /// stride NEES is at most its 95 % bound on every walk whose footfalls the detector paired
  /// with at most 2 groups (docs/estimation/firefighter.md, "An honest covariance on real boots").
  double stride_noise_m2_per_m = 0.015;
  /// No swing phase for this long: the firefighter has not moved (a PASS device's alarm).
  double motionless_after_s = 30.0;
  void validate() const;
};

/// The displacement of the boot over [t0, t1] in the navigation frame, its covariance, and the
/// yaw change (for the robocentric Odometry the device publishes).
struct StepDisplacement {
  double t0 = 0.0, t1 = 0.0;
  Eigen::Vector3d delta = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  double yaw_change = 0.0;
  double yaw_at_start = 0.0;
};

class ZuptIns {
 public:
  static constexpr int kP = 0, kV = 3, kTheta = 6, kBa = 9, kBg = 12, kClone = 15, kStates = 18;
  using StateCov = Eigen::Matrix<double, kStates, kStates>;

  struct Nominal {
    Eigen::Vector3d p = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero();
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  ///< body to navigation
    Eigen::Vector3d ba = Eigen::Vector3d::Zero(), bg = Eigen::Vector3d::Zero();
  };

  explicit ZuptIns(ZuptInsConfig config);

  /// One IMU sample. Throws InputError (naming the field) for NaN/Inf, magnitudes beyond the
  /// sensor's range (16 g, 2000 deg/s), or a time not after the previous sample.
  void push(const ImuSample& sample);

  bool aligned() const { return aligned_; }
  bool stationary() const { return stationary_; }
  /// Seconds since the last swing phase (0 while moving).
  double motionless_s() const { return motionless_s_; }
  bool motionless() const { return motionless_s_ >= config_.motionless_after_s; }
  const Nominal& nominal() const { return x_; }
  /// Measured where the gyro bias was (zero before alignment).
  const RestNoise& rest_noise() const { return rest_noise_; }
  const StateCov& covariance() const { return P_; }
  double time() const { return t_; }
  double yaw() const;

  /// Displacement since the previous call (or since alignment), then starts a new interval.
  StepDisplacement take_displacement();

  /// The discrete nominal propagation over one sample interval, trapezoidal in the samples at
  /// its two ends (a rectangle rule tilts the boot by half a sample of its 5 rad/s swing and
  /// loses 3 cm of height a stride), and its error-state transition (exposed for the Jacobian
  /// test): x' = f(x, s0, s1, dt); F = d(x' error)/d(x error).
  static Nominal propagate(const Nominal& x, const ImuSample& s0, const ImuSample& s1, double dt);
  static Eigen::Matrix<double, 15, 15> transition(const Nominal& x, const ImuSample& s0, const ImuSample& s1,
                                                  double dt);
  /// x (+) dx and x' (-) x for the 15 navigation error states.
  static Nominal inject(const Nominal& x, const Eigen::Matrix<double, 15, 1>& dx);
  static Eigen::Matrix<double, 15, 1> difference(const Nominal& a, const Nominal& b);

 private:
  void align();
  bool detect();
  /// A still reading now is a pause in a swing (landing_speed_max_mps), not a stance.
  bool in_swing_pause() const;
  void zero_velocity_update(const ImuSample& s);
  void level_floor_update();
  void zero_angular_rate_update(const ImuSample& s);
  /// The Kalman correction of the error state for residual r = H dx + noise(R).
  template <int N>
  void correct(const Eigen::Matrix<double, N, kStates>& H, const Eigen::Matrix<double, N, 1>& r,
               const Eigen::Matrix<double, N, N>& R);

  ZuptInsConfig config_;
  Nominal x_;
  StateCov P_ = StateCov::Zero();
  std::deque<ImuSample> window_;
  StanceThreshold stance_threshold_;  // SHOE's, and in a vote ARED's and AMVD's
  StanceThreshold ared_threshold_;
  StanceThreshold amvd_threshold_;
  ImuSample previous_;
  std::deque<ImuSample> alignment_;
  RestNoise rest_noise_;
  bool aligned_ = false;
  bool stationary_ = true;
  bool have_time_ = false;
  double t_ = 0.0;
  double motionless_s_ = 0.0;
  double stance_s_ = 0.0;                ///< the current stance so far
  double still_s_ = 0.0;                 ///< the current still spell (before alignment)
  double stance_ended_at_ = 0.0;         ///< when the last stance ended
  double still_run_s_ = 0.0;             ///< how long the detector has read still, stance or not
  std::optional<double> last_stance_z_;  ///< height at the end of the previous stance
  double interval_t0_ = 0.0;
  Eigen::Vector3d interval_p0_ = Eigen::Vector3d::Zero();
  double interval_yaw0_ = 0.0;
};

}  // namespace sarloc::firefighter
