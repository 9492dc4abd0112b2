#include "sarloc/core/incident/incident_command.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <utility>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/identifier.hpp"
#include "sarloc/core/common/time_units.hpp"
#include "sarloc/core/common/validate.hpp"
#include "sarloc/core/incident/geodetic_frame.hpp"
#include "sarloc/core/incident/source_estimate.hpp"

namespace sarloc::incident {

void IncidentCommandConfig::validate() const {
  fusion.validate();
  teams.validate();
  standby.validate();
  require(!incident_id.empty() && incident_id.size() <= 64, "incident.id", incident_id, "must be 1-64 characters");
  require(position_max_age_s > 0.0 && position_max_age_s <= 600.0, "command.position_max_age_s", position_max_age_s,
          "must be in (0, 600]");
  require(fix_interpolation_max_gap_s >= 0.0 && fix_interpolation_max_gap_s <= 60.0,
          "command.fix_interpolation_max_gap_s", fix_interpolation_max_gap_s, "must be in [0, 60]");
  require(fix_wait_s > 0.0 && fix_wait_s <= 600.0, "command.fix_wait_s", fix_wait_s, "must be in (0, 600]");
  require(antenna_height_m >= 0.0 && antenna_height_m <= 5.0, "command.antenna_height_m", antenna_height_m,
          "must be in [0, 5]");
  require(antenna_height_sigma_m > 0.0 && antenna_height_sigma_m <= 5.0, "command.antenna_height_sigma_m",
          antenna_height_sigma_m, "must be in (0, 5]");
  triage.validate();
  (void)GeodeticFrame(origin);  // the one check of a WGS-84 origin (ConfigError naming incident.<field>)
  if (deposit) {
    search_plan.validate();
    check_deposit_fits(*deposit, search_plan, "incident.deposit");
  }
}

void check_deposit_fits(const Deposit& deposit, const SearchPlanConfig& search_plan, const std::string& key) {
  constexpr std::size_t kMax = IncidentCommandConfig::kDepositVerticesMax;
  require(deposit.vertices().size() <= kMax, key, deposit.vertices().size(),
          "at most " + std::to_string(kMax) + " vertices");
  // The fewest strips it takes (entered from anywhere: the count does not depend on it).
  const auto strips = plan_strips(deposit, search_plan.strips, deposit.vertices().front()).size();
  require(strips <= kSearchStripsMax, key, strips,
          "strips at search.strip_width_m; at most " + std::to_string(kSearchStripsMax) +
              ": a smaller deposit or wider strips");
}

IncidentCommand::IncidentCommand(IncidentCommandConfig config, TimestampNs start_wall_ns)
    : config_((config.validate(), std::move(config))),
      fusion_(config_.fusion),
      tracker_(config_.teams),
      arbiter_(config_.standby, start_wall_ns) {
  frame_.incident_id = config_.incident_id;
  frame_.origin = config_.origin;
  frame_.name = config_.incident_name;
  if (config_.deposit) {
    planner_.emplace(*config_.deposit, config_.search_plan);
    pursuits_.emplace(config_.search_plan.pursuit_timeout_s);
  }
}

void IncidentCommand::say(IncidentEvent::Kind kind, std::string text) {
  IncidentEvent event;
  event.kind = kind;
  event.text = std::move(text);
  events_.push_back(std::move(event));
}

void IncidentCommand::reject(std::string subject, std::string reason, std::string text) {
  IncidentEvent event;
  event.kind = IncidentEvent::Kind::kRejected;
  event.subject = std::move(subject);
  event.reason = std::move(reason);
  event.text = std::move(text);
  events_.push_back(std::move(event));
}

void IncidentCommand::on_estimate(responder::VictimEstimate estimate, std::string writer, bool from_device,
                                  TimestampNs now) {
  pending_estimates_.push_back({std::move(estimate), std::move(writer), from_device, now});
}

void IncidentCommand::on_position(const responder::ResponderPosition& position, const std::string& writer,
                                  TimestampNs now) {
  if (!position.position.position.allFinite() || !position.position.covariance.allFinite()) {
    reject(position.responder_id, "invalid_value", "responder_position.position: non-finite value");
    return;
  }
  // A device's own writer stands for its link; the core daemon's map-aided positions come from
  // one writer for many responders, whose liveliness says nothing of them.
  if (position.source != responder::PositionSource::kMapAided) link_writers_.try_emplace(writer, position.responder_id);
  tracker_.on_position(position, now);
  // GNSS heights become the antenna's above the snow; indoor positions keep theirs.
  fixes_[position.responder_id].add(
      position.stamp, reporter_fix_of(position, config_.antenna_height_m, config_.antenna_height_sigma_m));
  // An avalanche rescuer's walk searches the deposit (firefighters' positions are indoors).
  if (planner_ && position.source == responder::PositionSource::kGnss)
    planner_->on_position(position.responder_id, position.position.position.head<2>());
}

void IncidentCommand::on_writer_liveliness(const std::string& writer, bool alive, TimestampNs now) {
  const auto it = link_writers_.find(writer);
  if (it == link_writers_.end()) return;
  tracker_.on_link(it->second, alive, now);
  if (!alive) say(IncidentEvent::Kind::kWarning, "link to responder '" + it->second + "' lost");
}

void IncidentCommand::on_writer_disposed(const std::string& writer, TimestampNs now) {
  // A device that stops in order disposes its own position instance before its writer goes:
  // signed off, not lost.
  const auto it = link_writers_.find(writer);
  if (it == link_writers_.end()) return;
  if (!tracker_.signed_off(it->second)) say(IncidentEvent::Kind::kInfo, "responder '" + it->second + "' signed off");
  tracker_.on_signed_off(it->second, now);
}

void IncidentCommand::on_device_alarm(const responder::ResponderAlarm& alarm, TimestampNs now) {
  try {
    alarm_board_.on_device_alarm(alarm, now);
  } catch (const InputError& error) {
    reject(alarm.responder_id, "invalid_value", std::string("responder alarm: ") + error.what());
    return;
  }
  if (alarm.active) {
    say(IncidentEvent::Kind::kWarning, std::string(responder::to_string(alarm.kind)) + " alarm from '" +
                                           alarm.responder_id + "' (team '" + alarm.team_id + "')");
  } else {
    say(IncidentEvent::Kind::kInfo,
        std::string(responder::to_string(alarm.kind)) + " alarm of '" + alarm.responder_id + "' cleared");
  }
}

void IncidentCommand::on_acknowledgement(std::uint32_t alarm_id, const std::string& operator_id, TimestampNs stamp,
                                         TimestampNs now) {
  if (arbiter_.role() != CommandRole::kActive) return;  // the active one's picture carries it
  if (!is_identifier(operator_id)) {
    // It would travel on as the alarm's acknowledged_by, which every reader refuses.
    reject(printable_excerpt(operator_id), "invalid_value", "alarm acknowledgement: operator_id is not an identifier");
    return;
  }
  const auto result = alarm_board_.acknowledge(alarm_id, operator_id, stamp, now);
  if (result == AckResult::kUnknown) {
    reject(operator_id, "unknown_alarm", "acknowledgement of alarm " + std::to_string(alarm_id) + ": no such alarm");
  } else if (result == AckResult::kEarlierEpisode) {
    say(IncidentEvent::Kind::kWarning, "alarm " + std::to_string(alarm_id) + " went off again after '" + operator_id +
                                           "' acknowledged it: still to be acknowledged");
  } else if (result == AckResult::kAcknowledged) {
    say(IncidentEvent::Kind::kInfo, "alarm " + std::to_string(alarm_id) + " acknowledged by '" + operator_id + "'");
  }
}

void IncidentCommand::on_recovery(std::uint32_t victim_id, const std::string& reported_by, TimestampNs stamp,
                                  TimestampNs now) {
  if (!is_identifier(reported_by)) {
    reject(printable_excerpt(reported_by), "invalid_value", "victim recovery: reported_by is not an identifier");
    return;
  }
  // Both instances apply it: a standby that takes over before the active one published the
  // recovered victim still has it (one that has not seen the victim FOUND yet adopts it so).
  try {
    if (fusion_.recover(victim_id, stamp > 0 ? std::min(stamp, now) : now)) {
      say(IncidentEvent::Kind::kInfo, "victim " + std::to_string(victim_id) + " dug out (reported by '" + reported_by +
                                          "'): its signal is no longer expected");
    }
  } catch (const InputError& error) {
    if (arbiter_.role() != CommandRole::kActive) return;
    reject(reported_by, fusion_.victim(victim_id) != nullptr ? "not_found" : "unknown_victim", error.what());
  }
}

void IncidentCommand::on_dig_order(const std::string& incident_id, const std::vector<std::uint32_t>& victim_ids,
                                   const std::string& operator_id) {
  if (incident_id != config_.incident_id) return;
  // Both instances take it; a standby that has not seen a victim FOUND yet keeps quiet (the
  // active one says why it refused).
  auto refuse_order = [&](std::string subject, std::string reason, std::string text) {
    if (arbiter_.role() == CommandRole::kActive) reject(std::move(subject), std::move(reason), std::move(text));
  };
  if (!is_identifier(operator_id)) {
    return refuse_order(printable_excerpt(operator_id), "invalid_value", "dig order: operator_id is not an identifier");
  }
  const std::string from = "dig order from '" + operator_id + "'";
  if (victim_ids.empty()) return refuse_order(operator_id, "invalid_value", from + ": no victim");
  const std::set<std::uint32_t> found = fusion_.found_ids();
  std::set<std::uint32_t> given;
  std::string ids;
  for (const std::uint32_t id : victim_ids) {
    const std::string name = from + ": victim " + std::to_string(id);
    if (!given.insert(id).second) return refuse_order(operator_id, "invalid_value", name + " is listed twice");
    if (found.count(id) == 0) {
      const bool known = fusion_.victim(id) != nullptr;
      return refuse_order(operator_id, known ? "not_found" : "unknown_victim",
                          name + (known ? " is not FOUND: only found victims are dug" : ": no such victim"));
    }
    ids += " " + std::to_string(id);
  }
  operator_dig_order_ = OperatorDigOrder{victim_ids, operator_id, found};
  say(IncidentEvent::Kind::kInfo, from + ": victims" + ids + " first");
}

void IncidentCommand::on_deposit_drawing(const std::string& incident_id, const std::vector<Vec2>& outline,
                                         const std::string& operator_id) {
  if (incident_id != config_.incident_id) return;
  // Both instances take it; only the active one says why it refused.
  auto refuse = [&](std::string subject, std::string text) {
    if (arbiter_.role() == CommandRole::kActive) reject(std::move(subject), "invalid_value", std::move(text));
  };
  if (!is_identifier(operator_id)) {
    return refuse(printable_excerpt(operator_id), "deposit drawing: operator_id is not an identifier");
  }
  const std::string from = "deposit drawn by '" + operator_id + "'";
  std::optional<Deposit> drawn;
  try {
    drawn.emplace(outline, "deposit_drawing.outline");
    check_deposit_fits(*drawn, config_.search_plan, "deposit_drawing.outline");
  } catch (const ConfigError& e) {
    return refuse(operator_id, from + " refused: " + e.what());
  }
  if (config_.deposit && config_.deposit->vertices() == drawn->vertices()) return;  // delivered again
  const bool had = config_.deposit.has_value();
  config_.deposit = std::move(drawn);
  // A redrawn outline keeps what was searched: a corner moved in mid-search re-walks nothing.
  if (planner_) {
    SearchPlanner replaced = std::move(*planner_);
    planner_.emplace(*config_.deposit, config_.search_plan, replaced);
  } else {
    planner_.emplace(*config_.deposit, config_.search_plan);
  }
  planner_seeded_ = false;
  if (!pursuits_) pursuits_.emplace(config_.search_plan.pursuit_timeout_s);
  say(had ? IncidentEvent::Kind::kWarning : IncidentEvent::Kind::kInfo,
      from + ": " + std::to_string(config_.deposit->vertices().size()) + " vertices, " +
          std::to_string(static_cast<long>(std::lround(config_.deposit->area_m2()))) +
          " m2; the search is planned over it" +
          (had ? " in place of the last one (strips cut afresh; what was searched inside the new outline stays "
                 "searched)"
               : ""));
}

void IncidentCommand::on_peer_summary(const std::string& writer, TimestampNs wall_now) {
  arbiter_.on_peer_sample(writer, wall_now);
  fresh_picture_ = true;  // written after that cycle's victims and teams
}

void IncidentCommand::on_peer_lost(const std::string& writer, TimestampNs wall_now) {
  arbiter_.on_peer_lost(writer, wall_now);
}

void IncidentCommand::on_peer_victim(FusedVictim victim) {
  try {
    check_adoptable(victim);
  } catch (const InputError& error) {
    reject("picture", "invalid_value", std::string("adopted victim: ") + error.what());
    return;
  }
  largest_id_seen_ = std::max(largest_id_seen_, victim.victim_id);
  adopted_victims_[victim.victim_id] = std::move(victim);
}

void IncidentCommand::on_peer_victim_disposed(std::uint32_t victim_id) {
  // Merged away. (Its writer lost is no disposal: the victim stays.)
  adopted_victims_.erase(victim_id);
  largest_id_seen_ = std::max(largest_id_seen_, victim_id);
}

void IncidentCommand::on_peer_team(TeamStatus team) { adopted_teams_[team.team_id] = std::move(team); }

void IncidentCommand::on_peer_alarm(IncidentAlarm alarm) { adopted_alarms_[alarm.alarm_id] = std::move(alarm); }

void IncidentCommand::on_peer_alarm_disposed(std::uint32_t alarm_id) { adopted_alarms_.erase(alarm_id); }

void IncidentCommand::on_peer_frame(const IncidentFrame& frame) {
  if (frame.incident_id == frame_.incident_id) adopted_frame_ = frame;
}

void IncidentCommand::on_peer_search_plan(SearchPlanPicture plan) {
  if (plan.incident_id != config_.incident_id) return;
  if (plan.incident_start != 0 && (!incident_start_ || plan.incident_start < *incident_start_))
    incident_start_ = plan.incident_start;
  adopted_plan_ = std::move(plan);
}

std::optional<ReporterFix> IncidentCommand::fix_for(const responder::VictimEstimate& e) const {
  const auto max_age = seconds_to_ns(config_.position_max_age_s);
  // The fix the estimate carries (a device's own), if it is of the estimate's epoch: it
  // survives any fade that lost the responder_position samples of that epoch.
  if (e.reporter && e.reporter->position.position.allFinite() && e.reporter->position.covariance.allFinite() &&
      std::llabs(e.reporter->stamp - e.stamp) <= max_age) {
    return reporter_fix_of(*e.reporter, config_.antenna_height_m, config_.antenna_height_sigma_m);
  }
  const auto it = fixes_.find(e.rescuer_id);
  if (it == fixes_.end()) return std::nullopt;
  return it->second.at(e.stamp, max_age, seconds_to_ns(config_.fix_interpolation_max_gap_s));
}

void IncidentCommand::note_separation_event(const responder::VictimEstimate& e, bool from_device) {
  // A repeat's state as the device says it (it saw every sample), once per change: the
  // commander learns why a victim went back to unconfirmed or merged away.
  auto& repeat = repeats_logged_[{e.rescuer_id, e.signal_id}];
  if (from_device && e.repeat != repeat) {
    repeat = e.repeat;
    if (e.repeat != responder::RepeatState::kNone) {
      say(IncidentEvent::Kind::kWarning, "rescuer '" + e.rescuer_id + "' signal " + std::to_string(e.signal_id) + ": " +
                                             responder::to_string(e.repeat) + " repeat of its signal " +
                                             std::to_string(e.repeat_of_signal) +
                                             " (one transmitter split in two; it confirms nothing)");
    }
  }
  if (e.signal_event != responder::SignalEvent::kReacquired && e.signal_event != responder::SignalEvent::kSeparated)
    return;
  auto& logged = separation_events_logged_[{e.rescuer_id, e.signal_id}];
  if (e.signal_event_stamp <= logged) return;
  logged = e.signal_event_stamp;
  say(IncidentEvent::Kind::kInfo, "signal separation: rescuer '" + e.rescuer_id + "' signal " +
                                      std::to_string(e.signal_id) + " " + responder::to_string(e.signal_event) +
                                      " at stamp " + std::to_string(e.signal_event_stamp) +
                                      " (its victim estimate continues from it)");
}

void IncidentCommand::note_heard(const responder::VictimEstimate& e, TimestampNs now) {
  if (!pursuits_) return;  // no search plan: nobody is sent or handed over
  auto [it, added] = heard_.try_emplace({e.rescuer_id, e.signal_id});
  HeardSignal& s = it->second.signal;
  if (added) {
    s.rescuer_id = e.rescuer_id;
    s.signal_id = e.signal_id;
    s.first_heard = e.stamp;
  }
  s.first_heard = std::min(s.first_heard, e.stamp);
  if (e.transmitter.known()) s.transmitter = e.transmitter;
  s.placed = e.status >= responder::EstimatorStatus::kConverged;
  double weight = 0.0, range = 0.0;
  for (const auto& c : e.top_components) {
    weight += c.weight;
    range += c.weight * c.mean.norm();
  }
  s.range_m = weight > 0.0 && std::isfinite(range) ? range / weight : std::numeric_limits<double>::quiet_NaN();
  it->second.arrived = std::max(it->second.arrived, now);
}

std::vector<HeardSignal> IncidentCommand::heard_signals(TimestampNs now) {
  const auto timeout = seconds_to_ns(config_.fusion.source_timeout_s);
  std::vector<HeardSignal> out;
  for (auto it = heard_.begin(); it != heard_.end();) {
    if (now - it->second.arrived > timeout) {
      it = heard_.erase(it);
      continue;
    }
    out.push_back(it->second.signal);
    ++it;
  }
  return out;
}

void IncidentCommand::fuse_pending(TimestampNs now, CommandCycle& out) {
  std::deque<PendingEstimate> waiting;
  while (!pending_estimates_.empty()) {
    auto pending = std::move(pending_estimates_.front());
    pending_estimates_.pop_front();
    const auto& e = pending.estimate;
    note_separation_event(e, pending.from_device);
    note_heard(e, pending.arrived);
    if (e.status < responder::EstimatorStatus::kConverged) continue;  // a multimodal mean means nothing
    const auto fix = fix_for(e);
    if (!fix) {
      // The fix may still be on its way: the estimate waits for the next cycle, briefly.
      // Counted from its arrival, not its stamp: after a radio fade both arrive late, in a burst.
      say(IncidentEvent::Kind::kDebug, "no fix of '" + e.rescuer_id + "' near stamp " + std::to_string(e.stamp) +
                                           ": estimate waits");
      if (static_cast<double>(now - pending.arrived) < config_.fix_wait_s * 1e9) waiting.push_back(std::move(pending));
      continue;
    }
    try {
      auto source = make_source_estimate(e, *fix);
      source.estimator = pending.writer;
      source.from_device = pending.from_device;
      source.received = pending.arrived;
      fusion_.update(source);
      ++out.estimates_fused;
    } catch (const InputError& error) {
      reject(e.rescuer_id, "invalid_value", error.what());
    }
  }
  pending_estimates_ = std::move(waiting);
}

void IncidentCommand::adopt_picture() {
  std::vector<FusedVictim> victims;
  victims.reserve(adopted_victims_.size());
  for (const auto& [id, v] : adopted_victims_) victims.push_back(v);
  std::vector<TeamStatus> teams;
  for (const auto& [id, t] : adopted_teams_) teams.push_back(t);
  std::vector<IncidentAlarm> alarms;
  for (const auto& [id, a] : adopted_alarms_) alarms.push_back(a);
  try {
    fusion_.adopt(victims, largest_id_seen_);
    tracker_.adopt(teams);
    alarm_board_.adopt(alarms);
  } catch (const InputError& error) {  // checked on arrival: not expected
    say(IncidentEvent::Kind::kError, std::string("cannot adopt the picture: ") + error.what());
  }
  // Taking over must send no rescuer to another strip or victim.
  if (planner_ && adopted_plan_) {
    if (!planner_->adopt_assignments(adopted_plan_->plan) && !plan_adoption_refused_) {
      plan_adoption_refused_ = true;
      say(IncidentEvent::Kind::kWarning,
          "search plan: the active incident command's strips are cut differently; keeping this one's own");
    }
    pursuits_->adopt(adopted_plan_->handed_over, adopted_plan_->stamp);
  }
}

void IncidentCommand::take_over(TimestampNs now) {
  if (adopted_frame_) frame_ = *adopted_frame_;
  if (frame_.established == 0) frame_.established = now;
  adopted_victims_.clear();
  adopted_teams_.clear();
  adopted_alarms_.clear();
  adopted_frame_.reset();
  adopted_plan_.reset();
}

std::vector<std::uint32_t> IncidentCommand::retired_ids(const std::vector<std::uint32_t>& removed) const {
  // Ids are handed out in sequence, so every id up to the largest one seen that is neither in
  // the picture nor being removed now was merged away by this instance or a predecessor.
  std::set<std::uint32_t> kept(removed.begin(), removed.end());
  for (const auto& v : fusion_.victims()) kept.insert(v.victim_id);
  std::vector<std::uint32_t> retired;
  for (std::uint32_t id = 1; id <= largest_id_seen_; ++id) {
    if (kept.count(id) == 0) retired.push_back(id);
  }
  return retired;
}

void IncidentCommand::raise_conditions(const std::vector<TeamStatus>& teams, TimestampNs now) {
  // Link lost and map error are alarms until acknowledged (docs/topics.md, IncidentAlarm).
  for (const auto& t : teams) {
    for (const auto& m : t.members) {
      std::optional<GaussianPosition> where;
      if (m.has_position) where = m.last_position;
      alarm_board_.set_condition(m.responder_id, t.team_id, responder::AlarmKind::kLinkLost,
                                 m.link == LinkState::kLost, now, where, m.floor);
      alarm_board_.set_condition(
          m.responder_id, t.team_id, responder::AlarmKind::kMapError,
          m.has_position && m.source == responder::PositionSource::kMapAided && m.map_error_suspected, now, where,
          m.floor);
    }
  }
}

std::optional<SearchPlanPicture> IncidentCommand::plan_search(const std::vector<TeamStatus>& teams,
                                                              const std::vector<FusedVictim>& victims,
                                                              TimestampNs now) {
  if (!planner_) return std::nullopt;
  std::map<std::string, Vec2> searching;  // who may pursue a victim, where
  for (const auto& t : teams)
    for (const auto& m : t.members) {
      if (m.source != responder::PositionSource::kGnss) continue;
      // A planner made for a drawn deposit starts from where everyone is, not at their next fix.
      if (!planner_seeded_ && m.has_position) planner_->on_position(m.responder_id, m.last_position.position.head<2>());
      const bool gone = m.link == LinkState::kLost || tracker_.signed_off(m.responder_id);
      if (!gone && m.has_position && m.link == LinkState::kAlive)
        searching.emplace(m.responder_id, m.last_position.position.head<2>());
      const auto had = planner_->strip_of(m.responder_id);
      const auto helped = planner_->strip_helped_by(m.responder_id);
      if (gone) {
        planner_->release(m.responder_id);
        if (had)
          say(IncidentEvent::Kind::kWarning, "search plan: strip " + std::to_string(*had) + " open again (" +
                                                 m.responder_id + " no longer searching)");
        if (helped)
          say(IncidentEvent::Kind::kInfo, "search plan: strip " + std::to_string(*helped) + " has no helper (" +
                                              m.responder_id + " no longer searching)");
      } else {
        planner_->resume(m.responder_id);
      }
    }
  planner_seeded_ = true;
  const std::uint32_t revision = planner_->plan().revision;
  std::vector<std::string> helpers_before;
  for (const auto& s : planner_->plan().strips) helpers_before.push_back(s.helper_id);
  planner_->update();
  const auto& strips = planner_->plan().strips;
  for (std::size_t i = 0; i < strips.size(); ++i) {
    if (strips[i].helper_id.empty() || (i < helpers_before.size() && helpers_before[i] == strips[i].helper_id))
      continue;
    say(IncidentEvent::Kind::kInfo, "search plan: " + strips[i].helper_id + " helps on strip " + std::to_string(i) +
                                        " (" + strips[i].rescuer_id + "'s) from the bottom up");
  }
  SearchPlanPicture picture = planner_->picture(config_.incident_id, now);
  picture.handed_over = pursuits_->update(
      victims, searching, now, group_heard_signals(heard_signals(now), victims, config_.fusion.gate_probability));
  for (const auto& e : pursuits_->events())
    say(e.warning ? IncidentEvent::Kind::kWarning : IncidentEvent::Kind::kInfo, "search plan: " + e.text);
  // The dig order: free rescuers walk no strip and pursue no victim.
  std::map<std::string, Vec2> free = searching;
  for (const auto& h : picture.handed_over) free.erase(h.pursued_by);
  for (auto it = free.begin(); it != free.end();) {
    const bool walks = planner_->strip_of(it->first) || planner_->strip_helped_by(it->first);
    it = walks ? free.erase(it) : std::next(it);
  }
  picture.incident_start = *incident_start_;
  const double buried_min = config_.triage.buried_before_start_min + ns_to_seconds(now - *incident_start_) / 60.0;
  // An operator's order holds for the FOUND victims it was given for; once they change, this
  // re-plan is the last writer.
  if (operator_dig_order_ && operator_dig_order_->found != fusion_.found_ids()) {
    say(IncidentEvent::Kind::kInfo,
        "dig order: the FOUND victims changed, incident command re-plans; the order from '" +
            operator_dig_order_->operator_id + "' no longer holds");
    operator_dig_order_.reset();
  }
  try {
    picture.digs =
        plan_victim_digs(victims, free, buried_min, config_.triage,
                         operator_dig_order_ ? operator_dig_order_->victim_ids : std::vector<std::uint32_t>{});
  } catch (const InputError& e) {  // the picture's positions are finite: not expected
    say(IncidentEvent::Kind::kError, std::string("dig order: ") + e.what());
  }
  std::string order;
  for (const auto& d : picture.digs.digs) order += " " + std::to_string(d.victim_id);
  if (order != dig_order_logged_) {
    dig_order_logged_ = order;
    char survivors[32];
    std::snprintf(survivors, sizeof(survivors), "%.2f", picture.digs.expected_survivors);
    if (!order.empty())
      say(IncidentEvent::Kind::kInfo, "dig order: victims" + order + " (expected survivors " + survivors + ")");
  }
  if (picture.plan.revision != revision) {
    std::string who;
    for (const auto& s : picture.plan.strips)
      who += " " + std::to_string(s.strip.index) + ":" +
             (s.rescuer_id.empty() ? (s.done ? "done" : "open") : s.rescuer_id);
    say(IncidentEvent::Kind::kInfo, "search plan revision " + std::to_string(picture.plan.revision) + ", " +
                                        std::to_string(static_cast<int>(100.0 * picture.plan.searched)) +
                                        " % of the deposit searched; strips" + who);
  }
  return picture;
}

CommandCycle IncidentCommand::cycle(TimestampNs now, TimestampNs wall_now) {
  CommandCycle out;
  out.stamp = now;
  if (!incident_start_) incident_start_ = now;
  out.role_change = arbiter_.decide(wall_now);
  const bool took_over = out.role_change && out.role_change->role == CommandRole::kActive;
  if (out.role_change) {
    if (out.role_change->role == CommandRole::kStandby) {
      say(IncidentEvent::Kind::kWarning, "standing by: " + out.role_change->reason);
    } else if (config_.standby.instances > 1) {
      say(IncidentEvent::Kind::kWarning, "taking over as the active incident command (" + out.role_change->reason +
                                             "): " + std::to_string(adopted_victims_.size()) +
                                             " victim(s) adopted, ownership strength " +
                                             std::to_string(out.role_change->strength));
    } else {
      say(IncidentEvent::Kind::kInfo, "active (" + out.role_change->reason + ")");
    }
  }
  fuse_pending(now, out);
  out.active = arbiter_.role() == CommandRole::kActive;
  // A standby adopts each new picture of the active one, then fuses as the active one would
  // (unpublished): when no new picture comes (the active one just died), it carries on from the
  // last one, so what it hears until it takes over is not lost (VictimFusion::adopt).
  if (!out.active && fresh_picture_) {
    adopt_picture();
    fresh_picture_ = false;
  }
  if (took_over) take_over(now);
  fusion_.step(now);
  for (const auto& w : fusion_.take_withdrawn()) {
    say(IncidentEvent::Kind::kWarning,
        "victim " + std::to_string(w.victim_id) + ": LOCATED withdrawn, now unconfirmed with evidence conflict: " +
            "the signal that located it (rescuer '" + w.rescuer_id + "' signal " + std::to_string(w.signal_id) +
            ") is now estimated at victim " + std::to_string(w.now_bound_to) + " and nothing else stands by it");
  }
  for (const auto& e : fusion_.take_late_echoes()) {
    say(IncidentEvent::Kind::kInfo, "rescuer '" + e.rescuer_id + "' signal " + std::to_string(e.signal_id) +
                                        ": an estimate of dug-out victim " + std::to_string(e.victim_id) +
                                        " measured before its transmitter went off, heard late: ignored");
  }
  out.victims = fusion_.victims();
  if (out.active) {
    for (const auto& v : out.victims) largest_id_seen_ = std::max(largest_id_seen_, v.victim_id);
  }
  out.disposed_victims = fusion_.take_removed();
  if (took_over) redispose_until_ = wall_now + kRedisposeWindowNs;
  if (out.active && wall_now < redispose_until_) {
    const auto retired = retired_ids(out.disposed_victims);
    if (took_over && !retired.empty()) {
      std::string list;
      for (const auto id : retired) list += " " + std::to_string(id);
      say(IncidentEvent::Kind::kInfo, "disposing again, for " + std::to_string(kRedisposeWindowNs / kNsPerSecond) +
                                           " s, the victim id(s)" + list +
                                           " no longer in the picture (a reader may have missed a predecessor's "
                                           "disposal)");
    }
    out.disposed_victims.insert(out.disposed_victims.end(), retired.begin(), retired.end());
  }
  out.teams = tracker_.evaluate(now);
  last_teams_ = out.teams;
  raise_conditions(out.teams, now);
  out.search_plan = plan_search(out.teams, out.victims, now);
  out.alarms = alarm_board_.alarms();
  out.disposed_alarms = alarm_board_.take_removed();

  out.counts.victims_total = static_cast<std::uint32_t>(out.victims.size());
  for (const auto& v : out.victims) {
    if (v.state != VictimState::kUnconfirmed) ++out.counts.victims_located;
    if (is_found(v.state)) ++out.counts.victims_found;
  }
  out.counts.responders_total = static_cast<std::uint32_t>(tracker_.responders_total());
  out.counts.responders_link_lost = static_cast<std::uint32_t>(tracker_.link_lost_count(now));
  out.frame = frame_;
  out.events = std::move(events_);
  events_.clear();
  return out;
}

}  // namespace sarloc::incident
