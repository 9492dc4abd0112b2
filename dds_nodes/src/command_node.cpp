#include "sarloc/dds/command_node.hpp"

#include "sarloc/core/common/validate.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>

#include "sarloc/core/common/identifier.hpp"
#include "sarloc/core/incident/source_estimate.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/process_stats.hpp"
#include "sarloc/dds/sign_off.hpp"

namespace sarloc::dds {
namespace {

// The arbiter learns how often an active peer publishes: its summary comes every cycle.
incident::StandbyConfig standby_config_of(const CommandNodeConfig& config) {
  incident::StandbyConfig standby = config.standby;
  standby.peer_period_s = config.cycle_s;
  return standby;
}

}  // namespace

void CommandNodeConfig::validate() const {
  fusion.validate();
  teams.validate();
  standby.validate();
  if (node_id.empty() || node_id.size() > 64) throw ConfigError("command.node_id = '" + node_id + "': must be 1-64 characters");
  if (incident_id.empty() || incident_id.size() > 64) {
    throw ConfigError("incident.id = '" + incident_id + "': must be 1-64 characters");
  }
  if (!(cycle_s > 0.0 && cycle_s <= 60.0)) throw ConfigError("command.cycle_s = " + config_value(cycle_s) + ": must be in (0, 60]");
  if (!(position_max_age_s > 0.0 && position_max_age_s <= 600.0)) {
    throw ConfigError("command.position_max_age_s = " + config_value(position_max_age_s) + ": must be in (0, 600]");
  }
  if (!(fix_interpolation_max_gap_s >= 0.0 && fix_interpolation_max_gap_s <= 60.0)) {
    throw ConfigError("command.fix_interpolation_max_gap_s = " + config_value(fix_interpolation_max_gap_s) +
                      ": must be in [0, 60]");
  }
  if (!(fix_wait_s > 0.0 && fix_wait_s <= 600.0)) {
    throw ConfigError("command.fix_wait_s = " + config_value(fix_wait_s) + ": must be in (0, 600]");
  }
  if (!(antenna_height_m >= 0.0 && antenna_height_m <= 5.0)) {
    throw ConfigError("command.antenna_height_m = " + config_value(antenna_height_m) + ": must be in [0, 5]");
  }
  if (!(antenna_height_sigma_m > 0.0 && antenna_height_sigma_m <= 5.0)) {
    throw ConfigError("command.antenna_height_sigma_m = " + config_value(antenna_height_sigma_m) + ": must be in (0, 5]");
  }
  if (!(origin.latitude_deg >= -90.0 && origin.latitude_deg <= 90.0)) {
    throw ConfigError("incident.latitude_deg = " + config_value(origin.latitude_deg) + ": must be in [-90, 90]");
  }
  if (!(origin.longitude_deg >= -180.0 && origin.longitude_deg <= 180.0)) {
    throw ConfigError("incident.longitude_deg = " + config_value(origin.longitude_deg) + ": must be in [-180, 180]");
  }
}

CommandNode::CommandNode(std::shared_ptr<Participant> participant, CommandNodeConfig config, MissionClock clock)
    : config_((config.validate(), std::move(config))),
      clock_(clock),
      participant_(std::move(participant)),
      authority_(participant_),
      warnings_(std::chrono::seconds(5)),
      fusion_(config_.fusion),
      tracker_(config_.teams),
      arbiter_(standby_config_of(config_), MissionClock::wall_now_ns()),
      victim_writer_(participant_),
      team_writer_(participant_),
      summary_writer_(participant_),
      frame_writer_(participant_),
      alarm_writer_(participant_),
      status_writer_(participant_) {
  // Published while active (established: when this instance first takes over, unless it
  // adopts the frame of the instance before it).
  frame_.incident_id(config_.incident_id);
  frame_.latitude_deg(config_.origin.latitude_deg);
  frame_.longitude_deg(config_.origin.longitude_deg);
  frame_.altitude_m(config_.origin.altitude_m);
  frame_.name(config_.incident_name.substr(0, ::sarloc::TEXT_MAX));

  estimate_reader_ = std::make_unique<Reader<::sarloc::VictimEstimate>>(
      participant_,
      [this](const ::sarloc::VictimEstimate& e, const auto& info) {
        try {
          auto estimate = to_core(e);
          if (!admitted(info.publication_handle, estimate.rescuer_id, WriterAuthority::Speakers::kDeviceOrCore,
                        "victim estimate")) {
            return;
          }
          // The writer tells the daemon's estimates from a device's own: two estimators of one
          // source, which VictimFusion holds to agreeing with each other.
          std::string writer = handle_text(info.publication_handle);
          spdlog::debug("estimate {}/{} status {} stamp {} from writer {} relative ({:.2f}, {:.2f}, {:.2f})",
                        estimate.rescuer_id, estimate.signal_id, static_cast<int>(estimate.status), estimate.stamp,
                        writer, estimate.relative.position.x(), estimate.relative.position.y(),
                        estimate.relative.position.z());
          std::lock_guard<std::mutex> lock(mutex_);
          pending_estimates_.push_back({std::move(estimate), std::move(writer), e.from_device(), clock_.now()});
        } catch (const InputError& error) {
          counters_.rejected("invalid_value");
          warnings_.warn(printable_id(e.rescuer_id()), "invalid_value", std::string("victim estimate: ") + error.what());
        }
      },
      EndpointOptions::in(config_.estimate_partitions));

  ReaderEvents events;
  events.on_liveliness = [this](const auto& handle, bool alive) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [writer, responder] : writer_owner_) {
      if (writer == handle) {
        tracker_.on_link(responder, alive, clock_.now());
        if (!alive) spdlog::warn("{}: link to responder '{}' lost", config_.node_id, responder);
      }
    }
  };
  const auto on_position = [this](const ::sarloc::ResponderPosition& p, const auto& info) {
        try {
          auto position = to_core(p);
          if (!position.position.position.allFinite() || !position.position.covariance.allFinite()) {
            throw InputError("responder_position.position: non-finite value");
          }
          // Map-aided fixes come from the core daemon; any other kind only from the device itself.
          const auto speakers = position.source == responder::PositionSource::kMapAided
                                    ? WriterAuthority::Speakers::kDeviceOrCore
                                    : WriterAuthority::Speakers::kDevice;
          if (!admitted(info.publication_handle, position.responder_id, speakers, "responder position")) return;
          std::lock_guard<std::mutex> lock(mutex_);
          auto& owners = writer_owner_;
          const bool known = std::any_of(owners.begin(), owners.end(),
                                         [&](const auto& o) { return o.first == info.publication_handle; });
          // A device's own writer stands for its link; the core daemon's map-aided positions
          // come from one writer for many responders, whose liveliness says nothing of them.
          if (!known && position.source != responder::PositionSource::kMapAided) {
            owners.emplace_back(info.publication_handle, position.responder_id);
          }
          tracker_.on_position(position, clock_.now());
          // GNSS heights become the antenna's above the snow; indoor positions keep theirs.
          fixes_[position.responder_id].add(
              position.stamp, incident::reporter_fix_of(position, config_.antenna_height_m, config_.antenna_height_sigma_m));
        } catch (const InputError& error) {
          counters_.rejected("invalid_value");
          warnings_.warn(printable_id(p.responder_id()), "invalid_value", error.what());
        }
      };
  // A device that stops in order disposes its own position instance before its writer goes
  // (sign_off.hpp): signed off, not lost. Only a device's own writer speaks for its responder.
  events.on_instance_gone = [this](const auto& info) {
    if (info.instance_state != eprosima::fastdds::dds::NOT_ALIVE_DISPOSED_INSTANCE_STATE) return;
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [writer, responder] : writer_owner_) {
      if (writer != info.publication_handle) continue;
      if (!tracker_.signed_off(responder)) spdlog::info("{}: responder '{}' signed off", config_.node_id, responder);
      tracker_.on_signed_off(responder, clock_.now());
    }
  };
  position_reader_ = std::make_unique<Reader<::sarloc::ResponderPosition>>(participant_, on_position, EndpointOptions{}, events);
  // Devices' own writers also match this MANUAL_BY_TOPIC reader, whose liveliness reports a
  // killed device within its 3 s lease (the AUTOMATIC one waits for the participant's).
  device_position_reader_ =
      std::make_unique<Reader<::sarloc::ResponderPosition>>(participant_, on_position, device_position_options(true), events);

  // The picture as the active instance publishes it. Exclusive ownership: these readers
  // deliver the strongest live writer's samples only, so another instance's summary here means
  // that one is active and outranks this one (incident::StandbyArbiter). Own samples come back
  // too and are ignored.
  ReaderEvents summary_events;
  summary_events.on_liveliness = [this](const auto& handle, bool alive) {
    if (alive) return;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      arbiter_.on_peer_lost(handle_text(handle), MissionClock::wall_now_ns());
    }
    wake_.store(true);
  };
  summary_reader_ = std::make_unique<Reader<::sarloc::IncidentSummary>>(
      participant_,
      [this](const ::sarloc::IncidentSummary&, const auto& info) {
        if (participant_->is_own_writer(info.publication_handle)) return;
        std::lock_guard<std::mutex> lock(mutex_);
        arbiter_.on_peer_sample(handle_text(info.publication_handle), MissionClock::wall_now_ns());
        fresh_picture_ = true;  // written after that cycle's victims and teams
      },
      EndpointOptions{}, summary_events);
  ReaderEvents victim_events;
  victim_events.on_instance_gone = [this](const auto& info) {
    // Merged away. (Its writer lost: NOT_ALIVE_NO_WRITERS, the victim stays.)
    if (info.instance_state != eprosima::fastdds::dds::NOT_ALIVE_DISPOSED_INSTANCE_STATE) return;
    if (participant_->is_own_writer(info.publication_handle)) return;
    const auto id = victim_id_of(info.instance_handle);
    if (!id) return;
    std::lock_guard<std::mutex> lock(mutex_);
    adopted_victims_.erase(*id);
    largest_id_seen_ = std::max(largest_id_seen_, *id);
  };
  picture_victim_reader_ = std::make_unique<Reader<::sarloc::FusedVictim>>(
      participant_,
      [this](const ::sarloc::FusedVictim& v, const auto& info) {
        if (participant_->is_own_writer(info.publication_handle)) return;
        try {
          auto victim = to_core(v);
          incident::check_adoptable(victim);
          std::lock_guard<std::mutex> lock(mutex_);
          largest_id_seen_ = std::max(largest_id_seen_, victim.victim_id);
          adopted_victims_[victim.victim_id] = std::move(victim);
        } catch (const InputError& error) {
          counters_.rejected("invalid_value");
          warnings_.warn("picture", "invalid_value", std::string("adopted victim: ") + error.what());
        }
      },
      EndpointOptions{}, victim_events);
  picture_team_reader_ = std::make_unique<Reader<::sarloc::TeamStatus>>(
      participant_, [this](const ::sarloc::TeamStatus& t, const auto& info) {
        if (participant_->is_own_writer(info.publication_handle)) return;
        try {
          auto team = to_core(t);
          std::lock_guard<std::mutex> lock(mutex_);
          adopted_teams_[team.team_id] = std::move(team);
        } catch (const InputError& error) {
          counters_.rejected("invalid_value");
          warnings_.warn("picture", "invalid_value", std::string("adopted team: ") + error.what());
        }
      });
  picture_frame_reader_ = std::make_unique<Reader<::sarloc::IncidentFrame>>(
      participant_, [this](const ::sarloc::IncidentFrame& f, const auto& info) {
        if (participant_->is_own_writer(info.publication_handle) || f.incident_id() != frame_.incident_id()) return;
        std::lock_guard<std::mutex> lock(mutex_);
        adopted_frame_ = f;
      });

  responder_alarm_reader_ = std::make_unique<Reader<::sarloc::ResponderAlarm>>(
      participant_, [this](const ::sarloc::ResponderAlarm& a, const auto& info) {
        try {
          const auto alarm = to_core(a);
          // A mayday "for r1" counts only from r1's own device.
          if (!admitted(info.publication_handle, alarm.responder_id, WriterAuthority::Speakers::kDevice, "responder alarm")) {
            return;
          }
          std::lock_guard<std::mutex> lock(mutex_);
          alarm_board_.on_device_alarm(alarm, clock_.now());
          if (alarm.active) {
            spdlog::warn("{}: {} alarm from '{}' (team '{}')", config_.node_id, responder::to_string(alarm.kind),
                         alarm.responder_id, alarm.team_id);
          } else {
            spdlog::info("{}: {} alarm of '{}' cleared", config_.node_id, responder::to_string(alarm.kind),
                         alarm.responder_id);
          }
        } catch (const InputError& error) {
          counters_.rejected("invalid_value");
          warnings_.warn(printable_id(a.responder_id()), "invalid_value", std::string("responder alarm: ") + error.what());
        }
      });
  acknowledgement_reader_ = std::make_unique<Reader<::sarloc::AlarmAcknowledgement>>(
      participant_, [this](const ::sarloc::AlarmAcknowledgement& ack, const auto&) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (arbiter_.role() != incident::CommandRole::kActive) return;  // the active one's picture carries it
        const std::string operator_id = ack.operator_id().to_string();
        if (!is_identifier(operator_id)) {
          // It would travel on as the alarm's acknowledged_by, which every reader refuses.
          counters_.rejected("invalid_value");
          warnings_.warn(printable_id(ack.operator_id()), "invalid_value", "alarm acknowledgement: operator_id is not an identifier");
          return;
        }
        const auto result = alarm_board_.acknowledge(ack.alarm_id(), operator_id, clock_.now());
        if (result == incident::AckResult::kUnknown) {
          counters_.rejected("unknown_alarm");
          warnings_.warn(printable_id(ack.operator_id()), "unknown_alarm",
                         "acknowledgement of alarm " + std::to_string(ack.alarm_id()) + ": no such alarm");
        } else if (result == incident::AckResult::kAcknowledged) {
          spdlog::info("{}: alarm {} acknowledged by '{}'", config_.node_id, ack.alarm_id(), operator_id);
        }
      });
  ReaderEvents alarm_events;
  alarm_events.on_instance_gone = [this](const auto& info) {
    if (info.instance_state != eprosima::fastdds::dds::NOT_ALIVE_DISPOSED_INSTANCE_STATE) return;
    if (participant_->is_own_writer(info.publication_handle)) return;
    const auto id = alarm_id_of(info.instance_handle);
    if (!id) return;
    std::lock_guard<std::mutex> lock(mutex_);
    adopted_alarms_.erase(*id);
  };
  picture_alarm_reader_ = std::make_unique<Reader<::sarloc::IncidentAlarm>>(
      participant_,
      [this](const ::sarloc::IncidentAlarm& a, const auto& info) {
        if (participant_->is_own_writer(info.publication_handle)) return;
        try {
          auto alarm = to_core(a);
          std::lock_guard<std::mutex> lock(mutex_);
          adopted_alarms_[alarm.alarm_id] = std::move(alarm);
        } catch (const InputError& error) {
          counters_.rejected("invalid_value");
          warnings_.warn("picture", "invalid_value", std::string("adopted alarm: ") + error.what());
        }
      },
      EndpointOptions{}, alarm_events);

  thread_ = std::thread([this] {
    using Clock = std::chrono::steady_clock;
    auto asserted = Clock::now();
    while (!stopping_.load()) {
      cycle();
      asserted = Clock::now();
      const auto until = Clock::now() + std::chrono::milliseconds(static_cast<std::int64_t>(config_.cycle_s * 1000));
      while (!stopping_.load() && Clock::now() < until && !wake_.exchange(false)) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        if (Clock::now() - asserted >= std::chrono::seconds(1)) {  // long cycles: keep the 3 s lease
          assert_picture_liveliness();
          asserted = Clock::now();
        }
      }
    }
  });
}

bool CommandNode::admitted(const eprosima::fastrtps::rtps::InstanceHandle_t& writer, const std::string& responder_id,
                           WriterAuthority::Speakers speakers, const char* what) {
  if (authority_.admits(writer, responder_id, speakers)) return true;
  counters_.rejected("unauthorized_writer");
  warnings_.warn(responder_id, "unauthorized_writer", authority_.refusal(what, writer, responder_id));
  return false;
}

bool CommandNode::sign_off(std::chrono::milliseconds timeout) {
  stopping_.store(true);
  if (thread_.joinable()) thread_.join();  // no status is written after the disposal
  return dds::sign_off(status_writer_, config_.node_id, timeout);
}

CommandNode::~CommandNode() {
  estimate_reader_.reset();
  position_reader_.reset();
  device_position_reader_.reset();
  summary_reader_.reset();
  picture_victim_reader_.reset();
  picture_team_reader_.reset();
  picture_frame_reader_.reset();
  picture_alarm_reader_.reset();
  responder_alarm_reader_.reset();
  acknowledgement_reader_.reset();
  stopping_.store(true);
  if (thread_.joinable()) thread_.join();
  if (arbiter_.role() != incident::CommandRole::kActive) return;
  // A clean stop: every reader gets the last picture and disposals before the writers go. (Seen
  // with Fast DDS 2.9: a reader takes no other writer's disposal of a deleted writer's instance.)
  const auto wait = std::chrono::milliseconds(500);
  if (!victim_writer_.wait_for_acknowledgments(wait) || !team_writer_.wait_for_acknowledgments(wait) ||
      !summary_writer_.wait_for_acknowledgments(wait) || !frame_writer_.wait_for_acknowledgments(wait) ||
      !alarm_writer_.wait_for_acknowledgments(wait)) {
    spdlog::warn("{}: stopping before every reader acknowledged the last picture", config_.node_id);
  }
}

std::optional<incident::ReporterFix> CommandNode::fix_at(const std::string& rescuer_id, TimestampNs stamp) const {
  const auto it = fixes_.find(rescuer_id);
  if (it == fixes_.end()) return std::nullopt;
  return it->second.at(stamp, static_cast<TimestampNs>(config_.position_max_age_s * 1e9),
                       static_cast<TimestampNs>(config_.fix_interpolation_max_gap_s * 1e9));
}

std::optional<incident::ReporterFix> CommandNode::fix_for(const responder::VictimEstimate& e) const {
  // The fix the estimate carries (a device's own), if it is of the estimate's epoch: it
  // survives any fade that lost the responder_position samples of that epoch.
  if (e.reporter && e.reporter->position.position.allFinite() && e.reporter->position.covariance.allFinite() &&
      std::llabs(e.reporter->stamp - e.stamp) <= static_cast<TimestampNs>(config_.position_max_age_s * 1e9)) {
    return incident::reporter_fix_of(*e.reporter, config_.antenna_height_m, config_.antenna_height_sigma_m);
  }
  return fix_at(e.rescuer_id, e.stamp);
}

void CommandNode::cycle() {
  static thread_local ProcessStats stats;
  std::vector<incident::FusedVictim> victims;
  std::vector<std::uint32_t> removed;
  std::vector<std::uint32_t> retired;
  std::vector<incident::TeamStatus> teams;
  std::vector<incident::IncidentAlarm> alarms;
  std::vector<std::uint32_t> removed_alarms;
  const TimestampNs now = clock_.now();
  std::size_t responders = 0;
  std::size_t lost = 0;
  std::optional<incident::RoleChange> change;
  std::size_t adopted = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    change = arbiter_.decide(MissionClock::wall_now_ns());
    adopted = adopted_victims_.size();
  }
  if (change) apply(*change, adopted);
  bool active = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::deque<PendingEstimate> waiting;
    while (!pending_estimates_.empty()) {
      auto pending = std::move(pending_estimates_.front());
      pending_estimates_.pop_front();
      const auto& e = pending.estimate;
      log_separation_event(e, pending.from_device);
      if (e.status < responder::EstimatorStatus::kConverged) continue;  // a multimodal mean means nothing
      const auto fix = fix_for(e);
      if (!fix) {
        spdlog::debug("no fix of '{}' near stamp {}: estimate waits", e.rescuer_id, e.stamp);
        // The fix may still be on its way: keep the estimate for the next cycle, briefly. Counted
        // from its arrival, not its stamp: after a radio fade both arrive late, in a burst.
        if (static_cast<double>(now - pending.arrived) < config_.fix_wait_s * 1e9) waiting.push_back(std::move(pending));
        continue;
      }
      try {
        auto source = incident::make_source_estimate(e, *fix);
        source.estimator = pending.writer;
        source.from_device = pending.from_device;
        source.received = pending.arrived;
        spdlog::trace("source {}/{} stamp {} status {} at ({:.2f}, {:.2f}, {:.2f}) sd ({:.2f}, {:.2f}, {:.2f}) "
                      "carrier {:.2f} +- {:.2f} Hz period {:.5f} +- {:.5f} s",
                      source.rescuer_id, source.signal_id, source.stamp, static_cast<int>(source.state),
                      source.position.position.x(), source.position.position.y(), source.position.position.z(),
                      std::sqrt(source.position.covariance(0, 0)), std::sqrt(source.position.covariance(1, 1)),
                      std::sqrt(source.position.covariance(2, 2)), source.transmitter.carrier_offset_hz,
                      source.transmitter.carrier_sigma_hz, source.transmitter.period_s, source.transmitter.period_sigma_s);
        fusion_.update(source);
        counters_.accepted();
      } catch (const InputError& error) {
        counters_.rejected("invalid_value");
        warnings_.warn(e.rescuer_id, "invalid_value", error.what());
      }
    }
    pending_estimates_ = std::move(waiting);
    active = arbiter_.role() == incident::CommandRole::kActive;
    // A standby adopts each new picture of the active one, then fuses as the active one would
    // (unpublished): when no new picture comes (the active one just died), it carries on from
    // the last one, so what it hears until it takes over is not lost (VictimFusion::adopt).
    if (!active && fresh_picture_) {
      adopt_picture();
      fresh_picture_ = false;
    }
    if (change && change->role == incident::CommandRole::kActive) {
      if (adopted_frame_) frame_ = *adopted_frame_;
      if (frame_.established() == 0) frame_.established(now);
      adopted_victims_.clear();
      adopted_teams_.clear();
      adopted_alarms_.clear();
      adopted_frame_.reset();
    }
    fusion_.step(now);
    victims = fusion_.victims();
    if (active) {
      for (const auto& v : victims) largest_id_seen_ = std::max(largest_id_seen_, v.victim_id);
    }
    if (spdlog::should_log(spdlog::level::trace)) {
      for (const auto& v : victims) {
        std::string sources;
        for (const auto& src : v.sources) sources += " " + src.rescuer_id + "/" + std::to_string(src.signal_id);
        spdlog::trace("victim {} state {} at ({:.2f}, {:.2f}, {:.2f}) sources{}", v.victim_id, static_cast<int>(v.state),
                      v.position.position.x(), v.position.position.y(), v.position.position.z(), sources);
      }
    }
    removed = fusion_.take_removed();
    const bool took_over = change && change->role == incident::CommandRole::kActive;
    const TimestampNs wall = MissionClock::wall_now_ns();
    if (took_over) redispose_until_ = wall + kRedisposeWindowNs;
    if (active && wall < redispose_until_) retired = retired_ids(victims, removed);
    if (took_over && !retired.empty()) {
      std::string list;
      for (const auto id : retired) list += " " + std::to_string(id);
      spdlog::info("{}: disposing again, for {} s, the victim id(s){} no longer in the picture (a reader may "
                   "have missed a predecessor's disposal)",
                   config_.node_id, kRedisposeWindowNs / 1'000'000'000, list);
    }
    teams = tracker_.evaluate(now);
    last_teams_ = teams;
    // Link lost and map error are alarms until acknowledged (docs/topics.md, IncidentAlarm).
    for (const auto& t : teams) {
      for (const auto& m : t.members) {
        std::optional<GaussianPosition> where;
        if (m.has_position) where = m.last_position;
        alarm_board_.set_condition(m.responder_id, t.team_id, responder::AlarmKind::kLinkLost,
                                   m.link == incident::LinkState::kLost, now, where, m.floor);
        alarm_board_.set_condition(m.responder_id, t.team_id, responder::AlarmKind::kMapError,
                                   m.has_position && m.source == responder::PositionSource::kMapAided &&
                                       m.map_error_suspected,
                                   now, where, m.floor);
      }
    }
    alarms = alarm_board_.alarms();
    removed_alarms = alarm_board_.take_removed();
    responders = tracker_.responders_total();
    lost = tracker_.link_lost_count(now);
  }

  const auto snapshot = counters_.snapshot();
  ::sarloc::NodeStatus status;
  status.node_id(config_.node_id);
  status.kind(::sarloc::NODE_COMMAND);
  status.stamp(now);
  status.samples_accepted(snapshot.accepted);
  status.samples_rejected(snapshot.rejected);
  status.cpu_percent(stats.cpu_percent());
  status.rss_mb(ProcessStats::rss_mb());
  status_writer_.write(status);
  if (!active) return;  // a standby publishes no picture

  removed.insert(removed.end(), retired.begin(), retired.end());
  for (const auto id : removed) {
    ::sarloc::FusedVictim key;
    key.victim_id(id);
    if (!victim_writer_.dispose(key)) spdlog::error("{}: cannot dispose of victim {}", config_.node_id, id);
  }
  std::uint32_t located = 0;
  std::uint32_t found = 0;
  for (const auto& v : victims) {
    if (v.state != incident::VictimState::kUnconfirmed) ++located;
    if (incident::is_found(v.state)) ++found;
    try {
      victim_writer_.write(to_idl(v));
    } catch (const InputError& e) {
      spdlog::error("cannot publish victim {}: {}", v.victim_id, e.what());
    }
  }
  for (const auto& t : teams) {
    try {
      team_writer_.write(to_idl(t));
    } catch (const InputError& e) {
      spdlog::error("cannot publish team '{}': {}", t.team_id, e.what());
    }
  }
  for (const auto id : removed_alarms) {
    ::sarloc::IncidentAlarm key;
    key.alarm_id(id);
    if (!alarm_writer_.dispose(key)) spdlog::error("{}: cannot dispose of alarm {}", config_.node_id, id);
  }
  for (const auto& a : alarms) {
    try {
      alarm_writer_.write(to_idl(a));
    } catch (const InputError& e) {
      spdlog::error("cannot publish alarm {}: {}", a.alarm_id, e.what());
    }
  }
  ::sarloc::IncidentSummary summary;
  summary.incident_id(config_.incident_id);
  summary.stamp(now);
  summary.victims_total(static_cast<std::uint32_t>(victims.size()));
  summary.victims_located(located);
  summary.victims_found(found);
  summary.responders_total(static_cast<std::uint32_t>(responders));
  summary.responders_link_lost(static_cast<std::uint32_t>(lost));
  summary_writer_.write(summary);
  // Every cycle: a reader that still counted the previous active instance alive when this one
  // took over dropped its first frame.
  frame_writer_.write(frame_);
  assert_picture_liveliness();
}

void CommandNode::apply(const incident::RoleChange& change, std::size_t adopted_victims) {
  try {
    victim_writer_.set_ownership_strength(change.strength);
    team_writer_.set_ownership_strength(change.strength);
    summary_writer_.set_ownership_strength(change.strength);
    frame_writer_.set_ownership_strength(change.strength);
    alarm_writer_.set_ownership_strength(change.strength);
  } catch (const DdsError& error) {  // publishes anyway: readers take it once no stronger one is alive
    spdlog::error("{}: {}", config_.node_id, error.what());
  }
  if (change.role == incident::CommandRole::kStandby) {
    spdlog::warn("{}: standing by: {}", config_.node_id, change.reason);
  } else if (arbiter_.config().instances > 1) {
    spdlog::warn("{}: taking over as the active incident command ({}): {} victim(s) adopted, ownership strength {}",
                 config_.node_id, change.reason, adopted_victims, change.strength);
  } else {
    spdlog::info("{}: active ({})", config_.node_id, change.reason);
  }
}

void CommandNode::log_separation_event(const responder::VictimEstimate& e, bool from_device) {
  // A repeat's state as the device says it (it saw every sample), once per change: the
  // commander learns why a victim went back to unconfirmed or merged away.
  auto& repeat = repeats_logged_[{e.rescuer_id, e.signal_id}];
  if (from_device && e.repeat != repeat) {
    repeat = e.repeat;
    if (e.repeat != responder::RepeatState::kNone)
      spdlog::warn("rescuer '{}' signal {}: {} repeat of its signal {} (one transmitter split in two; it confirms nothing)",
                   e.rescuer_id, e.signal_id, responder::to_string(e.repeat), e.repeat_of_signal);
  }
  if (e.signal_event != responder::SignalEvent::kReacquired && e.signal_event != responder::SignalEvent::kSeparated)
    return;
  auto& logged = separation_events_logged_[{e.rescuer_id, e.signal_id}];
  if (e.signal_event_stamp <= logged) return;
  logged = e.signal_event_stamp;
  spdlog::info("signal separation: rescuer '{}' signal {} {} at stamp {} (its victim estimate continues from it)",
               e.rescuer_id, e.signal_id, responder::to_string(e.signal_event), e.signal_event_stamp);
}

std::vector<std::uint32_t> CommandNode::retired_ids(const std::vector<incident::FusedVictim>& victims,
                                                    const std::vector<std::uint32_t>& removed) const {
  // Ids are handed out in sequence, so every id up to the largest one seen that is neither in
  // the picture nor being removed now was merged away by this instance or a predecessor.
  std::set<std::uint32_t> kept(removed.begin(), removed.end());
  for (const auto& v : victims) kept.insert(v.victim_id);
  std::vector<std::uint32_t> retired;
  for (std::uint32_t id = 1; id <= largest_id_seen_; ++id) {
    if (kept.count(id) == 0) retired.push_back(id);
  }
  return retired;
}

void CommandNode::adopt_picture() {
  std::vector<incident::FusedVictim> victims;
  victims.reserve(adopted_victims_.size());
  for (const auto& [id, v] : adopted_victims_) victims.push_back(v);
  std::vector<incident::TeamStatus> teams;
  for (const auto& [id, t] : adopted_teams_) teams.push_back(t);
  try {
    fusion_.adopt(victims, largest_id_seen_);
    tracker_.adopt(teams);
    std::vector<incident::IncidentAlarm> alarms;
    for (const auto& [id, a] : adopted_alarms_) alarms.push_back(a);
    alarm_board_.adopt(alarms);
  } catch (const InputError& error) {  // checked on arrival: not expected
    spdlog::error("{}: cannot adopt the picture: {}", config_.node_id, error.what());
  }
}

void CommandNode::assert_picture_liveliness() {
  if (role() != incident::CommandRole::kActive) return;
  victim_writer_.assert_liveliness();
  team_writer_.assert_liveliness();
  summary_writer_.assert_liveliness();
  frame_writer_.assert_liveliness();
  alarm_writer_.assert_liveliness();
}

std::vector<incident::IncidentAlarm> CommandNode::alarms() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return alarm_board_.alarms();
}

incident::CommandRole CommandNode::role() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return arbiter_.role();
}

std::vector<incident::FusedVictim> CommandNode::victims() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return fusion_.victims();
}

std::vector<incident::TeamStatus> CommandNode::teams() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_teams_;
}

}  // namespace sarloc::dds
