#include "sarloc/core/mission/firefighter_summary.hpp"

#include <algorithm>
#include <cmath>

#include "sarloc/core/common/gaussian.hpp"

namespace sarloc::mission {

FirefighterScore::FirefighterScore(std::string responder_id, std::string team, double enter_at_s) {
  summary_.responder_id = std::move(responder_id);
  summary_.team = std::move(team);
  summary_.enter_at_s = enter_at_s;
}

namespace {

void note_floor(std::vector<std::int32_t>& floors, std::int32_t floor) {
  if (std::find(floors.begin(), floors.end(), floor) == floors.end()) floors.push_back(floor);
}

}  // namespace

void FirefighterScore::on_fix_without_truth(double t, const responder::ResponderPosition& fix) {
  ++summary_.fixes;
  map_error_ += fix.map_error_suspected ? 1 : 0;
  confirmed_ += fix.confirmed ? 1 : 0;
  note_floor(summary_.floors_reported, fix.floor);
  if (!summary_.converged_at_s && fix.converged && t >= summary_.enter_at_s) {
    summary_.converged_at_s = t;
    summary_.time_to_converge_s = t - summary_.enter_at_s;
  }
}

void FirefighterScore::on_fix(double t, const responder::ResponderPosition& fix, const firefighter::Vec2& truth,
                              std::int32_t truth_floor) {
  on_fix_without_truth(t, fix);
  note_floor(summary_.floors_visited, truth_floor);
  const Eigen::Vector2d err = fix.position.position.head<2>() - truth;
  if (fix.confirmed) {
    const Eigen::Matrix2d P = fix.position.covariance.topLeftCorner<2, 2>() + 1e-9 * Eigen::Matrix2d::Identity();
    if (err.dot(P.ldlt().solve(err)) > kChi2_2_99) ++summary_.confirmed_outside_99;
  }
  if (summary_.converged_at_s) {
    sum_sq_ += err.squaredNorm();
    ++after_;
    if (fix.floor != truth_floor) ++summary_.wrong_floor;
  }
}

void FirefighterScore::on_own_position(const responder::ResponderPosition& own, const firefighter::Vec2& truth) {
  ++summary_.own_positions;
  const Eigen::Vector2d err = own.position.position.head<2>() - truth;
  summary_.own_max_error_m = std::max(summary_.own_max_error_m.value_or(0.0), err.norm());
  const Eigen::Matrix2d P = own.position.covariance.topLeftCorner<2, 2>() + 1e-9 * Eigen::Matrix2d::Identity();
  if (err.dot(P.ldlt().solve(err)) > kChi2_2_99) ++summary_.own_outside_99;
}

void FirefighterScore::on_alarm(const responder::ResponderAlarm& alarm, TimestampNs epoch) {
  const auto seconds = [&](TimestampNs stamp) { return 1e-9 * static_cast<double>(stamp - epoch); };
  for (auto& record : summary_.alarms) {
    if (record.kind == responder::to_string(alarm.kind) && std::abs(record.raised_s - seconds(alarm.raised_at)) < 1e-6) {
      if (!alarm.active) record.cleared_s = seconds(alarm.cleared_at);
      return;
    }
  }
  FirefighterAlarmRecord record;
  record.kind = responder::to_string(alarm.kind);
  record.raised_s = seconds(alarm.raised_at);
  if (!alarm.active) record.cleared_s = seconds(alarm.cleared_at);
  summary_.alarms.push_back(record);
}

FirefighterDeviceSummary FirefighterScore::summary(double distance_walked_m,
                                                   const std::optional<std::pair<double, double>>& stop,
                                                   double motionless_after_s) const {
  FirefighterDeviceSummary s = summary_;
  s.distance_walked_m = distance_walked_m;
  if (after_ > 0) s.rmse_after_convergence_m = std::sqrt(sum_sq_ / static_cast<double>(after_));
  if (s.fixes > 0) {
    s.map_error_share = static_cast<double>(map_error_) / static_cast<double>(s.fixes);
    s.confirmed_share = static_cast<double>(confirmed_) / static_cast<double>(s.fixes);
  }
  if (stop) {
    for (auto& a : s.alarms) {
      if (a.kind != responder::to_string(responder::AlarmKind::kMotionless)) continue;
      const double event = stop->first + motionless_after_s;
      if (a.raised_s < stop->first || a.raised_s > stop->second + 1.0) continue;  // not the scripted stop's
      a.true_event_s = event;
      a.delay_s = a.raised_s - event;
      if (a.cleared_s) a.clear_delay_s = *a.cleared_s - stop->second;
    }
  }
  return s;
}

}  // namespace sarloc::mission
