#include "sarloc/core/incident/alarm_board.hpp"

#include <algorithm>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::incident {

IncidentAlarm& AlarmBoard::open(const responder::ResponderAlarm& alarm) {
  IncidentAlarm a;
  a.alarm_id = next_id_++;
  a.alarm = alarm;
  return alarms_[a.alarm_id] = a;
}

void AlarmBoard::remove_if_done(std::uint32_t alarm_id) {
  const auto it = alarms_.find(alarm_id);
  if (it == alarms_.end() || it->second.alarm.active || !it->second.acknowledged) return;
  alarms_.erase(it);
  removed_.push_back(alarm_id);
}

void AlarmBoard::on_device_alarm(const responder::ResponderAlarm& alarm, TimestampNs /*now*/) {
  if (alarm.responder_id.empty()) throw InputError("responder_alarm.responder_id = \"\": must not be empty");
  if (!alarm.active && alarm.cleared_at < alarm.raised_at) {
    throw InputError("responder_alarm of '" + alarm.responder_id + "': cleared_at " + std::to_string(alarm.cleared_at) +
                     " before raised_at " + std::to_string(alarm.raised_at));
  }
  for (auto& [id, a] : alarms_) {
    if (a.alarm.responder_id != alarm.responder_id || a.alarm.kind != alarm.kind || a.alarm.raised_at != alarm.raised_at) {
      continue;
    }
    if (!a.alarm.active) return;  // cleared already: a raise arriving late changes nothing
    const bool acknowledged = a.acknowledged;
    a.alarm = alarm;
    a.acknowledged = acknowledged;
    remove_if_done(id);
    return;
  }
  open(alarm);  // a clear never seen raised still shows: it happened
}

void AlarmBoard::set_condition(const std::string& responder_id, const std::string& team_id, responder::AlarmKind kind,
                               bool active, TimestampNs now, const std::optional<GaussianPosition>& position,
                               std::int32_t floor) {
  if (responder_id.empty()) throw InputError("alarm condition: responder_id must not be empty");
  IncidentAlarm* current = nullptr;
  for (auto& [id, a] : alarms_) {
    if (a.alarm.responder_id == responder_id && a.alarm.kind == kind && a.alarm.active) current = &a;
  }
  if (active && current == nullptr) {
    responder::ResponderAlarm alarm;
    alarm.responder_id = responder_id;
    alarm.team_id = team_id;
    alarm.kind = kind;
    alarm.raised_at = now;
    alarm.active = true;
    if (position) {
      alarm.last_position = *position;
      alarm.position_known = true;
      alarm.floor = floor;
    }
    open(alarm);
  } else if (!active && current != nullptr) {
    current->alarm.active = false;
    current->alarm.cleared_at = now;
    remove_if_done(current->alarm_id);
  }
}

AckResult AlarmBoard::acknowledge(std::uint32_t alarm_id, const std::string& operator_id, TimestampNs now) {
  const auto it = alarms_.find(alarm_id);
  if (it == alarms_.end()) return AckResult::kUnknown;
  if (it->second.acknowledged) return AckResult::kAlready;
  it->second.acknowledged = true;
  it->second.acknowledged_by = operator_id;
  it->second.acknowledged_at = now;
  remove_if_done(alarm_id);
  return AckResult::kAcknowledged;
}

std::vector<IncidentAlarm> AlarmBoard::alarms() const {
  std::vector<IncidentAlarm> out;
  out.reserve(alarms_.size());
  for (const auto& [id, a] : alarms_) out.push_back(a);
  return out;
}

std::vector<std::uint32_t> AlarmBoard::take_removed() {
  std::vector<std::uint32_t> out;
  out.swap(removed_);
  return out;
}

void AlarmBoard::adopt(const std::vector<IncidentAlarm>& alarms) {
  alarms_.clear();
  for (const IncidentAlarm& a : alarms) {
    alarms_[a.alarm_id] = a;
    next_id_ = std::max(next_id_, a.alarm_id + 1);
  }
}

std::size_t AlarmBoard::active_count() const {
  return static_cast<std::size_t>(
      std::count_if(alarms_.begin(), alarms_.end(), [](const auto& kv) { return kv.second.alarm.active; }));
}

}  // namespace sarloc::incident
