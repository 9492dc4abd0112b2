#pragma once
// What a firefighter's device does apart from DDS (sarloc-rescuer, firefighter role):
//   - runs the ZUPT INS on the boot's 100 Hz IMU and hands out its displacement as Odometry
//     (source kFootMountedIns) at the odometry rate (2 Hz, seed 004 section V-B), in the
//     convention FirefighterEstimator reads (level frame at the interval's start, yaw change);
//   - keeps the alarms a PASS device keeps: motionless (no swing phase for
//     `ins.motionless_after_s`), cleared by moving again or an explicit reset, and re-armed
//     after a reset; and the mayday the firefighter raises, cleared only by an explicit reset
//     (a firefighter who called a mayday and walks on is still in trouble);
//   - dead reckons from the daemon's last map-aided fix when the daemon is silent: the fix
//     plus the INS's displacement since, turned into the incident frame with the fix's heading,
//     its uncertainty grown by `dead_reckoning_drift` of the distance walked since.
//
//   FirefighterDevice dev("ff1", "alpha", FirefighterDeviceConfig{}, mission_start_ns);
//   dev.start_at(*entry_fix(plan, placement, "ff1", "alpha", "front", Hand::kRight));
//   dev.push(imu_sample);                                  // t: s since power-up
//   if (auto o = dev.take_odometry()) publish(*o);         // when an interval is due
//   if (auto own = dev.take_own_position()) publish(*own);  // once a mission second
//   for (auto& a : dev.alarm_changes()) publish(a);
//   dev.on_fix(daemon_position);
//   auto p = dev.dead_reckoning();                          // POSITION_DEAD_RECKONING
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "sarloc/core/estimator/firefighter_estimator.hpp"
#include "sarloc/core/firefighter/zupt_ins.hpp"
#include "sarloc/core/responder/alarm.hpp"
#include "sarloc/core/responder/odometry.hpp"
#include "sarloc/core/responder/responder_position.hpp"

namespace sarloc::estimator {

struct FirefighterDeviceConfig {
  firefighter::ZuptInsConfig ins;  ///< motionless_after_s: the motionless alarm's time (30 s)
  double odometry_rate_hz = 2.0;
  /// 1-sigma growth of a dead-reckoned position per metre walked since the fix (the INS's
  /// drift: about 1 % median, 2 % at the 95th percentile, docs/estimation/firefighter.md).
  double dead_reckoning_drift = 0.02;
  /// How long the INS history for dead reckoning reaches back (a fix older than this is not used).
  double history_s = 600.0;
  /// Mission seconds between two of the device's own positions (take_own_position).
  double own_position_period_s = 1.0;
  void validate() const;
};

class FirefighterDevice {
 public:
  /// `origin`: the mission time of the IMU's t = 0.
  FirefighterDevice(std::string responder_id, std::string team_id, FirefighterDeviceConfig config, TimestampNs origin);

  /// One IMU sample. Throws InputError naming the field (the device is left untouched).
  void push(const firefighter::ImuSample& sample);
  /// The displacement since the previous odometry once 1 / odometry_rate_hz has passed since
  /// it (and the INS is aligned); nullopt otherwise.
  std::optional<responder::Odometry> take_odometry();

  void press_mayday();
  /// Clears the alarm of `kind` (the firefighter or incident command pressed reset).
  void reset(responder::AlarmKind kind);
  /// Alarms raised or cleared since the previous call, oldest first; each carries the last
  /// known position (the dead-reckoned one, or none).
  std::vector<responder::ResponderAlarm> alarm_changes();
  /// Every alarm active now.
  std::vector<responder::ResponderAlarm> active_alarms() const;

  /// The device's first anchor before any fix (entry_fix: where the crew aligns its boots),
  /// taken at the INS's first pose, whose stamp it gets: when the INS starts (so an alarm
  /// raised before the first odometry already carries it), or at once if it has. Returns false
  /// when it is not taken (on_fix's rules, or the history no longer reaches the first pose);
  /// throws InputError for a position, covariance or heading not finite.
  bool start_at(responder::ResponderPosition entry);
  /// The daemon's map-aided position (or a manual one): the anchor of dead reckoning. A fix that
  /// has not converged does not replace an anchor whose dead reckoning is surer (a smaller
  /// horizontal covariance): a daemon restarted mid-search first answers with the mean of a
  /// cloud spread over the plan, and the device keeps what it knew. Returns whether it anchors.
  /// (A converged fix is taken even where it contradicts the reckoning: refusing those, tried on
  /// the kill-core building mission, kept reckonings that had gone wrong; docs/estimation/firefighter.md.)
  bool on_fix(const responder::ResponderPosition& fix);
  /// The last fix moved by the INS since (source kDeadReckoning), or nullopt without a fix
  /// in the history's reach.
  std::optional<responder::ResponderPosition> dead_reckoning() const;
  /// The dead reckoning under the device's own ids, once own_position_period_s of mission time
  /// has passed since the last one taken (nullopt otherwise, or without an anchor). Published, it
  /// is the firefighter's link at incident command while the daemon is silent, and the start a
  /// daemon that meets the firefighter mid-search takes (ResponderEstimator::hint_position).
  std::optional<responder::ResponderPosition> take_own_position();

  TimestampNs now() const;
  bool aligned() const { return ins_.aligned(); }
  bool motionless() const { return ins_.motionless(); }
  double distance_walked_m() const { return walked_m_; }
  const firefighter::ZuptIns& ins() const { return ins_; }

 private:
  struct InsPose {
    TimestampNs stamp;
    Eigen::Vector3d position;
    double yaw;
    double walked_m;
  };
  std::optional<InsPose> pose_at(TimestampNs stamp) const;
  void raise(responder::AlarmKind kind);
  void clear(responder::AlarmKind kind);
  void update_motionless();

  std::string id_, team_;
  FirefighterDeviceConfig config_;
  TimestampNs origin_;
  firefighter::ZuptIns ins_;
  bool started_ = false;
  double interval_start_s_ = 0.0;
  std::uint64_t sequence_ = 0;
  double walked_m_ = 0.0;
  std::deque<InsPose> history_;
  std::optional<responder::ResponderPosition> fix_;
  std::optional<responder::ResponderPosition> start_;  ///< start_at's anchor until the INS starts
  std::optional<TimestampNs> own_position_at_;         ///< stamp of the last take_own_position
  TimestampNs first_pose_stamp_ = 0;                   ///< when the INS started
  std::optional<responder::ResponderAlarm> motionless_, mayday_;
  double motionless_reset_at_s_ = -1.0;  ///< a reset while still motionless re-arms from here
  std::vector<responder::ResponderAlarm> changes_;
};

/// The device's first anchor, before any fix: where the crew aligns its boots, just inside the
/// reported entry of `plan` and turned to its wall (firefighter::entry_stance), in the incident
/// frame of `placement`, within its entry_position_sigma_m (source kManual). Nullopt without an
/// entry or for one `plan` does not have. Stamp it with the INS history's first pose.
std::optional<responder::ResponderPosition> entry_fix(const firefighter::FloorPlan& plan,
                                                      const FirefighterEstimatorConfig& placement,
                                                      const std::string& responder_id, const std::string& team_id,
                                                      const std::string& entry, firefighter::Hand hand);

}  // namespace sarloc::estimator
