#include "sarloc/core/incident/team_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::incident {
namespace {

// A dead-reckoned position does not replace a map-aided one younger than this (device stamps).
constexpr TimestampNs kMapAidedPreferredNs = 3'000'000'000;

}  // namespace

void TeamTrackerConfig::validate() const {
  require(std::isfinite(stale_after_s) && stale_after_s > 0.0, "team_tracker.stale_after_s", stale_after_s,
          "must be > 0");
  require(std::isfinite(lost_after_s) && lost_after_s > stale_after_s, "team_tracker.lost_after_s", lost_after_s,
          "must be > stale_after_s");
}

const char* to_string(LinkState link) {
  switch (link) {
    case LinkState::kAlive: return "alive";
    case LinkState::kStale: return "stale";
    case LinkState::kLost: return "lost";
    case LinkState::kSignedOff: return "signed_off";
  }
  return "lost";
}

const char* display_name(LinkState link) {
  switch (link) {
    case LinkState::kAlive:
      return "alive";
    case LinkState::kStale:
      return "stale";
    case LinkState::kLost:
      return "LOST";
    case LinkState::kSignedOff:
      return "signed off";
  }
  return "LOST";
}

AccountabilityState accountability_of(LinkState link) {
  switch (link) {
    case LinkState::kAlive: return AccountabilityState::kAccounted;
    case LinkState::kStale: return AccountabilityState::kPending;
    case LinkState::kLost: return AccountabilityState::kMissing;
    case LinkState::kSignedOff: return AccountabilityState::kAccounted;
  }
  return AccountabilityState::kMissing;
}

TeamTracker::TeamTracker(TeamTrackerConfig config) : config_(config) { config_.validate(); }

void TeamTracker::on_position(const ResponderPosition& position, TimestampNs now) {
  if (position.responder_id.empty())
    throw InputError("responder_position.responder_id = \"\": must not be empty");
  latest_now_ = std::max(latest_now_, now);
  Member& m = members_[position.responder_id];
  if (position.source == responder::PositionSource::kMapAided) {
    // A copy of the daemon's last position of a silent firefighter, or one overtaken on the way.
    if (m.newest_map_aided != 0 && position.stamp <= m.newest_map_aided) return;
    m.newest_map_aided = position.stamp;
  }
  // The daemon's map-aided positions do not know the team: they never move a member out of
  // the team its own device reports.
  if (!position.team_id.empty() || m.team_id.empty()) m.team_id = position.team_id;
  // A firefighter's device dead reckons while the daemon is silent; while the daemon's
  // map-aided positions still come, they are the better ones.
  const bool map_aided_fresh = m.has_position && m.last_position.source == responder::PositionSource::kMapAided &&
                               position.source == responder::PositionSource::kDeadReckoning &&
                               position.stamp - m.last_position.stamp < kMapAidedPreferredNs;
  // A sign-off stands until a newer position of the device's own: one reader of two may deliver
  // an older one late, and the daemon's map-aided positions answer odometry that the device sent
  // before it signed off (they came after the sign-off in 1 of 4 devices of a busy relay).
  if (position.source != responder::PositionSource::kMapAided &&
      (!m.has_position || position.stamp > m.last_position.stamp)) {
    m.signed_off = false;
  }
  if ((!m.has_position || position.stamp >= m.last_position.stamp) && !map_aided_fresh) {
    m.last_position = position;
    m.has_position = true;
  }
  m.last_heard = std::max(m.last_heard, now);
  m.liveliness_lost = false;  // seen again
}

void TeamTracker::on_link(const std::string& responder_id, bool alive, TimestampNs now) {
  if (responder_id.empty()) throw InputError("link.responder_id = \"\": must not be empty");
  latest_now_ = std::max(latest_now_, now);
  Member& m = members_[responder_id];  // unknown: team "" until its first position
  if (alive) {
    m.liveliness_lost = false;
    m.signed_off = false;  // a device started again
    m.last_heard = std::max(m.last_heard, now);
  } else if (!m.signed_off) {
    m.liveliness_lost = true;
  }
}

void TeamTracker::on_signed_off(const std::string& responder_id, TimestampNs now) {
  if (responder_id.empty()) throw InputError("sign_off.responder_id = \"\": must not be empty");
  latest_now_ = std::max(latest_now_, now);
  Member& m = members_[responder_id];
  m.signed_off = true;
  m.liveliness_lost = false;
  m.last_heard = std::max(m.last_heard, now);
}

void TeamTracker::adopt(const std::vector<TeamStatus>& teams) {
  for (const TeamStatus& t : teams)
    for (const MemberStatus& s : t.members)
      if (s.responder_id.empty()) throw InputError("team_status[" + t.team_id + "].members.responder_id = \"\": must not be empty");
  for (const TeamStatus& t : teams) {
    for (const MemberStatus& s : t.members) {
      const bool known = members_.count(s.responder_id) != 0;
      Member& m = members_[s.responder_id];
      if (!known) {
        m.team_id = t.team_id;
        m.liveliness_lost = s.link == LinkState::kLost;
        m.signed_off = s.link == LinkState::kSignedOff;
      }
      if (!m.has_position && s.has_position) {
        if (m.team_id.empty()) m.team_id = t.team_id;
        m.last_position.responder_id = s.responder_id;
        m.last_position.team_id = t.team_id;
        m.last_position.stamp = s.position_stamp;
        m.last_position.position = s.last_position;
        m.last_position.floor = s.floor;
        m.last_position.source = s.source;
        m.last_position.converged = s.converged;
        m.last_position.map_error_suspected = s.map_error_suspected;
        m.last_position.confirmed = s.confirmed;
        m.last_position.ambiguous = s.ambiguous;
        m.has_position = true;
      }
      m.last_heard = std::max(m.last_heard, s.last_seen);
    }
  }
}

LinkState TeamTracker::link_of(const Member& m, TimestampNs now) const {
  if (m.signed_off) return LinkState::kSignedOff;
  if (m.liveliness_lost) return LinkState::kLost;
  const double silent_s = static_cast<double>(now - m.last_heard) * 1e-9;
  if (silent_s > config_.lost_after_s) return LinkState::kLost;
  if (silent_s > config_.stale_after_s) return LinkState::kStale;
  return LinkState::kAlive;
}

std::vector<TeamStatus> TeamTracker::evaluate(TimestampNs now) const {
  std::map<std::string, TeamStatus> teams;
  for (const auto& [id, m] : members_) {  // by responder id: members come out sorted
    TeamStatus& t = teams[m.team_id];
    t.team_id = m.team_id;
    t.stamp = now;
    MemberStatus s;
    s.responder_id = id;
    if (m.has_position) {
      s.last_position = m.last_position.position;
      s.position_stamp = m.last_position.stamp;
      s.floor = m.last_position.floor;
      s.source = m.last_position.source;
      s.converged = m.last_position.converged;
      s.map_error_suspected = m.last_position.map_error_suspected;
      s.confirmed = m.last_position.confirmed;
      s.ambiguous = m.last_position.ambiguous;
    }
    s.has_position = m.has_position;
    s.last_seen = m.last_heard;
    s.link = link_of(m, now);
    s.accountability = accountability_of(s.link);
    t.members.push_back(s);
  }
  std::vector<TeamStatus> out;
  out.reserve(teams.size());
  for (auto& [id, t] : teams) out.push_back(std::move(t));
  return out;
}

bool TeamTracker::signed_off(const std::string& responder_id) const {
  const auto it = members_.find(responder_id);
  return it != members_.end() && it->second.signed_off;
}

std::size_t TeamTracker::link_lost_count(TimestampNs now) const {
  return static_cast<std::size_t>(std::count_if(members_.begin(), members_.end(), [&](const auto& kv) {
    return link_of(kv.second, now) == LinkState::kLost;
  }));
}

}  // namespace sarloc::incident
