#include "sarloc/core/estimator/firefighter_device.hpp"

#include <cmath>
#include <sstream>
#include <utility>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/firefighter/search_walk.hpp"

namespace sarloc::estimator {
namespace {

TimestampNs to_ns(double s) { return static_cast<TimestampNs>(std::llround(s * 1e9)); }

}  // namespace

void FirefighterDeviceConfig::validate() const {
  ins.validate();
  const auto in_range = [](double v, const char* key, double lo, double hi) {
    if (!std::isfinite(v) || v <= lo || v > hi) {
      std::ostringstream os;
      os << "firefighter_device." << key << " = " << v << ": must be in (" << lo << ", " << hi << "]";
      throw ConfigError(os.str());
    }
  };
  in_range(odometry_rate_hz, "odometry_rate_hz", 0.0, 50.0);
  in_range(dead_reckoning_drift, "dead_reckoning_drift", 0.0, 1.0);
  in_range(history_s, "history_s", 1.0, 86400.0);
  in_range(own_position_period_s, "own_position_period_s", 0.01, 3600.0);
}

FirefighterDevice::FirefighterDevice(std::string responder_id, std::string team_id, FirefighterDeviceConfig config,
                                     TimestampNs origin)
    : id_(std::move(responder_id)),
      team_(std::move(team_id)),
      config_((config.validate(), std::move(config))),
      origin_(origin),
      ins_(config_.ins) {}

TimestampNs FirefighterDevice::now() const { return origin_ + to_ns(ins_.time()); }

void FirefighterDevice::push(const firefighter::ImuSample& sample) {
  ins_.push(sample);  // throws InputError before touching anything
  if (!ins_.aligned()) return;
  if (!started_) {
    (void)ins_.take_displacement();
    started_ = true;
    interval_start_s_ = ins_.time();
    first_pose_stamp_ = now();
    history_.push_back({first_pose_stamp_, ins_.nominal().p, ins_.yaw(), 0.0});
    if (start_) start_at(*std::exchange(start_, std::nullopt));
  }
  update_motionless();
}

std::optional<responder::Odometry> FirefighterDevice::take_odometry() {
  if (!started_ || ins_.time() - interval_start_s_ + 1e-9 < 1.0 / config_.odometry_rate_hz) return std::nullopt;
  const firefighter::StepDisplacement d = ins_.take_displacement();
  responder::Odometry o;
  o.rescuer_id = id_;
  o.sequence = ++sequence_;
  o.interval_start = origin_ + to_ns(interval_start_s_);
  o.interval_end = now();
  interval_start_s_ = ins_.time();
  // Level frame at the interval's start: x along the INS yaw then.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(-d.yaw_at_start, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  o.translation = R * d.delta;
  o.rotation_rpy = Vec3(0.0, 0.0, d.yaw_change);
  o.covariance.setZero();
  o.covariance.topLeftCorner<3, 3>() = R * d.covariance * R.transpose();
  const double dt = d.t1 - d.t0;
  const double gyro = config_.ins.gyro_noise_density;
  o.covariance(3, 3) = o.covariance(4, 4) = 1e-6;  // level by construction
  o.covariance(5, 5) = std::max(gyro * gyro * dt, 1e-8);
  o.source = responder::OdometrySource::kFootMountedIns;
  walked_m_ += d.delta.head<2>().norm();
  history_.push_back({o.interval_end, ins_.nominal().p, ins_.yaw(), walked_m_});
  while (!history_.empty() && history_.front().stamp < o.interval_end - to_ns(config_.history_s)) history_.pop_front();
  return o;
}

void FirefighterDevice::update_motionless() {
  const double t = ins_.time();
  if (ins_.motionless_s() == 0.0) motionless_reset_at_s_ = -1.0;
  const bool rearmed = motionless_reset_at_s_ < 0.0 || t - motionless_reset_at_s_ >= config_.ins.motionless_after_s;
  if (!motionless_ && ins_.motionless() && rearmed) {
    raise(responder::AlarmKind::kMotionless);
  } else if (motionless_ && ins_.motionless_s() == 0.0) {
    clear(responder::AlarmKind::kMotionless);
  }
}

void FirefighterDevice::press_mayday() {
  if (!mayday_) raise(responder::AlarmKind::kMayday);
}

void FirefighterDevice::reset(responder::AlarmKind kind) {
  if (kind == responder::AlarmKind::kMotionless && motionless_) {
    motionless_reset_at_s_ = ins_.time();
    clear(kind);
  } else if (kind == responder::AlarmKind::kMayday && mayday_) {
    clear(kind);
  }
}

void FirefighterDevice::raise(responder::AlarmKind kind) {
  responder::ResponderAlarm a;
  a.responder_id = id_;
  a.team_id = team_;
  a.kind = kind;
  a.raised_at = now();
  a.active = true;
  if (const auto p = dead_reckoning()) {
    a.last_position = p->position;
    a.position_known = true;
    a.floor = p->floor;
  }
  (kind == responder::AlarmKind::kMotionless ? motionless_ : mayday_) = a;
  changes_.push_back(a);
}

void FirefighterDevice::clear(responder::AlarmKind kind) {
  auto& slot = kind == responder::AlarmKind::kMotionless ? motionless_ : mayday_;
  if (!slot) return;
  responder::ResponderAlarm a = *slot;
  a.active = false;
  a.cleared_at = now();
  if (const auto p = dead_reckoning()) {
    a.last_position = p->position;
    a.position_known = true;
    a.floor = p->floor;
  }
  slot.reset();
  changes_.push_back(a);
}

std::vector<responder::ResponderAlarm> FirefighterDevice::alarm_changes() {
  std::vector<responder::ResponderAlarm> out;
  out.swap(changes_);
  return out;
}

std::vector<responder::ResponderAlarm> FirefighterDevice::active_alarms() const {
  std::vector<responder::ResponderAlarm> out;
  if (motionless_) out.push_back(*motionless_);
  if (mayday_) out.push_back(*mayday_);
  return out;
}

namespace {

void check_finite(const responder::ResponderPosition& fix) {
  if (!fix.position.position.allFinite() || !fix.position.covariance.allFinite() || !std::isfinite(fix.heading_rad)) {
    throw InputError("fix of '" + fix.responder_id + "': position, covariance or heading not finite");
  }
}

}  // namespace

bool FirefighterDevice::on_fix(const responder::ResponderPosition& fix) {
  check_finite(fix);
  if (fix_ && fix.stamp < fix_->stamp) return false;  // an older fix overtaken on the way
  if (const auto own = dead_reckoning();
      own && !fix.converged &&
      own->position.covariance.topLeftCorner<2, 2>().trace() <= fix.position.covariance.topLeftCorner<2, 2>().trace()) {
    return false;
  }
  fix_ = fix;
  return true;
}

bool FirefighterDevice::start_at(responder::ResponderPosition entry) {
  check_finite(entry);  // here, not in push(), which throws only before touching anything
  if (!started_) {
    start_ = std::move(entry);
    return true;
  }
  // The first pose, as long as the history reaches back to it.
  if (history_.empty() || history_.front().stamp != first_pose_stamp_) return false;
  entry.stamp = first_pose_stamp_;
  return on_fix(entry);
}

std::optional<responder::ResponderPosition> FirefighterDevice::take_own_position() {
  if (history_.empty()) return std::nullopt;
  if (own_position_at_ && history_.back().stamp - *own_position_at_ < to_ns(config_.own_position_period_s) - 1) {
    return std::nullopt;
  }
  auto own = dead_reckoning();
  if (!own) return std::nullopt;
  own->responder_id = id_;
  own->team_id = team_;
  own_position_at_ = own->stamp;
  return own;
}

std::optional<FirefighterDevice::InsPose> FirefighterDevice::pose_at(TimestampNs stamp) const {
  if (history_.empty() || stamp < history_.front().stamp) return std::nullopt;
  const InsPose* best = &history_.front();
  for (const InsPose& p : history_) {
    if (p.stamp > stamp) break;
    best = &p;
  }
  return *best;
}

std::optional<responder::ResponderPosition> FirefighterDevice::dead_reckoning() const {
  if (!fix_ || history_.empty()) return std::nullopt;
  const auto at_fix = pose_at(fix_->stamp);
  if (!at_fix) return std::nullopt;
  const InsPose& latest = history_.back();
  // The fix's heading is the boot's ENU yaw at its stamp: it turns the INS frame into ENU.
  const double frame = fix_->heading_rad - at_fix->yaw;
  const Eigen::Vector3d moved = latest.position - at_fix->position;
  const Eigen::Vector2d east_north = Eigen::Rotation2Dd(frame) * moved.head<2>();
  responder::ResponderPosition p = *fix_;
  p.stamp = latest.stamp;
  p.position.position += Vec3(east_north.x(), east_north.y(), 0.0);
  const double grown = config_.dead_reckoning_drift * (latest.walked_m - at_fix->walked_m);
  p.position.covariance.topLeftCorner<2, 2>() += grown * grown * Eigen::Matrix2d::Identity();
  p.heading_rad = wrap_angle(frame + latest.yaw);
  p.source = responder::PositionSource::kDeadReckoning;
  p.converged = false;
  p.confirmed = false;
  return p;
}

std::optional<responder::ResponderPosition> entry_fix(const firefighter::FloorPlan& plan,
                                                      const FirefighterEstimatorConfig& placement,
                                                      const std::string& responder_id, const std::string& team_id,
                                                      const std::string& entry, firefighter::Hand hand) {
  if (entry.empty()) return std::nullopt;
  const auto stance = firefighter::entry_stance(plan, entry, hand);
  if (!stance) return std::nullopt;
  const firefighter::Vec2 xy = placement.to_incident(stance->position);
  responder::ResponderPosition p;
  p.responder_id = responder_id;
  p.team_id = team_id;
  p.position.position = Vec3(xy.x(), xy.y(), plan.floors[stance->floor].elevation_m);
  p.position.covariance = Mat3::Identity() * std::pow(placement.entry_position_sigma_m, 2);
  p.heading_rad = wrap_angle(placement.rotation_rad() + stance->heading_rad);
  p.floor = static_cast<std::int32_t>(stance->floor);
  p.source = responder::PositionSource::kManual;
  return p;
}

}  // namespace sarloc::estimator
