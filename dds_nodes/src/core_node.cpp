#include "sarloc/dds/core_node.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <functional>

#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/mission_clock.hpp"
#include "sarloc/dds/process_stats.hpp"

namespace sarloc::dds {

void CoreNodeConfig::validate() const {
  search.validate();
  if (node_id.empty() || node_id.size() > 64) throw ConfigError("core.node_id = '" + node_id + "': must be 1-64 characters");
  if (workers < 1 || workers > 64) throw ConfigError("core.workers = " + std::to_string(workers) + ": must be in [1, 64]");
  if (max_rescuers < 1) throw ConfigError("core.max_rescuers = 0: must be >= 1");
  if (queue_limit < 16) throw ConfigError("core.queue_limit = " + std::to_string(queue_limit) + ": must be >= 16");
  if (!(status_period_s > 0.0 && status_period_s <= 60.0)) {
    throw ConfigError("core.status_period_s = " + std::to_string(status_period_s) + ": must be in (0, 60]");
  }
  if (!(odometry_wait_s >= 0.0 && odometry_wait_s <= 10.0)) {
    throw ConfigError("core.odometry_wait_s = " + std::to_string(odometry_wait_s) + ": must be in [0, 10]");
  }
  if (!(warning_interval_s >= 0.0 && warning_interval_s <= 3600.0)) {
    throw ConfigError("core.warning_interval_s = " + std::to_string(warning_interval_s) + ": must be in [0, 3600]");
  }
  for (const auto& p : partitions) {
    if (p.empty()) throw ConfigError("core.partitions contains an empty name");
  }
}

namespace {

// A refused step may close at most this far past the last epoch (its stamp is untrusted too).
constexpr TimestampNs kMaxEpochGapNs = 60'000'000'000;

}  // namespace

CoreNode::CoreNode(std::shared_ptr<Participant> participant, CoreNodeConfig config)
    : config_((config.validate(), std::move(config))),
      participant_(std::move(participant)),
      warnings_(std::chrono::milliseconds(static_cast<std::int64_t>(config_.warning_interval_s * 1000.0))),
      estimate_writer_(participant_, EndpointOptions::in(config_.partitions)),
      guidance_writer_(participant_, EndpointOptions::in(config_.partitions)),
      status_writer_(participant_) {
  known_rescuers_.insert(config_.rescuers.begin(), config_.rescuers.end());
  for (unsigned i = 0; i < config_.workers; ++i) {
    workers_.push_back(std::make_unique<Worker>());
    Worker& w = *workers_.back();
    w.thread = std::thread([this, &w] { run_worker(w); });
  }
  status_thread_ = std::thread([this] {
    while (!stopping_.load()) {
      publish_status();
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
    // Listener callbacks: convert, refuse what cannot even be converted, enqueue.
    auto convert_and_enqueue = [this](const auto& sample, const auto&) {
      const std::string id = sample.rescuer_id().to_string();
      try {
        enqueue(id, to_core(sample));
      } catch (const InputError& e) {
        reject(id, "invalid_value", e.what());
      }
    };
    measurement_reader_ = std::make_unique<Reader<::sarloc::FieldMeasurement>>(participant_, convert_and_enqueue,
                                                                               EndpointOptions::in(config_.partitions));
    odometry_reader_ = std::make_unique<Reader<::sarloc::Odometry>>(participant_, convert_and_enqueue,
                                                                    EndpointOptions::in(config_.partitions));
    // Victims incident command declares found: stop guiding this sector's rescuers to them.
    victim_reader_ = std::make_unique<Reader<::sarloc::FusedVictim>>(
        participant_, [this](const ::sarloc::FusedVictim& v, const auto&) {
          if (v.state() != ::sarloc::VICTIM_FOUND && v.state() != ::sarloc::VICTIM_RECOVERED) return;
          for (const auto& source : v.sources()) {
            const std::string id = source.rescuer_id().to_string();
            enqueue(id, MarkDone{id, source.signal_id()});
          }
        });
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
  // Stop the inflow first, then the threads, then (implicitly) the writers.
  measurement_reader_.reset();
  odometry_reader_.reset();
  victim_reader_.reset();
  stop_threads();
}

void CoreNode::stop_threads() {
  stopping_.store(true);
  for (auto& w : workers_) {
    {
      std::lock_guard<std::mutex> lock(w->mutex);
    }
    w->cv.notify_all();
  }
  for (auto& w : workers_) w->thread.join();
  status_thread_.join();
}

void CoreNode::reject(const std::string& rescuer_id, const std::string& reason, const std::string& detail) {
  counters_.rejected(reason);
  warnings_.warn(rescuer_id, reason, "rejected sample (" + reason + "): " + detail);
}

void CoreNode::enqueue(const std::string& rescuer_id, Work work) {
  Worker& w = *workers_[std::hash<std::string>{}(rescuer_id) % workers_.size()];
  bool dropped = false;
  {
    std::lock_guard<std::mutex> lock(w.mutex);
    if (w.queue.size() >= config_.queue_limit) {
      w.queue.pop_front();
      dropped = true;
    }
    w.queue.push_back(std::move(work));
  }
  w.cv.notify_one();
  if (dropped) reject(rescuer_id, "overloaded", "worker queue full: dropped the oldest waiting sample");
}

void CoreNode::run_worker(Worker& worker) {
  while (true) {
    // Sleep until work arrives or the earliest held measurement's wait expires.
    std::optional<SteadyTime> wake;
    for (const auto& [id, state] : worker.rescuers) {
      if (!state.held.empty() && (!wake || state.held.front().deadline < *wake)) wake = state.held.front().deadline;
    }
    std::optional<Work> work;
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
        work = std::move(worker.queue.front());
        worker.queue.pop_front();
      }
    }
    if (work) handle(worker, *work);
    const auto now = std::chrono::steady_clock::now();
    for (auto& [id, state] : worker.rescuers) release_held(state, now);
  }
}

CoreNode::RescuerState* CoreNode::state_for(Worker& worker, const std::string& rescuer_id) {
  if (auto it = worker.rescuers.find(rescuer_id); it != worker.rescuers.end()) return &it->second;
  if (rescuer_id.empty()) {
    reject(rescuer_id, "unknown_rescuer", "rescuer_id is empty");
    return nullptr;
  }
  {
    std::lock_guard<std::mutex> lock(rescuers_mutex_);
    const bool listed = !config_.rescuers.empty();
    if (listed && known_rescuers_.count(rescuer_id) == 0) {
      reject(rescuer_id, "unknown_rescuer", "rescuer_id = '" + rescuer_id + "' is not one of this node's rescuers");
      return nullptr;
    }
    if (!listed && known_rescuers_.size() >= config_.max_rescuers) {
      reject(rescuer_id, "too_many_rescuers",
             "rescuer_id = '" + rescuer_id + "': already serving max_rescuers = " + std::to_string(config_.max_rescuers));
      return nullptr;
    }
    known_rescuers_.insert(rescuer_id);
  }
  rescuers_served_.fetch_add(1);
  spdlog::info("{}: new rescuer '{}'", config_.node_id, rescuer_id);
  return &worker.rescuers.emplace(rescuer_id, RescuerState{avalanche::RescuerSearch(rescuer_id, config_.search), 0, {}, {}})
              .first->second;
}

void CoreNode::handle(Worker& worker, Work& work) {
  if (auto* done = std::get_if<MarkDone>(&work)) {
    if (auto it = worker.rescuers.find(done->rescuer_id); it != worker.rescuers.end()) {
      it->second.search.mark_done(done->signal_id);
    }
    return;
  }
  if (auto* odometry = std::get_if<avalanche::Odometry>(&work)) {
    auto* state = state_for(worker, odometry->rescuer_id);
    if (state == nullptr) return;
    if (auto rejected = state->search.add_odometry(*odometry)) {
      reject(odometry->rescuer_id, avalanche::to_string(rejected->reason), rejected->detail);
      // A step refused for its values still says how far the rescuer's clock went: waiting
      // for it would only make the next epoch late. Refused timing moves nothing.
      const bool timing_ok = rejected->reason == avalanche::RejectReason::kAbsurdMotion ||
                             rejected->reason == avalanche::RejectReason::kInvalidValue;
      if (timing_ok && odometry->interval_end > state->odometry_until &&
          (!state->measured_at || odometry->interval_end <= *state->measured_at + kMaxEpochGapNs)) {
        state->odometry_until = odometry->interval_end;
      }
    } else {
      counters_.accepted();
      state->odometry_until = std::max(state->odometry_until, odometry->interval_end);
    }
    return;
  }
  auto& measurement = std::get<avalanche::FieldMeasurement>(work);
  auto* state = state_for(worker, measurement.rescuer_id);
  if (state == nullptr) return;
  // A new epoch follows a step: wait for the odometry up to its stamp (see the config). The
  // other signals of an epoch already processed share its stamp and need nothing more.
  const bool new_epoch = state->measured_at && measurement.stamp > *state->measured_at;
  const bool motion_pending = new_epoch && measurement.stamp > state->odometry_until;
  if ((motion_pending || !state->held.empty()) && config_.odometry_wait_s > 0.0) {
    const auto wait = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(config_.odometry_wait_s));
    state->held.push_back(Held{measurement, std::chrono::steady_clock::now() + wait});
    return;
  }
  process_measurement(*state, measurement);
}

void CoreNode::release_held(RescuerState& state, SteadyTime now) {
  while (!state.held.empty()) {
    const Held& front = state.held.front();
    const bool covered = front.measurement.stamp <= state.odometry_until;
    if (!covered && now < front.deadline) return;
    if (!covered) {
      // Processing as if the rescuer had stood still would let one near-field measurement lock
      // a filter onto a wrong position with a small covariance (seen under 20 % packet loss:
      // "located" 10 m off). Unknown motion stands in for the missing odometry instead.
      const TimestampNs from = state.odometry_until > 0 ? state.odometry_until : state.measured_at.value_or(0);
      bool stood_in = false;
      try {
        stood_in = state.search.add_unknown_motion(from, front.measurement.stamp);
      } catch (const InputError& e) {  // the covariance is built valid; never let it stop a worker
        spdlog::error("{}: unknown motion refused: {}", config_.node_id, e.what());
      }
      if (stood_in) state.odometry_until = front.measurement.stamp;
      counters_.anomaly("odometry_late");
      warnings_.warn(front.measurement.rescuer_id, "odometry_late",
                     "rescuer '" + front.measurement.rescuer_id + "': no odometry up to stamp " +
                         std::to_string(front.measurement.stamp) + " within odometry_wait_s: processed " +
                         (stood_in ? "with unknown motion in its place" : "without it (no stand-in for this gap)"));
    }
    const auto measurement = front.measurement;
    state.held.pop_front();
    process_measurement(state, measurement);
  }
}

void CoreNode::process_measurement(RescuerState& state, const avalanche::FieldMeasurement& measurement) {
  auto& search = state.search;
  const std::size_t signals_before = search.signal_count();
  auto outcome = search.process(measurement);
  if (auto* rejected = std::get_if<avalanche::Rejection>(&outcome)) {
    reject(measurement.rescuer_id, avalanche::to_string(rejected->reason), rejected->detail);
    return;
  }
  counters_.accepted();
  state.measured_at = std::max(state.measured_at.value_or(measurement.stamp), measurement.stamp);
  active_filters_.fetch_add(search.signal_count() - signals_before);
  auto& update = std::get<avalanche::SearchUpdate>(outcome);
  if (!estimate_writer_.write(to_idl(update.estimate, measurement.sequence))) {
    spdlog::error("{}: DDS refused a VictimEstimate for '{}'", config_.node_id, measurement.rescuer_id);
  }
  if (update.guidance && !guidance_writer_.write(to_idl(*update.guidance, measurement.sequence))) {
    spdlog::error("{}: DDS refused a Guidance for '{}'", config_.node_id, measurement.rescuer_id);
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
