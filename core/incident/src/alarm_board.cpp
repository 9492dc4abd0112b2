#include "sarloc/core/incident/alarm_board.hpp"

#include <algorithm>
#include <tuple>
#include <vector>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::incident {

bool same_alarm(const IncidentAlarm& a, const IncidentAlarm& b) {
  const responder::ResponderAlarm& x = a.alarm;
  const responder::ResponderAlarm& y = b.alarm;
  return a.alarm_id == b.alarm_id && a.acknowledged == b.acknowledged && a.acknowledged_by == b.acknowledged_by &&
         a.acknowledged_at == b.acknowledged_at && x.responder_id == y.responder_id && x.team_id == y.team_id &&
         x.kind == y.kind && x.raised_at == y.raised_at && x.cleared_at == y.cleared_at && x.active == y.active &&
         x.position_known == y.position_known && x.floor == y.floor &&
         x.last_position.position == y.last_position.position &&
         x.last_position.covariance == y.last_position.covariance;
}

IncidentAlarm* AlarmBoard::find(const std::string& responder_id, responder::AlarmKind kind) {
  const auto it = alarm_of_.find({responder_id, kind});
  if (it == alarm_of_.end()) return nullptr;
  const auto alarm = alarms_.find(it->second);
  return alarm == alarms_.end() ? nullptr : &alarm->second;
}

void AlarmBoard::raise(const responder::ResponderAlarm& alarm, TimestampNs now) {
  if (IncidentAlarm* current = find(alarm.responder_id, alarm.kind)) {
    if (!current->acknowledged) {
      current->alarm = alarm;  // nobody answered it yet: the same alarm, now this episode
      current->reopened_at = now;
      return;
    }
    remove(current->alarm_id);  // answered, and its episode is over
  }
  IncidentAlarm a;
  a.alarm_id = next_id_++;
  a.alarm = alarm;
  alarms_[a.alarm_id] = a;
  alarm_of_[{alarm.responder_id, alarm.kind}] = a.alarm_id;
}

void AlarmBoard::remove(std::uint32_t alarm_id) {
  const auto it = alarms_.find(alarm_id);
  if (it == alarms_.end()) return;
  const auto index = alarm_of_.find({it->second.alarm.responder_id, it->second.alarm.kind});
  if (index != alarm_of_.end() && index->second == alarm_id) alarm_of_.erase(index);
  alarms_.erase(it);
  removed_.push_back(alarm_id);
}

void AlarmBoard::remove_if_done(std::uint32_t alarm_id) {
  const auto it = alarms_.find(alarm_id);
  if (it == alarms_.end() || it->second.alarm.active || !it->second.acknowledged) return;
  remove(alarm_id);
}

void AlarmBoard::on_device_alarm(const responder::ResponderAlarm& alarm, TimestampNs now) {
  if (alarm.responder_id.empty()) throw InputError("responder_alarm.responder_id = \"\": must not be empty");
  if (!alarm.active && alarm.cleared_at < alarm.raised_at) {
    throw InputError("responder_alarm of '" + alarm.responder_id + "': cleared_at " + std::to_string(alarm.cleared_at) +
                     " before raised_at " + std::to_string(alarm.raised_at));
  }
  IncidentAlarm* current = find(alarm.responder_id, alarm.kind);
  // A newer episode, or a clear whose raise never arrived: it happened, so it shows.
  if (current == nullptr || alarm.raised_at > current->alarm.raised_at) {
    raise(alarm, now);
    return;
  }
  if (alarm.raised_at < current->alarm.raised_at) {
    // An earlier episode's sample, late; but a raise is never hidden (a device's clock went back).
    if (alarm.active && !current->alarm.active) raise(alarm, now);
    return;
  }
  if (!current->alarm.active) return;                      // cleared already: a raise arriving late changes nothing
  const std::uint32_t id = current->alarm_id;
  current->alarm = alarm;
  remove_if_done(id);
}

void AlarmBoard::set_condition(const std::string& responder_id, const std::string& team_id, responder::AlarmKind kind,
                               bool active, TimestampNs now, const std::optional<GaussianPosition>& position,
                               std::int32_t floor) {
  if (responder_id.empty()) throw InputError("alarm condition: responder_id must not be empty");
  IncidentAlarm* current = find(responder_id, kind);
  const bool raised = current != nullptr && current->alarm.active;
  if (active && !raised) {
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
    raise(alarm, now);
  } else if (!active && raised) {
    current->alarm.active = false;
    current->alarm.cleared_at = now;
    remove_if_done(current->alarm_id);
  }
}

AckResult AlarmBoard::acknowledge(std::uint32_t alarm_id, const std::string& operator_id, TimestampNs stamp,
                                  TimestampNs now) {
  const auto it = alarms_.find(alarm_id);
  if (it == alarms_.end()) return AckResult::kUnknown;
  if (it->second.acknowledged) return AckResult::kAlready;
  // The operator answered the episode shown before this one reopened the alarm.
  if (stamp > 0 && stamp < it->second.reopened_at) return AckResult::kEarlierEpisode;
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
  alarm_of_.clear();
  const auto newer = [](const IncidentAlarm& a, const IncidentAlarm& b) {
    return std::tie(a.alarm.raised_at, a.alarm_id) > std::tie(b.alarm.raised_at, b.alarm_id);
  };
  for (const IncidentAlarm& a : alarms) {
    alarms_[a.alarm_id] = a;
    next_id_ = std::max(next_id_, a.alarm_id + 1);
    auto [it, fresh] = alarm_of_.try_emplace({a.alarm.responder_id, a.alarm.kind}, a.alarm_id);
    if (!fresh && newer(a, alarms_.at(it->second))) it->second = a.alarm_id;
  }
  // Two of one (responder, kind) come only from a board of before one alarm per condition: the
  // newest episode goes on; an older one ended when the newer began, and goes if acknowledged.
  std::vector<std::uint32_t> answered;
  for (auto& [id, a] : alarms_) {
    const IncidentAlarm& newest = alarms_.at(alarm_of_.at({a.alarm.responder_id, a.alarm.kind}));
    if (id == newest.alarm_id) continue;
    if (a.alarm.active) {
      a.alarm.active = false;
      a.alarm.cleared_at = std::max(a.alarm.raised_at, newest.alarm.raised_at);
    }
    if (a.acknowledged) answered.push_back(id);
  }
  for (const std::uint32_t id : answered) remove(id);
}

std::size_t AlarmBoard::active_count() const {
  return static_cast<std::size_t>(
      std::count_if(alarms_.begin(), alarms_.end(), [](const auto& kv) { return kv.second.alarm.active; }));
}

}  // namespace sarloc::incident
