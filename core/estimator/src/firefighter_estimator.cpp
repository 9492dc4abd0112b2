#include "sarloc/core/estimator/firefighter_estimator.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::estimator {
namespace {

using responder::RejectReason;

// A step further than this past the last one is a clock jump, not a gap to spread over.
constexpr TimestampNs kMaxGapNs = 120'000'000'000;
// A brisk stride of one foot (m): the most a boot may be ahead of what max_speed_mps allows.
constexpr double kStrideSlackM = 1.5;

firefighter::MapFilterConfig filter_with_entry_prior(const FirefighterEstimatorConfig& config) {
  firefighter::MapFilterConfig f = config.filter;
  f.known_position_sigma_m = config.entry_position_sigma_m;
  f.known_heading_sigma_deg = config.entry_heading_sigma_deg;
  return f;
}

std::uint64_t seed_of(const std::string& id, std::uint64_t seed) {
  return seed ^ (std::hash<std::string>{}(id) * 0x9E3779B97F4A7C15ULL);
}

}  // namespace

void FirefighterEstimatorConfig::validate() const {
  const auto positive = [](double v, const char* key, double max) {
    if (!std::isfinite(v) || v <= 0.0 || v > max) {
      std::ostringstream os;
      os << "firefighter." << key << " = " << v << ": must be in (0, " << max << "]";
      throw ConfigError(os.str());
    }
  };
  positive(entry_position_sigma_m, "entry_position_sigma_m", 20.0);
  positive(entry_heading_sigma_deg, "entry_heading_sigma_deg", 180.0);
  positive(max_speed_mps, "max_speed_mps", 10.0);
  positive(hint_max_age_s, "hint_max_age_s", 120.0);
  positive(hint_sigma_scale, "hint_sigma_scale", 10.0);
  positive(hint_heading_sigma_deg, "hint_heading_sigma_deg", 180.0);
  positive(hint_max_sigma_m, "hint_max_sigma_m", 100.0);
  if (!origin.allFinite() || origin.norm() > 1e6) throw ConfigError("building.origin: must be finite, within 1000 km");
  if (!std::isfinite(rotation_deg) || std::abs(rotation_deg) > 360.0) {
    throw ConfigError("building.rotation_deg = " + config_value(rotation_deg) + ": must be in [-360, 360]");
  }
  filter.validate();
  if (!building && !entry_of.empty()) {
    throw ConfigError("rescuers[" + entry_of.begin()->first + "].entry: the mission has no building: section");
  }
  if (building) {
    for (const auto& [id, start] : entry_of) {
      if (start.entry.empty()) continue;
      bool found = false;
      for (const auto& e : building->plan().entries) found = found || e.id == start.entry;
      if (!found) throw ConfigError("rescuers[" + id + "].entry = '" + start.entry + "': not an entry of the building");
    }
  }
}

FirefighterEstimator::FirefighterEstimator(std::string responder_id, const FirefighterEstimatorConfig& config)
    : id_(std::move(responder_id)),
      config_(config),
      localizer_((config.building ? void() : throw ConfigError("firefighter '" + id_ + "': the mission has no building"),
                  config.building),
                 filter_with_entry_prior(config), seed_of(id_, config.seed)) {
  const auto it = config_.entry_of.find(id_);
  if (it != config_.entry_of.end() && !it->second.entry.empty()) {
    for (const auto& e : config_.building->plan().entries) {
      if (e.id == it->second.entry) entry_ = e.id;
    }
    if (entry_.empty()) {
      throw ConfigError("rescuers[" + id_ + "].entry = '" + it->second.entry + "': not an entry of the building");
    }
  }
}

void FirefighterEstimator::hint_position(const responder::ResponderPosition& own) {
  if (own.responder_id != id_ || own.source != responder::PositionSource::kDeadReckoning) return;
  if (!own.position.position.allFinite() || !own.position.covariance.allFinite() || !std::isfinite(own.heading_rad))
    return;
  if (own.floor < 0 || static_cast<std::size_t>(own.floor) >= config_.building->plan().floors.size()) return;
  if (hint_ && own.stamp <= hint_->stamp) return;
  hint_ = own;
}

bool FirefighterEstimator::start_near_hint(TimestampNs at) {
  if (!hint_) return false;
  const double age_s = 1e-9 * static_cast<double>(at > hint_->stamp ? at - hint_->stamp : hint_->stamp - at);
  if (age_s > config_.hint_max_age_s) return false;
  const double rot = config_.rotation_rad();
  const firefighter::Vec2 plan_xy =
      firefighter::rotate(firefighter::Vec2(hint_->position.position.head<2>()) - config_.origin, -rot);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> spread(hint_->position.covariance.topLeftCorner<2, 2>());
  // Its own spread, widened (a device's reckoning is not always as sure as it says), and how far
  // the firefighter may have walked between the hint and this step.
  const double sigma =
      std::max(0.5, config_.hint_sigma_scale * std::sqrt(std::max(0.0, spread.eigenvalues().maxCoeff())) +
                        0.5 * config_.max_speed_mps * age_s);
  if (sigma > config_.hint_max_sigma_m) return false;
  localizer_.start_near(plan_xy, static_cast<std::size_t>(hint_->floor), wrap_angle(hint_->heading_rad - rot - yaw_),
                        sigma, config_.hint_heading_sigma_deg);
  started_near_hint_ = true;
  started_inside_unknown_ = false;
  return true;
}

void FirefighterEstimator::start(std::uint64_t first_sequence, TimestampNs at) {
  // The reported entry is where the walk began: it holds only if this is the device's first
  // step. A daemon restarted (or whose idle state was released) mid-search meets the
  // firefighter somewhere inside, and starting it at the door would be a confident wrong place.
  const auto it = config_.entry_of.find(id_);
  if (!entry_.empty() && first_sequence == 1) {
    // The crew aligns the boot INS standing just inside the door, turned to its wall.
    if (const auto stance = firefighter::entry_stance(config_.building->plan(), entry_, it->second.hand)) {
      localizer_.start_at(stance->position, stance->floor, wrap_angle(stance->heading_rad));
    }
  } else if (first_sequence == 1) {
    // The device's first step: the firefighter is yet to come in, by a door most likely.
    localizer_.start_unknown(firefighter::UnknownStart::kWalkedIn);
  } else {
    started_mid_search_ = !entry_.empty();
    if (!start_near_hint(at)) {
      localizer_.start_unknown(firefighter::UnknownStart::kInside);
      started_inside_unknown_ = true;
    }
  }
}

Outcome FirefighterEstimator::add_odometry(const responder::Odometry& o) {
  if (o.rescuer_id != id_) {
    return responder::reject(RejectReason::kWrongRescuer, id_, "odometry of '" + o.rescuer_id + "'");
  }
  if (last_sequence_ && o.sequence == *last_sequence_) {
    return responder::reject(RejectReason::kDuplicateSequence, id_, "odometry sequence " + std::to_string(o.sequence) + " again");
  }
  if (last_sequence_ && o.sequence < *last_sequence_) {
    return responder::reject(RejectReason::kSequenceBackwards, id_,
                             "odometry sequence " + std::to_string(o.sequence) + " after " + std::to_string(*last_sequence_));
  }
  if (o.interval_end <= o.interval_start || o.interval_start < last_end_ ||
      (last_end_ > 0 && o.interval_end - last_end_ > kMaxGapNs)) {
    return responder::reject(RejectReason::kStampBackwards, id_,
                             "odometry interval [" + std::to_string(o.interval_start) + ", " +
                                 std::to_string(o.interval_end) + "] after " + std::to_string(last_end_));
  }
  if (!o.translation.allFinite() || !o.rotation_rpy.allFinite() || !o.covariance.allFinite()) {
    return responder::reject(RejectReason::kInvalidValue, id_, "odometry translation/rotation/covariance: not finite");
  }
  const double dt = 1e-9 * static_cast<double>(o.interval_end - o.interval_start);
  // The boot, not the body: within a window its foot may start half a stride behind the body
  // and end half a stride ahead (a real 0.5 s window held 1.29 m of a 1.5 m/s walk: x-io's short
  // walk, docs/estimation/firefighter.md "Real recordings"), so one stride of slack.
  const double reach = config_.max_speed_mps * dt + kStrideSlackM;
  if (o.translation.norm() > reach || std::abs(o.rotation_rpy.z()) > 3.2) {
    std::ostringstream os;
    os << "odometry translation " << o.translation.norm() << " m in " << dt << " s (at most " << reach
       << " m) or yaw change " << o.rotation_rpy.z() << " rad";
    return responder::reject(RejectReason::kAbsurdMotion, id_, os.str());
  }
  if (!localizer_.started()) {
    start(o.sequence, o.interval_start);
  } else if (started_inside_unknown_ && !ever_converged_) {
    start_near_hint(o.interval_start);  // the device's position came after the first step
  }
  if (last_end_ > 0 && o.interval_start > last_end_) {
    // Steps lost on the way: the firefighter walked somewhere meanwhile.
    const double gap_s = 1e-9 * static_cast<double>(o.interval_start - last_end_);
    localizer_.lost_motion(0.5 * config_.max_speed_mps * gap_s);
  }
  const firefighter::Vec2 horizontal = firefighter::rotate(o.translation.head<2>(), yaw_);
  const firefighter::MapEstimate e = localizer_.step(Eigen::Vector3d(horizontal.x(), horizontal.y(), o.translation.z()));
  yaw_ = wrap_angle(yaw_ + o.rotation_rpy.z());
  last_sequence_ = o.sequence;
  last_end_ = o.interval_end;
  ever_converged_ = ever_converged_ || e.converged;
  EstimatorOutput out;
  out.position = position_at(o.interval_end, e);
  out.candidates = candidates_at(o.interval_end, e);
  return out;
}

bool FirefighterEstimator::add_unknown_motion(TimestampNs from, TimestampNs until) {
  if (until <= from || until <= last_end_ || !localizer_.started()) return false;
  localizer_.lost_motion(0.5 * config_.max_speed_mps * 1e-9 * static_cast<double>(until - std::max(from, last_end_)));
  last_end_ = until;
  return true;
}

Outcome FirefighterEstimator::process(const SensorSample&) {
  return responder::reject(RejectReason::kWrongRole, id_, "a firefighter takes odometry only");
}

responder::ResponderPosition FirefighterEstimator::position_at(TimestampNs stamp, const firefighter::MapEstimate& e) const {
  const double rot = config_.rotation_rad();
  const Eigen::Rotation2Dd R(rot);
  responder::ResponderPosition p;
  p.responder_id = id_;
  p.stamp = stamp;
  const auto& plan = config_.building->plan();
  const firefighter::Vec2 xy = config_.to_incident(e.position);
  p.position.position = Vec3(xy.x(), xy.y(), plan.floors[e.floor].elevation_m);
  p.position.covariance.setZero();
  p.position.covariance.topLeftCorner<2, 2>() = R.toRotationMatrix() * e.covariance * R.toRotationMatrix().transpose();
  p.position.covariance(2, 2) = 0.25;  // the floor's height: a boot within half a metre of it
  p.heading_rad = wrap_angle(rot + e.frame_heading + yaw_);
  p.floor = static_cast<std::int32_t>(e.floor);
  p.source = responder::PositionSource::kMapAided;
  p.converged = e.converged;
  p.map_error_suspected = e.map_error_suspected;
  p.confirmed = e.confirmed;
  p.ambiguous = e.ambiguous;
  return p;
}

std::optional<responder::ResponderCandidates> FirefighterEstimator::candidates_at(TimestampNs stamp,
                                                                                  const firefighter::MapEstimate& e) {
  if (!e.ambiguous && !was_ambiguous_) return std::nullopt;
  was_ambiguous_ = e.ambiguous;
  responder::ResponderCandidates out;
  out.responder_id = id_;
  out.stamp = stamp;
  if (!e.ambiguous) return out;
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(config_.rotation_rad()).toRotationMatrix();
  const auto& plan = config_.building->plan();
  for (const firefighter::Place& place : e.candidates) {
    responder::PositionCandidate c;
    const firefighter::Vec2 xy = config_.to_incident(place.position);
    c.position.position = Vec3(xy.x(), xy.y(), plan.floors[place.floor].elevation_m);
    c.position.covariance.setZero();
    c.position.covariance.topLeftCorner<2, 2>() = R * place.covariance * R.transpose();
    c.position.covariance(2, 2) = 0.25;  // as the position's: a boot within half a metre of the floor
    c.floor = static_cast<std::int32_t>(place.floor);
    c.weight = place.weight;
    out.candidates.push_back(c);
  }
  return out;
}

}  // namespace sarloc::estimator
