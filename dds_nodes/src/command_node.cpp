#include "sarloc/dds/command_node.hpp"

#include <spdlog/spdlog.h>

#include "sarloc/core/common/validate.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/process_stats.hpp"
#include "sarloc/dds/sign_off.hpp"

namespace sarloc::dds {
namespace {

// The arbiter learns how often an active peer publishes: its summary comes every cycle.
incident::IncidentCommandConfig core_config_of(const CommandNodeConfig& config) {
  incident::IncidentCommandConfig core = config.incident;
  core.standby.peer_period_s = config.cycle_s;
  return core;
}

}  // namespace

void CommandNodeConfig::validate() const {
  incident.validate();
  require(!node_id.empty() && node_id.size() <= 64, "command.node_id", node_id, "must be 1-64 characters");
  require(cycle_s > 0.0 && cycle_s <= 60.0, "command.cycle_s", cycle_s, "must be in (0, 60]");
}

CommandNode::CommandNode(std::shared_ptr<Participant> participant, CommandNodeConfig config, MissionClock clock)
    : config_((config.validate(), std::move(config))),
      clock_(clock),
      participant_(std::move(participant)),
      authority_(participant_),
      warnings_(std::chrono::seconds(5)),
      command_(core_config_of(config_), MissionClock::wall_now_ns()),
      victim_writer_(participant_),
      team_writer_(participant_),
      summary_writer_(participant_),
      frame_writer_(participant_),
      plan_writer_(participant_),
      alarm_writer_(participant_),
      status_writer_(participant_) {
  create_input_readers();
  create_picture_readers();
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

void CommandNode::create_input_readers() {
  estimate_reader_ = std::make_unique<Reader<::sarloc::VictimEstimate>>(
      participant_,
      [this](const ::sarloc::VictimEstimate& e, const auto& info) {
        try {
          auto estimate = to_core(e);
          if (!admitted(info.publication_handle, speaker_claim(e))) return;
          // The writer tells the daemon's estimates from a device's own: two estimators of one
          // source, which VictimFusion holds to agreeing with each other.
          std::string writer = handle_text(info.publication_handle);
          spdlog::debug("estimate {}/{} status {} stamp {} from writer {} relative ({:.2f}, {:.2f}, {:.2f})",
                        estimate.rescuer_id, estimate.signal_id, static_cast<int>(estimate.status), estimate.stamp,
                        writer, estimate.relative.position.x(), estimate.relative.position.y(),
                        estimate.relative.position.z());
          const std::string subject = estimate.rescuer_id;
          enqueue(subject, [estimate = std::move(estimate), writer = std::move(writer), from_device = e.from_device(),
                            now = clock_.now()](incident::IncidentCommand& command) mutable {
            command.on_estimate(std::move(estimate), std::move(writer), from_device, now);
          });
        } catch (const InputError& error) {
          refuse_invalid(printable_id(e.rescuer_id()), std::string("victim estimate: ") + error.what());
        }
      },
      EndpointOptions::in(config_.estimate_partitions));

  ReaderEvents events;
  events.on_liveliness = [this](const auto& handle, bool alive) {
    enqueue("liveliness", [writer = handle_text(handle), alive, now = clock_.now()](incident::IncidentCommand& command) {
      command.on_writer_liveliness(writer, alive, now);
    });
  };
  // A device that stops in order disposes its own position instance before its writer goes
  // (sign_off.hpp): signed off, not lost.
  events.on_instance_gone = [this](const auto& info) {
    if (info.instance_state != eprosima::fastdds::dds::NOT_ALIVE_DISPOSED_INSTANCE_STATE) return;
    enqueue("disposal", [writer = handle_text(info.publication_handle), now = clock_.now()](
                            incident::IncidentCommand& command) { command.on_writer_disposed(writer, now); });
  };
  const auto on_position = [this](const ::sarloc::ResponderPosition& p, const auto& info) {
    try {
      auto position = to_core(p);
      if (!admitted(info.publication_handle, speaker_claim(p))) return;
      const std::string subject = position.responder_id;
      enqueue(subject, [position = std::move(position), writer = handle_text(info.publication_handle),
                        now = clock_.now()](incident::IncidentCommand& command) {
        command.on_position(position, writer, now);
      });
    } catch (const InputError& error) {
      refuse_invalid(printable_id(p.responder_id()), error.what());
    }
  };
  position_reader_ = std::make_unique<Reader<::sarloc::ResponderPosition>>(participant_, on_position, EndpointOptions{}, events);
  // Devices' own writers also match this MANUAL_BY_TOPIC reader, whose liveliness reports a
  // killed device within its 3 s lease (the AUTOMATIC one waits for the participant's).
  device_position_reader_ =
      std::make_unique<Reader<::sarloc::ResponderPosition>>(participant_, on_position, device_position_options(true), events);

  responder_alarm_reader_ = std::make_unique<Reader<::sarloc::ResponderAlarm>>(
      participant_, [this](const ::sarloc::ResponderAlarm& a, const auto& info) {
        try {
          auto alarm = to_core(a);
          // A mayday "for r1" counts only from r1's own device.
          if (!admitted(info.publication_handle, speaker_claim(a))) return;
          const std::string subject = alarm.responder_id;
          enqueue(subject, [alarm = std::move(alarm), now = clock_.now()](incident::IncidentCommand& command) {
            command.on_device_alarm(alarm, now);
          });
        } catch (const InputError& error) {
          refuse_invalid(printable_id(a.responder_id()), std::string("responder alarm: ") + error.what());
        }
      });
  acknowledgement_reader_ = std::make_unique<Reader<::sarloc::AlarmAcknowledgement>>(
      participant_, [this](const ::sarloc::AlarmAcknowledgement& ack, const auto&) {
        enqueue(printable_id(ack.operator_id()),
                [alarm_id = ack.alarm_id(), operator_id = ack.operator_id().to_string(), stamp = ack.stamp(),
                 now = clock_.now()](incident::IncidentCommand& command) {
                  command.on_acknowledgement(alarm_id, operator_id, stamp, now);
                });
      });
  // An operator's or a finder device's word that a victim is dug out. Under DDS Security the
  // governance lets only dashboards and devices write it (deploy/security/make-certs.sh).
  recovery_reader_ = std::make_unique<Reader<::sarloc::VictimRecovery>>(
      participant_, [this](const ::sarloc::VictimRecovery& r, const auto&) {
        enqueue(printable_id(r.reported_by()),
                [victim_id = r.victim_id(), reported_by = r.reported_by().to_string(), stamp = r.stamp(),
                 now = clock_.now()](incident::IncidentCommand& command) {
                  command.on_recovery(victim_id, reported_by, stamp, now);
                });
      });
  dig_order_reader_ =
      std::make_unique<Reader<::sarloc::DigOrder>>(participant_, [this](const ::sarloc::DigOrder& order, const auto&) {
        enqueue(printable_id(order.operator_id()),
                [incident_id = order.incident_id().to_string(), victim_ids = order.victim_ids(),
                 operator_id = order.operator_id().to_string()](incident::IncidentCommand& command) {
                  command.on_dig_order(incident_id, victim_ids, operator_id);
                });
      });
  // An operator's outline of the deposit; incident command checks it (a simple polygon).
  deposit_reader_ = std::make_unique<Reader<::sarloc::DepositDrawing>>(
      participant_, [this](const ::sarloc::DepositDrawing& drawing, const auto&) {
        std::vector<incident::Vec2> outline;
        for (const auto& p : drawing.outline()) outline.emplace_back(p.x(), p.y());
        enqueue(printable_id(drawing.operator_id()),
                [incident_id = drawing.incident_id().to_string(), outline = std::move(outline),
                 operator_id = drawing.operator_id().to_string()](incident::IncidentCommand& command) {
                  command.on_deposit_drawing(incident_id, outline, operator_id);
                });
      });
}

void CommandNode::create_picture_readers() {
  // The picture as the active instance publishes it. Exclusive ownership: these readers deliver
  // the strongest live writer's samples only, so another instance's summary here means that one
  // is active and outranks this one (incident::StandbyArbiter). Own samples come back too and
  // are ignored.
  ReaderEvents summary_events;
  summary_events.on_liveliness = [this](const auto& handle, bool alive) {
    if (alive) return;
    enqueue("picture", [writer = handle_text(handle), wall = MissionClock::wall_now_ns()](
                           incident::IncidentCommand& command) { command.on_peer_lost(writer, wall); });
    wake_.store(true);
  };
  summary_reader_ = std::make_unique<Reader<::sarloc::IncidentSummary>>(
      participant_,
      [this](const ::sarloc::IncidentSummary&, const auto& info) {
        if (participant_->is_own_writer(info.publication_handle)) return;
        enqueue("picture", [writer = handle_text(info.publication_handle), wall = MissionClock::wall_now_ns()](
                               incident::IncidentCommand& command) { command.on_peer_summary(writer, wall); });
      },
      EndpointOptions{}, summary_events);

  ReaderEvents victim_events;
  victim_events.on_instance_gone = [this](const auto& info) {
    // Merged away. (Its writer lost: NOT_ALIVE_NO_WRITERS, the victim stays.)
    if (info.instance_state != eprosima::fastdds::dds::NOT_ALIVE_DISPOSED_INSTANCE_STATE) return;
    if (participant_->is_own_writer(info.publication_handle)) return;
    const auto id = victim_id_of(info.instance_handle);
    if (!id) return;
    enqueue("picture", [id = *id](incident::IncidentCommand& command) { command.on_peer_victim_disposed(id); });
  };
  picture_victim_reader_ = std::make_unique<Reader<::sarloc::FusedVictim>>(
      participant_,
      [this](const ::sarloc::FusedVictim& v, const auto& info) {
        if (participant_->is_own_writer(info.publication_handle)) return;
        try {
          enqueue("picture", [victim = to_core(v)](incident::IncidentCommand& command) mutable {
            command.on_peer_victim(std::move(victim));
          });
        } catch (const InputError& error) {
          refuse_invalid("picture", std::string("adopted victim: ") + error.what());
        }
      },
      EndpointOptions{}, victim_events);
  picture_team_reader_ = std::make_unique<Reader<::sarloc::TeamStatus>>(
      participant_, [this](const ::sarloc::TeamStatus& t, const auto& info) {
        if (participant_->is_own_writer(info.publication_handle)) return;
        try {
          enqueue("picture", [team = to_core(t)](incident::IncidentCommand& command) mutable {
            command.on_peer_team(std::move(team));
          });
        } catch (const InputError& error) {
          refuse_invalid("picture", std::string("adopted team: ") + error.what());
        }
      });
  picture_frame_reader_ = std::make_unique<Reader<::sarloc::IncidentFrame>>(
      participant_, [this](const ::sarloc::IncidentFrame& f, const auto& info) {
        if (participant_->is_own_writer(info.publication_handle)) return;
        enqueue("picture",
                [frame = to_core(f)](incident::IncidentCommand& command) { command.on_peer_frame(frame); });
      });
  picture_plan_reader_ = std::make_unique<Reader<::sarloc::SearchPlan>>(
      participant_, [this](const ::sarloc::SearchPlan& p, const auto& info) {
        if (participant_->is_own_writer(info.publication_handle)) return;
        try {
          enqueue("picture", [plan = to_core(p)](incident::IncidentCommand& command) mutable {
            command.on_peer_search_plan(std::move(plan));
          });
        } catch (const InputError& error) {
          refuse_invalid("picture", std::string("adopted search plan: ") + error.what());
        }
      });

  ReaderEvents alarm_events;
  alarm_events.on_instance_gone = [this](const auto& info) {
    if (info.instance_state != eprosima::fastdds::dds::NOT_ALIVE_DISPOSED_INSTANCE_STATE) return;
    if (participant_->is_own_writer(info.publication_handle)) return;
    const auto id = alarm_id_of(info.instance_handle);
    if (!id) return;
    enqueue("picture", [id = *id](incident::IncidentCommand& command) { command.on_peer_alarm_disposed(id); });
  };
  picture_alarm_reader_ = std::make_unique<Reader<::sarloc::IncidentAlarm>>(
      participant_,
      [this](const ::sarloc::IncidentAlarm& a, const auto& info) {
        if (participant_->is_own_writer(info.publication_handle)) return;
        try {
          enqueue("picture", [alarm = to_core(a)](incident::IncidentCommand& command) mutable {
            command.on_peer_alarm(std::move(alarm));
          });
        } catch (const InputError& error) {
          refuse_invalid("picture", std::string("adopted alarm: ") + error.what());
        }
      },
      EndpointOptions{}, alarm_events);
}

void CommandNode::enqueue(const std::string& subject, Input input) {
  {
    std::lock_guard<std::mutex> lock(inbox_mutex_);
    if (inbox_.size() < kInboxLimit) {
      inbox_.push_back(std::move(input));
      return;
    }
  }
  counters_.rejected("inbox_full");
  warnings_.warn(subject, "inbox_full",
                 config_.node_id + ": " + std::to_string(kInboxLimit) + " inputs wait for the next cycle: sample dropped");
}

bool CommandNode::admitted(const eprosima::fastrtps::rtps::InstanceHandle_t& writer, const SpeakerClaim& claim) {
  if (admits(authority_, writer, claim)) return true;
  counters_.rejected("unauthorized_writer");
  warnings_.warn(claim.responder_id, "unauthorized_writer", refusal(authority_, writer, claim));
  return false;
}

void CommandNode::refuse_invalid(const std::string& subject, const std::string& what) {
  counters_.rejected("invalid_value");
  warnings_.warn(subject, "invalid_value", what);
}

void CommandNode::cycle() {
  const TimestampNs now = clock_.now();
  std::vector<Input> inputs;
  {
    std::lock_guard<std::mutex> lock(inbox_mutex_);
    inputs.swap(inbox_);
  }
  incident::CommandCycle out;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto& input : inputs) input(command_);
    out = command_.cycle(now, MissionClock::wall_now_ns());
  }
  if (out.role_change) apply(*out.role_change);
  log(out);

  static thread_local ProcessStats stats;
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
  if (out.active) publish(out);  // a standby publishes no picture
}

void CommandNode::log(const incident::CommandCycle& out) {
  for (std::size_t k = 0; k < out.estimates_fused; ++k) counters_.accepted();
  for (const auto& event : out.events) {
    using Kind = incident::IncidentEvent::Kind;
    switch (event.kind) {
      case Kind::kDebug: spdlog::debug("{}: {}", config_.node_id, event.text); break;
      case Kind::kInfo: spdlog::info("{}: {}", config_.node_id, event.text); break;
      case Kind::kWarning: spdlog::warn("{}: {}", config_.node_id, event.text); break;
      case Kind::kError: spdlog::error("{}: {}", config_.node_id, event.text); break;
      case Kind::kRejected:
        counters_.rejected(event.reason);
        warnings_.warn(event.subject, event.reason, config_.node_id + ": " + event.text);
        break;
    }
  }
  if (spdlog::should_log(spdlog::level::trace)) {
    for (const auto& v : out.victims) {
      std::string sources;
      for (const auto& src : v.sources) sources += " " + src.rescuer_id + "/" + std::to_string(src.signal_id);
      spdlog::trace("victim {} state {} at ({:.2f}, {:.2f}, {:.2f}) sources{}", v.victim_id, static_cast<int>(v.state),
                    v.position.position.x(), v.position.position.y(), v.position.position.z(), sources);
    }
  }
}

void CommandNode::publish(const incident::CommandCycle& out) {
  for (const auto id : out.disposed_victims) {
    ::sarloc::FusedVictim key;
    key.victim_id(id);
    if (!victim_writer_.dispose(key)) spdlog::error("{}: cannot dispose of victim {}", config_.node_id, id);
  }
  // A refused write is never silent: past a topic's max_instances Fast DDS refuses new keys.
  std::size_t refused_victims = 0, refused_teams = 0, refused_alarms = 0;
  for (const auto& v : out.victims) {
    try {
      if (!victim_writer_.write(to_idl(v))) ++refused_victims;
    } catch (const InputError& e) {
      spdlog::error("cannot publish victim {}: {}", v.victim_id, e.what());
    }
  }
  for (const auto& t : out.teams) {
    try {
      if (!team_writer_.write(to_idl(t))) ++refused_teams;
    } catch (const InputError& e) {
      spdlog::error("cannot publish team '{}': {}", t.team_id, e.what());
    }
  }
  for (const auto id : out.disposed_alarms) {
    ::sarloc::IncidentAlarm key;
    key.alarm_id(id);
    if (!alarm_writer_.dispose(key)) spdlog::error("{}: cannot dispose of alarm {}", config_.node_id, id);
  }
  for (const auto& a : out.alarms) {
    try {
      if (!alarm_writer_.write(to_idl(a))) ++refused_alarms;
    } catch (const InputError& e) {
      spdlog::error("cannot publish alarm {}: {}", a.alarm_id, e.what());
    }
  }
  if (refused_victims + refused_teams + refused_alarms > 0) {
    warnings_.warn(config_.node_id, "picture_write_refused",
                   fmt::format("{}: DDS refused {} of {} victims, {} of {} teams, {} of {} alarms (history or "
                               "max_instances full)",
                               config_.node_id, refused_victims, out.victims.size(), refused_teams, out.teams.size(),
                               refused_alarms, out.alarms.size()));
  }
  ::sarloc::IncidentSummary summary;
  summary.incident_id(config_.incident.incident_id);
  summary.stamp(out.stamp);
  summary.victims_total(out.counts.victims_total);
  summary.victims_located(out.counts.victims_located);
  summary.victims_found(out.counts.victims_found);
  summary.responders_total(out.counts.responders_total);
  summary.responders_link_lost(out.counts.responders_link_lost);
  summary_writer_.write(summary);
  // Every cycle: a reader that still counted the previous active instance alive when this one
  // took over dropped its first frame.
  frame_writer_.write(to_idl(out.frame));
  if (out.search_plan) {
    try {
      plan_writer_.write(to_idl(*out.search_plan));
    } catch (const InputError& e) {
      spdlog::error("{}: cannot publish the search plan: {}", config_.node_id, e.what());
    }
  }
  assert_picture_liveliness();
}

void CommandNode::apply(const incident::RoleChange& change) {
  try {
    victim_writer_.set_ownership_strength(change.strength);
    team_writer_.set_ownership_strength(change.strength);
    summary_writer_.set_ownership_strength(change.strength);
    frame_writer_.set_ownership_strength(change.strength);
    plan_writer_.set_ownership_strength(change.strength);
    alarm_writer_.set_ownership_strength(change.strength);
  } catch (const DdsError& error) {  // publishes anyway: readers take it once no stronger one is alive
    spdlog::error("{}: {}", config_.node_id, error.what());
  }
}

void CommandNode::assert_picture_liveliness() {
  if (role() != incident::CommandRole::kActive) return;
  victim_writer_.assert_liveliness();
  team_writer_.assert_liveliness();
  summary_writer_.assert_liveliness();
  frame_writer_.assert_liveliness();
  plan_writer_.assert_liveliness();
  alarm_writer_.assert_liveliness();
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
  picture_plan_reader_.reset();
  picture_alarm_reader_.reset();
  responder_alarm_reader_.reset();
  acknowledgement_reader_.reset();
  recovery_reader_.reset();
  dig_order_reader_.reset();
  deposit_reader_.reset();
  stopping_.store(true);
  if (thread_.joinable()) thread_.join();
  if (role() != incident::CommandRole::kActive) return;
  // A clean stop: every reader gets the last picture and disposals before the writers go. (Seen
  // with Fast DDS 2.9: a reader takes no other writer's disposal of a deleted writer's instance.)
  const auto wait = std::chrono::milliseconds(500);
  if (!victim_writer_.wait_for_acknowledgments(wait) || !team_writer_.wait_for_acknowledgments(wait) ||
      !summary_writer_.wait_for_acknowledgments(wait) || !frame_writer_.wait_for_acknowledgments(wait) ||
      !plan_writer_.wait_for_acknowledgments(wait) || !alarm_writer_.wait_for_acknowledgments(wait)) {
    spdlog::warn("{}: stopping before every reader acknowledged the last picture", config_.node_id);
  }
}

std::vector<incident::IncidentAlarm> CommandNode::alarms() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return command_.alarms();
}

incident::CommandRole CommandNode::role() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return command_.role();
}

std::vector<incident::FusedVictim> CommandNode::victims() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return command_.victims();
}

std::vector<incident::TeamStatus> CommandNode::teams() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return command_.teams();
}

}  // namespace sarloc::dds
