#include "sarloc/core/incident/picture_events.hpp"

#include "sarloc/core/common/gaussian.hpp"
#include "sarloc/core/common/number_text.hpp"
#include "sarloc/core/responder/alarm.hpp"

namespace sarloc::incident {

namespace {

std::string xy(const GaussianPosition& p) {
  return "(" + one_decimal(p.position.x()) + ", " + one_decimal(p.position.y()) + ")";
}

std::string at(const GaussianPosition& p) { return " at " + xy(p); }

// The sample's time for a step it gives no time of its own (0 where the writer left it unset).
TimestampNs stamp_or(TimestampNs stamp, TimestampNs fallback) { return stamp != 0 ? stamp : fallback; }

}  // namespace

const char* display_name(AccountabilityState state) {
  switch (state) {
    case AccountabilityState::kAccounted:
      return "accounted for";
    case AccountabilityState::kPending:
      return "check due (PAR)";
    case AccountabilityState::kMissing:
      return "MISSING at the check";
  }
  return "MISSING at the check";
}

std::vector<PictureEvent> PictureEvents::on_victim(const FusedVictim& v) {
  std::vector<PictureEvent> out;
  const std::string name = "victim " + std::to_string(v.victim_id);
  auto [it, first] = victims_.try_emplace(v.victim_id);
  VictimSeen& seen = it->second;
  if (first)
    out.push_back({stamp_or(v.first_seen, v.last_update), "victim", name + " in the picture" + at(v.position)});
  // The state decides, the sample's times date it. A withdrawn confirmation makes the next one
  // news again; a victim FOUND with no LOCATED time skips that step.
  const bool located = v.state != VictimState::kUnconfirmed, was_located = seen.state != VictimState::kUnconfirmed;
  if (located && !was_located && (v.state == VictimState::kLocated || v.located_at != 0)) {
    out.push_back({stamp_or(v.located_at, v.last_update), "victim", name + " LOCATED" + at(v.position)});
  }
  if (is_found(v.state) && !is_found(seen.state)) {
    out.push_back(
        {stamp_or(v.found_at, v.last_update), "victim",
         name + " FOUND" + at(v.position) + ", 95 % radius " + one_decimal(radius95_2d(v.position.covariance)) + " m"});
  }
  if (v.state == VictimState::kRecovered && seen.state != VictimState::kRecovered) {
    out.push_back({v.last_update, "victim", name + " recovered (dug out)"});
  }
  // A confirmation withdrawn (a FOUND whose witness no longer agrees, a LOCATED unconfirmed again):
  // VictimState is declared in the order of confirmation.
  if (!first && static_cast<int>(v.state) < static_cast<int>(seen.state)) {
    out.push_back(
        {v.last_update, "victim", name + " back to " + to_string(v.state) + ": its confirmation was withdrawn"});
  }
  if (v.evidence_conflict != seen.conflict) {
    out.push_back({v.last_update, "victim",
                   v.evidence_conflict ? name + ": its sources DISAGREE (evidence conflict): do not dig on it alone"
                                       : name + ": its sources agree again"});
  }
  seen.state = v.state;
  seen.conflict = v.evidence_conflict;
  return out;
}

std::vector<PictureEvent> PictureEvents::on_victim_gone(std::uint32_t victim_id, TimestampNs stamp) {
  if (victims_.erase(victim_id) == 0) return {};
  return {{stamp, "victim", "victim " + std::to_string(victim_id) + " merged into another (same transmitter)"}};
}

std::vector<PictureEvent> PictureEvents::on_team(const TeamStatus& t) {
  std::vector<PictureEvent> out;
  for (const auto& m : t.members) {
    const std::string who = m.responder_id + " (" + t.team_id + "): ";
    auto [it, first] = members_.try_emplace(m.responder_id, MemberSeen{m.link, m.accountability});
    MemberSeen& seen = it->second;
    if (first) continue;
    if (m.link != seen.link) {
      const std::string change = m.link == LinkState::kSignedOff
                                     ? std::string("signed off (the device stopped in order)")
                                 : m.link == LinkState::kAlive ? std::string("link alive again (regained)")
                                                               : std::string("link ") + display_name(m.link);
      out.push_back({t.stamp, "link", who + change});
    }
    if (m.accountability != seen.accountability) {
      out.push_back({t.stamp, "accountability", who + display_name(m.accountability)});
    }
    seen = {m.link, m.accountability};
  }
  return out;
}

std::vector<PictureEvent> PictureEvents::on_alarm(const IncidentAlarm& a) {
  std::vector<PictureEvent> out;
  const std::string name = std::string(responder::display_name(a.alarm.kind)) + " alarm " + std::to_string(a.alarm_id) +
                           " for " + a.alarm.responder_id;
  auto [it, first] = alarms_.try_emplace(a.alarm_id);
  AlarmSeen& seen = it->second;
  if (first) {
    out.push_back({a.alarm.raised_at, "alarm", name + " RAISED"});
  } else if (a.alarm.raised_at != seen.raised_at) {
    out.push_back({a.alarm.raised_at, "alarm", name + " RAISED again"});
    seen.active = true;  // so this episode's clear, if it came with it, is told too
  }
  if (a.acknowledged && !seen.acknowledged) {
    out.push_back(
        {stamp_or(a.acknowledged_at, a.alarm.raised_at), "alarm", name + " acknowledged by " + a.acknowledged_by});
  }
  if (!a.alarm.active && seen.active)
    out.push_back({stamp_or(a.alarm.cleared_at, a.alarm.raised_at), "alarm", name + " cleared"});
  seen = {a.acknowledged, a.alarm.active, a.alarm.raised_at};
  return out;
}

std::vector<PictureEvent> PictureEvents::on_alarm_gone(std::uint32_t alarm_id, TimestampNs stamp) {
  if (alarms_.erase(alarm_id) == 0) return {};
  return {{stamp, "alarm", "alarm " + std::to_string(alarm_id) + " closed"}};
}

std::vector<PictureEvent> PictureEvents::on_position(const responder::ResponderPosition& p) {
  if (p.source != responder::PositionSource::kMapAided) return {};
  auto [it, first] = map_aided_.try_emplace(p.responder_id);
  MapAidedSeen& seen = it->second;
  if (!first && p.stamp <= seen.stamp) return {};
  seen.stamp = p.stamp;
  if (p.map_error_suspected == seen.suspected) return {};
  seen.suspected = p.map_error_suspected;
  return {
      {p.stamp, "map error",
       p.responder_id + (p.map_error_suspected ? ": the map-aided filter suspects the floor plan near " + xy(p.position)
                                               : ": map error no longer suspected")}};
}

}  // namespace sarloc::incident
