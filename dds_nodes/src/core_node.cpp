#include "sarloc/dds/core_node.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <functional>
#include <optional>
#include <set>
#include <type_traits>
#include <variant>
#include <vector>

#include "sarloc/core/common/identifier.hpp"
#include "sarloc/core/common/validate.hpp"
#include "sarloc/core/incident/signal_pursuit.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/handover_message.hpp"
#include "sarloc/dds/mission_clock.hpp"
#include "sarloc/dds/process_stats.hpp"
#include "sarloc/dds/return_code.hpp"
#include "sarloc/dds/sign_off.hpp"
#include "sarloc/dds/speaker_claim.hpp"

namespace sarloc::dds {

namespace {

// A third of the writer's lifespan: its last position is written again long before it expires.
std::unique_ptr<estimator::PositionRefresh> refresh_within_lifespan(Writer<::sarloc::ResponderPosition>& writer) {
  const auto& life = writer.get()->get_qos().lifespan().duration;
  if (life == eprosima::fastrtps::c_TimeInfinite) return nullptr;
  const auto lifespan = std::chrono::seconds(life.seconds) + std::chrono::nanoseconds(life.nanosec);
  return std::make_unique<estimator::PositionRefresh>(
      std::max<std::chrono::steady_clock::duration>(lifespan / 3, std::chrono::milliseconds(100)));
}

// The roster as configured, with the firefighters whose teams reported an entry: their first
// step starts their filter at the door, however busy the daemon (responder_roster.hpp).
estimator::ResponderRosterConfig roster_with_door_starts(const CoreNodeConfig& config) {
  estimator::ResponderRosterConfig roster = config.roster;
  for (const auto& [id, start] : config.estimators.firefighter.entry_of) {
    const auto role = config.roles.find(id);
    if (!start.entry.empty() &&
        (role == config.roles.end() ? config.default_role : role->second) == estimator::ResponderRole::kFirefighter) {
      roster.door_starts.push_back(id);
    }
  }
  return roster;
}

}  // namespace

void CoreNodeConfig::validate() const {
  estimators.validate();
  roster.validate();
  busy.validate();
  if (node_id.empty() || node_id.size() > 64) throw ConfigError("core.node_id = '" + node_id + "': must be 1-64 characters");
  if (workers < 1 || workers > 64) throw ConfigError("core.workers = " + config_value(workers) + ": must be in [1, 64]");
  if (queue_limit < 16) throw ConfigError("core.queue_limit = " + config_value(queue_limit) + ": must be >= 16");
  if (!(status_period_s > 0.0 && status_period_s <= 60.0)) {
    throw ConfigError("core.status_period_s = " + config_value(status_period_s) + ": must be in (0, 60]");
  }
  if (!(odometry_wait_s >= 0.0 && odometry_wait_s <= 10.0)) {
    throw ConfigError("core.odometry_wait_s = " + config_value(odometry_wait_s) + ": must be in [0, 10]");
  }
  if (!(warning_interval_s >= 0.0 && warning_interval_s <= 3600.0)) {
    throw ConfigError("core.warning_interval_s = " + config_value(warning_interval_s) + ": must be in [0, 3600]");
  }
  for (const auto& p : partitions) {
    if (p.empty()) throw ConfigError("core.partitions contains an empty name");
  }
  if (handover_journal_entries > ::sarloc::HANDOVER_ENTRIES_MAX) {
    throw ConfigError("core.handover_journal_entries = " + config_value(handover_journal_entries) +
                      ": must be in [0, " + std::to_string(::sarloc::HANDOVER_ENTRIES_MAX) +
                      "] (the most a rescuer_handover carries)");
  }
}

CoreNode::CoreNode(std::shared_ptr<Participant> participant, CoreNodeConfig config)
    : config_((config.validate(), std::move(config))),
      participant_(std::move(participant)),
      // Devices and incident command believe this daemon's estimates by its certificate's name.
      authority_((require_identity(*participant_, config_.node_id, "core.node_id"), participant_)),
      warnings_(std::chrono::milliseconds(static_cast<std::int64_t>(config_.warning_interval_s * 1000.0))),
      roster_(roster_with_door_starts(config_)),
      busy_gate_(config_.busy),
      estimate_writer_(participant_, EndpointOptions::in(config_.partitions)),
      guidance_writer_(participant_, EndpointOptions::in(config_.partitions)),
      position_writer_(participant_),
      candidates_writer_(participant_),
      position_refresh_(refresh_within_lifespan(position_writer_)),
      status_writer_(participant_),
      handover_writer_(participant_) {
  for (unsigned i = 0; i < config_.workers; ++i) {
    workers_.push_back(std::make_unique<Worker>());
    Worker& w = *workers_.back();
    w.thread = std::thread([this, &w] { run_worker(w); });
  }
  load_noted_at_ = std::chrono::steady_clock::now();
  status_thread_ = std::thread([this] {
    while (!stopping_.load()) {
      note_worker_load();
      publish_status();
      refresh_silent_positions();
      evict_idle();
      const auto period = std::chrono::milliseconds(static_cast<std::int64_t>(config_.status_period_s * 1000.0));
      const auto until = std::chrono::steady_clock::now() + period;
      while (!stopping_.load() && std::chrono::steady_clock::now() < until) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
    }
  });

  // Readers last: they call back as soon as they exist. If one cannot be created, the
  // threads above must be stopped before the exception leaves (a joinable std::thread
  // destroyed by unwinding would terminate the process instead of reporting the error).
  try {
    auto inputs = EndpointOptions::in(config_.partitions);
    // The roster decides inside DDS, before the reader's history: a publisher cycling through
    // ids it refuses takes no instance there (responder_filter.hpp).
    inputs.admit_responder = [this](const ResponderSample& sample) { return admit(sample); };
    // Listener callbacks: convert, refuse what cannot even be converted, enqueue.
    auto refuse = [this](const std::string& id, const std::string& reason, const std::string& detail) {
      reject(id, reason, detail);
    };
    sample_readers_ = std::make_unique<SampleReaders>(
        participant_, authority_,
        [this](estimator::SensorSample s) {
          const std::string id = estimator::responder_of(s);  // copied: `s` is moved below
          enqueue(id, std::move(s));
        },
        refuse, inputs);
    odometry_reader_ = std::make_unique<Reader<::sarloc::Odometry>>(
        participant_,
        [this, refuse](const ::sarloc::Odometry& o, const auto& info) {
          try {
            auto odometry = to_core(o);
            const SpeakerClaim claim = speaker_claim(o);
            if (!admits(authority_, info.publication_handle, claim)) {
              refuse(claim.responder_id, "unauthorized_writer", refusal(authority_, info.publication_handle, claim));
              return;
            }
            enqueue(claim.responder_id, std::move(odometry));
          } catch (const InputError& e) {
            refuse(printable_id(o.rescuer_id()), "invalid_value", e.what());
          }
        },
        inputs);
    // Victims incident command declares found: stop guiding this sector's responders to them.
    victim_reader_ = std::make_unique<Reader<::sarloc::FusedVictim>>(
        participant_, [this](const ::sarloc::FusedVictim& v, const auto&) {
          if (v.state() != ::sarloc::VICTIM_FOUND && v.state() != ::sarloc::VICTIM_RECOVERED) return;
          for (const auto& source : v.sources()) {
            const std::string id = source.rescuer_id().to_string();
            if (!is_identifier(id)) continue;  // no rescuer of ours: nothing to stop
            enqueue(id, MarkDone{id, source.signal_id()});
          }
        });
    // Victims incident command sends another rescuer to (one rescuer per victim): the same
    // rule as on the device, so that daemon and device guide alike.
    plan_reader_ = std::make_unique<Reader<::sarloc::SearchPlan>>(
        participant_, [this](const ::sarloc::SearchPlan& p, const auto&) {
          incident::SearchPlanPicture plan;
          try {
            plan = to_core(p);
          } catch (const InputError& e) {
            reject("incident command", "invalid_value", std::string("search plan: ") + e.what());
            return;
          }
          std::set<std::string> now_handed;
          for (const auto& h : plan.handed_over) now_handed.insert(h.rescuer_id);
          std::set<std::string> affected = now_handed;
          affected.insert(handed_over_rescuers_.begin(), handed_over_rescuers_.end());
          for (const auto& id : affected) {
            enqueue(id, LeaveToOthers{id, incident::signals_left_to_others(plan.handed_over, id),
                                      plan.stamp + incident::kHandOverLapseNs});
          }
          handed_over_rescuers_ = std::move(now_handed);
        });
    // The devices' own positions (their dead reckoning): where a firefighter is when this daemon
    // meets him mid-search. Only for responders it serves already; never at a sample's cost.
    device_position_reader_ = std::make_unique<Reader<::sarloc::ResponderPosition>>(
        participant_,
        [this](const ::sarloc::ResponderPosition& p, const auto& info) {
          if (p.source() != ::sarloc::POSITION_DEAD_RECKONING || participant_->is_own_writer(info.publication_handle))
            return;
          try {
            auto own = to_core(p);
            if (!admits(authority_, info.publication_handle, speaker_claim(p))) return;
            const std::string id = own.responder_id;
            enqueue_hint(id, PositionHint{std::move(own)});
          } catch (const InputError&) {
            // a device's position this daemon cannot read starts nothing; incident command reports it
          }
        },
        device_position_options(true));
    if (config_.handover_journal_entries > 0) {
      // Other daemons' requests and journals; the worker of the responder decides.
      handover_reader_ = std::make_unique<Reader<::sarloc::RescuerHandover>>(
          participant_, [this](const ::sarloc::RescuerHandover& h, const auto& info) {
            if (participant_->is_own_writer(info.publication_handle)) return;
            const std::string id = h.responder_id().to_string();
            const std::string from = h.from_node().to_string();
            if (!is_identifier(id) || !is_identifier(from) || from == config_.node_id) return;
            // Only the mission's core daemons hand responders over (when the mission names them),
            // and with DDS Security only the identity CN=from_node speaks as it: a device's
            // identity asking for a rescuer's estimator would have it released from his daemon.
            const auto& cores = participant_->config().core_node_ids;
            if (!cores.empty() && std::find(cores.begin(), cores.end(), from) == cores.end()) {
              reject(id, "unauthorized_writer",
                     "rescuer_handover from '" + from + "', which is no core daemon of the mission");
              return;
            }
            if (!authority_.admits(info.publication_handle, from, WriterAuthority::Speakers::kDevice)) {
              reject(id, "unauthorized_writer", authority_.refusal("rescuer_handover", info.publication_handle, from));
              return;
            }
            if (h.kind() == ::sarloc::HANDOVER_REQUEST) {
              enqueue(id, HandOverTo{id, from});
              return;
            }
            if (h.to_node().to_string() != config_.node_id) return;
            if (h.kind() == ::sarloc::HANDOVER_TAKEN) {
              enqueue(id, HandedOver{id, from}, /*droppable=*/false);
              return;
            }
            if (h.kind() == ::sarloc::HANDOVER_UNAVAILABLE) {
              spdlog::warn(
                  "{}: '{}' cannot hand over the estimator of '{}' (its journal overflowed): it goes on afresh here",
                  config_.node_id, from, id);
              return;
            }
            try {
              enqueue(id, TakeOver{id, from, journal_of(h)}, /*droppable=*/false);
            } catch (const InputError& e) {
              reject(id, "invalid_value", std::string("rescuer_handover from '") + from + "': " + e.what());
            }
          });
    }
  } catch (...) {
    stop_threads();
    throw;
  }
  std::string served = "the default partition";
  if (!config_.partitions.empty()) {
    served = "partition(s)";
    for (const auto& p : config_.partitions) served += " " + p;
  }
  spdlog::info("{}: serving {} with {} worker(s)", config_.node_id, served, config_.workers);
}

CoreNode::~CoreNode() {
  stop();  // then (implicitly) the writers
}

bool CoreNode::sign_off(std::chrono::milliseconds timeout) {
  stop();  // no status is written after the disposal
  return dds::sign_off(status_writer_, config_.node_id, timeout);
}

void CoreNode::stop() {
  // The inflow first, then the threads.
  sample_readers_.reset();
  odometry_reader_.reset();
  victim_reader_.reset();
  plan_reader_.reset();  // its callback uses handed_over_rescuers_ (declared before the readers)
  device_position_reader_.reset();
  handover_reader_.reset();
  stop_threads();
}

void CoreNode::stop_threads() {
  if (stopping_.exchange(true)) return;  // stopped already (sign_off)
  for (auto& w : workers_) {
    {
      std::lock_guard<std::mutex> lock(w->mutex);
    }
    w->cv.notify_all();
  }
  for (auto& w : workers_) {
    if (w->thread.joinable()) w->thread.join();
  }
  if (status_thread_.joinable()) status_thread_.join();
}

void CoreNode::reject(const std::string& rescuer_id, const std::string& reason, const std::string& detail) {
  counters_.rejected(reason);
  warnings_.warn(rescuer_id, reason, "rejected sample (" + reason + "): " + detail);
}

bool CoreNode::admit(const ResponderSample& sample) {
  const std::string& rescuer_id = sample.responder_id;
  estimator::ResponderRoster::Admission admission;
  {
    std::lock_guard<std::mutex> lock(roster_mutex_);
    const auto now = std::chrono::steady_clock::now();
    admission = roster_.admit(rescuer_id, now, busy_gate_.busy(now), sample.first_step);
  }
  if (!estimator::refused(admission)) return true;
  std::string detail = "rescuer_id = '" + rescuer_id + "': ";
  if (admission == estimator::ResponderRoster::Admission::kFull) {
    detail += "already serving max_rescuers = " + std::to_string(config_.roster.max_responders);
  } else if (admission == estimator::ResponderRoster::Admission::kBusy) {
    detail += "a new responder while the workers are busy (over core.busy_utilisation = " +
              config_value(config_.busy.max_utilisation) +
              " of a period, or a sample waited over core.busy_wait_s = " + config_value(config_.busy.max_wait_s) +
              " s): admitted once neither was seen for core.busy_hold_s = " + config_value(config_.busy.hold_s) + " s";
  } else if (admission == estimator::ResponderRoster::Admission::kPaced) {
    detail += "more new responders than core.new_rescuers_per_s = " + config_value(config_.roster.new_per_s) +
              ": admitted by a later sample";
  } else {
    detail += rescuer_id.empty() ? "empty" : "not on this daemon's roster";
  }
  reject(rescuer_id, estimator::reason_of(admission), detail);
  return false;
}

void CoreNode::evict_idle() {
  // Under the roster's lock, so that a sample admitted after the eviction is queued after it.
  std::lock_guard<std::mutex> lock(roster_mutex_);
  for (auto& id : roster_.evict_idle(std::chrono::steady_clock::now())) {
    const std::string key = id;
    enqueue(key, Evict{std::move(id)});
  }
}

CoreNode::Worker& CoreNode::worker_of(const std::string& rescuer_id) {
  return *workers_[std::hash<std::string>{}(rescuer_id) % workers_.size()];
}

std::string CoreNode::responder_of(const Work& work) {
  return std::visit(
      [](const auto& w) -> std::string {
        using T = std::decay_t<decltype(w)>;
        if constexpr (std::is_same_v<T, estimator::SensorSample>) {
          return estimator::responder_of(w);
        } else if constexpr (std::is_same_v<T, PositionHint>) {
          return w.own.responder_id;
        } else {
          return w.rescuer_id;
        }
      },
      work);
}

void CoreNode::release_newest(Worker& worker, std::chrono::steady_clock::duration waited) {
  // A backlog of `waited` drains within kDrainS once responders worth waited / kDrainS of this
  // worker's time are gone (at least a tenth, at most half: a lull or a burst misjudged by
  // either must neither release nothing nor everyone).
  constexpr double kDrainS = 5.0;
  const double waited_s = std::chrono::duration<double>(waited).count();
  double total_s = 0.0;
  for (const auto& [id, cost] : worker.cost_s) total_s += cost;
  const double to_release_s = std::clamp(waited_s / kDrainS, 0.1, 0.5) * total_s;
  std::vector<std::string> released;
  std::size_t dropped = 0;
  double released_s = 0.0;
  {
    // Under the roster's lock, as evict_idle: a sample admitted after the release is queued after it.
    std::lock_guard<std::mutex> lock(roster_mutex_);
    const auto on_this_worker = [&](const std::string& id) { return &worker_of(id) == &worker; };
    while (released.empty() || released_s < to_release_s) {
      auto id = roster_.release_newest(on_this_worker);
      if (!id) break;
      const auto cost = worker.cost_s.find(*id);
      released_s += cost == worker.cost_s.end() ? 0.0 : cost->second;
      released.push_back(std::move(*id));
    }
    if (released.empty()) return;
    std::lock_guard<std::mutex> queue_lock(worker.mutex);
    const std::set<std::string> gone(released.begin(), released.end());
    // Their samples waiting go with them: they are part of what everyone waits behind.
    for (auto it = worker.queue.begin(); it != worker.queue.end();) {
      if (gone.count(responder_of(it->work)) > 0) {
        it = worker.queue.erase(it);
        ++dropped;
      } else {
        ++it;
      }
    }
    for (const auto& id : released) worker.queue.push_front({Evict{id, true}, std::chrono::steady_clock::now()});
  }
  for (std::size_t k = 0; k < dropped; ++k) counters_.rejected("daemon_busy");
  spdlog::warn(
      "{}: overloaded: a sample waited {:.2f} s in a worker's queue (core.busy_shed_wait_s = {}): released the {} "
      "responder(s) of that worker admitted last ({:.0f} % of its time; '{}' first) and their {} waiting sample(s); "
      "their devices guide on their own filters, and each is admitted afresh once the daemon is not busy",
      config_.node_id, waited_s, config_.busy.shed_wait_s, released.size(),
      total_s > 0.0 ? 100.0 * released_s / total_s : 0.0, released.front(), dropped);
}

void CoreNode::enqueue(const std::string& rescuer_id, Work work, bool droppable) {
  Worker& w = worker_of(rescuer_id);
  bool dropped = false;
  {
    std::lock_guard<std::mutex> lock(w.mutex);
    if (droppable && w.queue.size() >= config_.queue_limit) {
      w.queue.pop_front();
      dropped = true;
    }
    w.queue.push_back({std::move(work), std::chrono::steady_clock::now()});
  }
  w.cv.notify_one();
  if (dropped) reject(rescuer_id, "overloaded", "worker queue full: dropped the oldest waiting sample");
}

void CoreNode::enqueue_hint(const std::string& rescuer_id, PositionHint hint) {
  Worker& w = worker_of(rescuer_id);
  {
    std::lock_guard<std::mutex> lock(w.mutex);
    if (w.queue.size() >= config_.queue_limit / 2) return;  // a hint never pushes a sample out
    w.queue.push_back({std::move(hint), std::chrono::steady_clock::now()});
  }
  w.cv.notify_one();
}

void CoreNode::run_worker(Worker& worker) {
  estimator::SequencerReport report;
  while (true) {
    // Sleep until work arrives or the earliest held sample's wait expires.
    std::optional<estimator::SampleSequencer::Clock::time_point> wake;
    for (const auto& [id, sequencer] : worker.responders) {
      const auto deadline = sequencer.next_deadline();
      if (deadline && (!wake || *deadline < *wake)) wake = deadline;
    }
    std::optional<Work> work;
    std::chrono::steady_clock::time_point queued_at;
    {
      std::unique_lock<std::mutex> lock(worker.mutex);
      auto ready = [&] { return stopping_.load() || !worker.queue.empty(); };
      if (wake) {
        worker.cv.wait_until(lock, *wake, ready);
      } else {
        worker.cv.wait(lock, ready);
      }
      if (stopping_.load()) return;
      if (!worker.queue.empty()) {
        queued_at = worker.queue.front().at;
        work = std::move(worker.queue.front().work);
        worker.queue.pop_front();
      }
    }
    const auto began = std::chrono::steady_clock::now();
    if (work && busy_gate_.note_wait(began - queued_at, began)) {
      spdlog::warn(
          "{}: busy: a sample waited {:.1f} ms in a worker's queue (core.busy_wait_s = {}): no new "
          "responder for {} s; those served are served on",
          config_.node_id, 1e3 * std::chrono::duration<double>(began - queued_at).count(), config_.busy.max_wait_s,
          config_.busy.hold_s);
    }
    if (work && busy_gate_.note_shed(began - queued_at, began)) release_newest(worker, began - queued_at);
    if (work) {
      handle(worker, *work);
      worker.cost_s[responder_of(*work)] +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
    }
    const auto now = std::chrono::steady_clock::now();
    if (now - worker.cost_halved_at >= std::chrono::seconds(1)) {
      worker.cost_halved_at = now;
      for (auto it = worker.cost_s.begin(); it != worker.cost_s.end();) {
        it->second *= 0.5;
        it = worker.responders.count(it->first) > 0 ? std::next(it) : worker.cost_s.erase(it);
      }
    }
    for (auto& [id, sequencer] : worker.responders) sequencer.release(now, report);
    publish(report);
    worker.busy_ns.fetch_add(
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - began).count());
  }
}

void CoreNode::note_worker_load() {
  const auto now = std::chrono::steady_clock::now();
  const double span_ns =
      static_cast<double>(std::chrono::duration_cast<std::chrono::nanoseconds>(now - load_noted_at_).count());
  load_noted_at_ = now;
  double busiest = 0.0;
  for (auto& w : workers_) {
    const std::int64_t busy = w->busy_ns.load();
    if (span_ns > 0.0) busiest = std::max(busiest, static_cast<double>(busy - w->busy_noted_ns) / span_ns);
    w->busy_noted_ns = busy;
  }
  if (busy_gate_.note_utilisation(busiest, now)) {
    spdlog::warn(
        "{}: busy: a worker was busy {:.0f} % of the last {:.1f} s (core.busy_utilisation = {}): no new "
        "responder for {} s; those served are served on",
        config_.node_id, 100.0 * busiest, 1e-9 * span_ns, config_.busy.max_utilisation, config_.busy.hold_s);
  }
}

estimator::SampleSequencer& CoreNode::sequencer_for(Worker& worker, const std::string& rescuer_id) {
  // The roster admitted this id before its sample was queued (CoreNode::admit).
  if (auto it = worker.responders.find(rescuer_id); it != worker.responders.end()) return it->second;
  const auto role_it = config_.roles.find(rescuer_id);
  const auto role = role_it == config_.roles.end() ? config_.default_role : role_it->second;
  rescuers_served_.fetch_add(1);
  spdlog::info("{}: new responder '{}' ({})", config_.node_id, rescuer_id, estimator::to_string(role));
  const auto wait = std::chrono::duration_cast<estimator::SampleSequencer::Clock::duration>(
      std::chrono::duration<double>(config_.odometry_wait_s));
  auto estimator = estimator::make_estimator(role, rescuer_id, config_.estimators);
  if (config_.handover_journal_entries > 0) {
    estimator = std::make_unique<estimator::JournaledEstimator>(std::move(estimator), config_.handover_journal_entries);
    // Whoever holds this responder's estimator (the daemon of the sector it came from) hands it
    // over; meanwhile this one runs from scratch, and the journal, when it comes, takes its place.
    if (!handover_writer_.write(handover_request(rescuer_id, config_.node_id, MissionClock::wall_now_ns()))) {
      spdlog::error("{}: DDS refused the hand-over request for '{}'", config_.node_id, rescuer_id);
    }
  }
  return worker.responders.emplace(rescuer_id, estimator::SampleSequencer(std::move(estimator), wait)).first->second;
}

void CoreNode::drop_state(Worker& worker, std::map<std::string, estimator::SampleSequencer>::iterator it) {
  active_filters_.fetch_sub(it->second.estimator().active_filters());
  worker.responders.erase(it);
}

bool CoreNode::straggler(Worker& worker, const std::string& rescuer_id, TimestampNs stamp) {
  const auto it = worker.handed_away.find(rescuer_id);
  if (it == worker.handed_away.end()) return false;
  if (stamp <= it->second) {
    counters_.rejected("handed_over");
    warnings_.warn(rescuer_id, "handed_over",
                   "rejected sample (handed_over): rescuer '" + rescuer_id + "': stamp " + std::to_string(stamp) +
                       " is no later than its hand-over to another sector's daemon");
    return true;
  }
  // It came back: served on with the state still here (the other daemon's TAKEN is then
  // ignored), or, released already, a new responder here, which asks for its estimator.
  worker.handed_away.erase(it);
  return false;
}

void CoreNode::hand_over(Worker& worker, const HandOverTo& request) {
  const auto it = worker.responders.find(request.rescuer_id);
  if (it == worker.responders.end()) return;  // not here: another daemon's, or none
  const auto* journaled = dynamic_cast<const estimator::JournaledEstimator*>(&it->second.estimator());
  if (journaled == nullptr) return;
  // Samples still waiting for their odometry go in first (with unknown motion in its place):
  // the device sends the rest to the other daemon now, so they would reach no estimator.
  estimator::SequencerReport report;
  it->second.release(estimator::SampleSequencer::Clock::time_point::max(), report);
  publish(report);
  const estimator::EstimatorJournal& journal = journaled->journal();
  ::sarloc::RescuerHandover message;
  try {
    message = handover_journal(journal, config_.node_id, request.to_node, MissionClock::wall_now_ns());
  } catch (const InputError& e) {
    spdlog::error("{}: cannot hand the estimator of '{}' to '{}': {}", config_.node_id, request.rescuer_id,
                  request.to_node, e.what());
    return;
  }
  if (!handover_writer_.write(message)) {
    spdlog::error("{}: DDS refused the hand-over of '{}' to '{}': it stays here", config_.node_id, request.rescuer_id,
                  request.to_node);
    return;
  }
  if (journal.overflowed) {
    spdlog::warn(
        "{}: '{}' met '{}', whose journal overflowed (core.handover_journal_entries = {}): it starts afresh there",
        config_.node_id, request.to_node, request.rescuer_id, config_.handover_journal_entries);
    return;  // its state stays here until idle
  }
  // The state stays until the other daemon says it took the responder over (HANDOVER_TAKEN):
  // a journal lost on the way, or refused there, leaves the search here, not nowhere.
  spdlog::info("{}: handed '{}' to '{}' ({} calls); its state here goes once taken over", config_.node_id,
               request.rescuer_id, request.to_node, journal.entries.size());
  worker.handed_away[request.rescuer_id] = estimator::reach_of(journal).latest;
}

void CoreNode::release_handed(Worker& worker, const HandedOver& taken) {
  const auto it = worker.responders.find(taken.rescuer_id);
  // Came back since (straggler() forgot the hand-over) or gone already: nothing to release.
  if (it == worker.responders.end() || worker.handed_away.count(taken.rescuer_id) == 0) return;
  {
    // Under the roster's lock, as evict_idle: a sample admitted after the release is queued after it.
    std::lock_guard<std::mutex> lock(roster_mutex_);
    roster_.release(taken.rescuer_id);
    drop_state(worker, it);
  }
  if (position_refresh_) position_refresh_->forget(taken.rescuer_id);  // the new daemon writes his positions
  handed_over_.fetch_add(1);
  spdlog::info("{}: '{}' took '{}' over: its state here is released", config_.node_id, taken.by_node, taken.rescuer_id);
}

void CoreNode::take_over(Worker& worker, TakeOver& handed) {
  const auto it = worker.responders.find(handed.rescuer_id);
  if (it == worker.responders.end()) return;  // asked for and gone since (idle, released): nothing to resume
  const auto* own = dynamic_cast<const estimator::JournaledEstimator*>(&it->second.estimator());
  if (own == nullptr) return;
  if (handed.journal.role != own->role()) {
    reject(handed.rescuer_id, "invalid_value",
           "rescuer_handover from '" + handed.from_node + "': the journal of a " +
               estimator::to_string(handed.journal.role) + ", here a " + estimator::to_string(own->role()) +
               "; it goes on afresh here");
    return;
  }
  const auto began = std::chrono::steady_clock::now();
  estimator::MergedEstimator merged;
  try {
    merged = estimator::resume_with_newer(handed.journal, own->journal(), config_.estimators,
                                          config_.handover_journal_entries);
  } catch (const Error& e) {  // a refused entry, or a configuration that cannot make its estimator
    reject(handed.rescuer_id, "invalid_value",
           "rescuer_handover from '" + handed.from_node + "': " + std::string(e.what()) + "; it goes on afresh here");
    return;
  }
  const auto taken = [&] {
    if (!handover_writer_.write(
            handover_taken(handed.rescuer_id, config_.node_id, handed.from_node, MissionClock::wall_now_ns()))) {
      spdlog::error("{}: DDS refused to tell '{}' that '{}' was taken over", config_.node_id, handed.from_node,
                    handed.rescuer_id);
    }
  };
  if (!merged.estimator) {
    spdlog::warn(
        "{}: the journal of '{}' from '{}' is not its estimator any more (the device numbers its steps or "
        "samples afresh: it restarted): it goes on afresh here",
        config_.node_id, handed.rescuer_id, handed.from_node);
    taken();  // the old session's state is of no use there either
    return;
  }
  const std::size_t filters_before = it->second.estimator().active_filters();
  const auto reach = estimator::reach_of(handed.journal);
  it->second.replace_estimator(std::move(merged.estimator), reach.odometry_until, reach.measured_at);
  active_filters_.fetch_add(it->second.estimator().active_filters() - filters_before);
  taken_over_.fetch_add(1);
  taken();
  spdlog::info(
      "{}: took '{}' over from '{}': {} calls replayed and {} of its own since ({} within the journal) in {:.1f} ms",
      config_.node_id, handed.rescuer_id, handed.from_node, handed.journal.entries.size(), merged.applied,
      merged.skipped, 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count());
}

void CoreNode::handle(Worker& worker, Work& work) {
  estimator::SequencerReport report;
  if (auto* done = std::get_if<MarkDone>(&work)) {
    if (auto it = worker.responders.find(done->rescuer_id); it != worker.responders.end()) {
      it->second.estimator().mark_done(done->signal_id);
    }
    return;
  }
  if (auto* leave = std::get_if<LeaveToOthers>(&work)) {
    if (auto it = worker.responders.find(leave->rescuer_id); it != worker.responders.end()) {
      it->second.estimator().leave_to_others(leave->signal_ids, leave->until);
    }
    return;
  }
  if (auto* hint = std::get_if<PositionHint>(&work)) {
    if (auto it = worker.responders.find(hint->own.responder_id); it != worker.responders.end()) {
      it->second.estimator().hint_position(hint->own);
    }
    return;
  }
  if (auto* request = std::get_if<HandOverTo>(&work)) {
    hand_over(worker, *request);
    return;
  }
  if (auto* handed = std::get_if<TakeOver>(&work)) {
    take_over(worker, *handed);
    return;
  }
  if (auto* taken = std::get_if<HandedOver>(&work)) {
    release_handed(worker, *taken);
    return;
  }
  if (auto* evict = std::get_if<Evict>(&work)) {
    worker.handed_away.erase(evict->rescuer_id);
    if (auto it = worker.responders.find(evict->rescuer_id); it != worker.responders.end()) {
      drop_state(worker, it);
      if (!evict->shed) {
        spdlog::info("{}: responder '{}' idle for {} s: its state is released", config_.node_id, evict->rescuer_id,
                     config_.roster.idle_evict_s);
      }
    }
    return;
  }
  if (auto* odometry = std::get_if<responder::Odometry>(&work)) {
    if (straggler(worker, odometry->rescuer_id, odometry->interval_end)) return;
    auto& sequencer = sequencer_for(worker, odometry->rescuer_id);
    const TimestampNs motion_known = sequencer.odometry_until();
    sequencer.on_odometry(*odometry, report);
    // Not a firefighter's: his step 1 is his door start, which for a device restarted mid-search
    // would be a confident wrong place; he stays refused until idle, then is met mid-search.
    if (odometry->sequence == 1 && odometry->interval_start >= motion_known && !report.rejections.empty() &&
        report.rejections.back().reason == responder::RejectReason::kSequenceBackwards &&
        sequencer.estimator().role() == estimator::ResponderRole::kAvalancheRescuer) {
      // The device numbers its steps from 1 again, from after the last step it sent: it
      // restarted, and its signals are numbered afresh too. Its state here (or the estimator a
      // daemon handed over) would refuse all it sends until idle; it starts afresh instead, with
      // this step. (Step 1 replayed from before is refused as numbered backwards, as any replay.)
      spdlog::warn("{}: '{}' numbers its steps from 1 again (its device restarted): its state here starts afresh",
                   config_.node_id, odometry->rescuer_id);
      report.rejections.pop_back();
      drop_state(worker, worker.responders.find(odometry->rescuer_id));
      sequencer_for(worker, odometry->rescuer_id).on_odometry(*odometry, report);
    }
  } else {
    auto& sample = std::get<estimator::SensorSample>(work);
    if (straggler(worker, estimator::responder_of(sample), estimator::stamp_of(sample))) return;
    auto& sequencer = sequencer_for(worker, estimator::responder_of(sample));
    const std::size_t filters_before = sequencer.estimator().active_filters();
    sequencer.on_sample(sample, std::chrono::steady_clock::now(), report);
    active_filters_.fetch_add(sequencer.estimator().active_filters() - filters_before);
  }
  publish(report);
}

void CoreNode::publish(estimator::SequencerReport& report) {
  for (std::size_t i = 0; i < report.accepted; ++i) counters_.accepted();
  for (const auto& r : report.rejections) {
    const std::string reason = responder::to_string(r.reason);
    counters_.rejected(reason);
    warnings_.warn(r.rescuer_id, reason, "rejected sample (" + reason + "): " + r.detail);
  }
  for (const auto& late : report.odometry_late) {
    counters_.anomaly("odometry_late");
    warnings_.warn(late.rescuer_id, "odometry_late", late.detail);
  }
  for (const auto& [output, sequence] : report.answers) {
    for (const auto& e : output.estimates) {
      if (const auto code = estimate_writer_.write_returning(to_idl(e, sequence));
          code != eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
        spdlog::error("{}: DDS refused a VictimEstimate for '{}' signal {} ({})", config_.node_id, e.rescuer_id,
                      e.signal_id, return_code_name(code));
      }
    }
    if (output.guidance && !guidance_writer_.write(to_idl(*output.guidance, sequence))) {
      spdlog::error("{}: DDS refused a Guidance for '{}'", config_.node_id, output.guidance->rescuer_id);
    }
    // The places first: a reader that sees the ambiguous position has them already, mostly.
    if (output.candidates && !candidates_writer_.write(to_idl(*output.candidates))) {
      spdlog::error("{}: DDS refused the ResponderCandidates of '{}'", config_.node_id,
                    output.candidates->responder_id);
    }
    if (output.position) {
      if (!position_writer_.write(to_idl(*output.position))) {
        spdlog::error("{}: DDS refused a ResponderPosition for '{}'", config_.node_id, output.position->responder_id);
      } else if (position_refresh_) {
        position_refresh_->written(*output.position, std::chrono::steady_clock::now());
      }
    }
  }
  report = estimator::SequencerReport{};
}

void CoreNode::refresh_silent_positions() {
  if (!position_refresh_) return;
  for (const auto& position : position_refresh_->due(std::chrono::steady_clock::now())) {
    if (!position_writer_.write(to_idl(position))) {
      spdlog::error("{}: DDS refused the last position of '{}' written again", config_.node_id, position.responder_id);
    }
  }
}

void CoreNode::publish_status() {
  static thread_local ProcessStats stats;
  const auto snapshot = counters_.snapshot();
  ::sarloc::NodeStatus status;
  status.node_id(config_.node_id);
  status.kind(::sarloc::NODE_CORE);
  status.stamp(MissionClock::wall_now_ns());
  status.samples_accepted(snapshot.accepted);
  status.samples_rejected(snapshot.rejected);
  for (const auto& [reason, count] : snapshot.by_reason) {
    if (status.rejects().size() >= ::sarloc::REJECT_REASONS_MAX) break;
    ::sarloc::RejectCount r;
    r.reason(reason);
    r.count(count);
    status.rejects().push_back(r);
  }
  status.active_filters(static_cast<std::uint32_t>(active_filters_.load()));
  status.rescuers_served(static_cast<std::uint32_t>(rescuers_served_.load()));
  status.cpu_percent(stats.cpu_percent());
  status.rss_mb(ProcessStats::rss_mb());
  status_writer_.write(status);
}

}  // namespace sarloc::dds
