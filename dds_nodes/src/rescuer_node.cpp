#include "sarloc/dds/rescuer_node.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "sarloc/dds/conversions.hpp"

namespace sarloc::dds {
namespace {

int rank(avalanche::EstimatorStatus status) { return static_cast<int>(status); }

}  // namespace

const char* to_string(GuidanceSource source) {
  switch (source) {
    case GuidanceSource::kNone: return "none";
    case GuidanceSource::kDaemon: return "daemon";
    case GuidanceSource::kLocal: return "local";
  }
  return "unknown";
}

void RescuerNodeConfig::validate() const {
  search.validate();
  if (rescuer_id.empty() || rescuer_id.size() > 64) {
    throw ConfigError("rescuer.id = '" + rescuer_id + "': must be 1-64 characters");
  }
  if (team.empty() || team.size() > 64) throw ConfigError("rescuer.team = '" + team + "': must be 1-64 characters");
  if (!(fallback_timeout_s > 0.0 && fallback_timeout_s <= 600.0)) {
    throw ConfigError("rescuer.fallback_timeout_s = " + std::to_string(fallback_timeout_s) + ": must be in (0, 600]");
  }
  if (!(guidance_wait_s >= 0.0 && guidance_wait_s <= 10.0)) {
    throw ConfigError("rescuer.guidance_wait_s = " + std::to_string(guidance_wait_s) + ": must be in [0, 10]");
  }
}

RescuerNode::RescuerNode(std::shared_ptr<Participant> participant, RescuerNodeConfig config, MissionClock clock)
    : config_((config.validate(), std::move(config))),
      clock_(clock),
      participant_(std::move(participant)),
      local_(config_.rescuer_id, config_.search),
      measurement_writer_(participant_, EndpointOptions::in(config_.partitions)),
      odometry_writer_(participant_, EndpointOptions::in(config_.partitions)),
      estimate_writer_(participant_, EndpointOptions::in(config_.partitions)),
      position_writer_(participant_),
      started_(clock_.now()) {
  guidance_reader_ = std::make_unique<Reader<::sarloc::Guidance>>(
      participant_,
      [this](const ::sarloc::Guidance& g, const auto&) {
        if (g.rescuer_id().to_string() != config_.rescuer_id) return;
        try {
          auto guidance = to_core(g);
          std::lock_guard<std::mutex> lock(mutex_);
          // A late answer to an older epoch (retransmitted) must not replace a newer one: the
          // guidance and its sequence stay a pair.
          if (g.measurement_sequence() >= remote_.guidance_sequence) {
            remote_.guidance = guidance;
            remote_.guidance_sequence = g.measurement_sequence();
            remote_.guidance_mission_time = clock_.now();
            remote_.guidance_wall_ns = MissionClock::wall_now_ns();
          }
          remote_.answered_sequence = std::max(remote_.answered_sequence, g.measurement_sequence());
          remote_.answered_mission_time = clock_.now();
        } catch (const InputError& e) {
          spdlog::warn("ignoring guidance from the daemon: {}", e.what());
        }
        cv_.notify_all();
      },
      EndpointOptions::in(config_.partitions));
  estimate_reader_ = std::make_unique<Reader<::sarloc::VictimEstimate>>(
      participant_,
      [this](const ::sarloc::VictimEstimate& e, const auto& info) {
        if (e.rescuer_id().to_string() != config_.rescuer_id) return;
        // Our own fallback estimates come back to us too: only the daemon's count.
        if (info.publication_handle == estimate_writer_.get()->get_instance_handle()) return;
        if (e.status() > ::sarloc::ESTIMATOR_FOUND) return;
        {
          std::lock_guard<std::mutex> lock(mutex_);
          remote_.status[e.signal_id()] = {static_cast<avalanche::EstimatorStatus>(e.status()), e.measurement_sequence()};
          remote_.answered_sequence = std::max(remote_.answered_sequence, e.measurement_sequence());
          remote_.answered_mission_time = clock_.now();
        }
        cv_.notify_all();
      },
      EndpointOptions::in(config_.partitions));
  victim_reader_ = std::make_unique<Reader<::sarloc::FusedVictim>>(
      participant_, [this](const ::sarloc::FusedVictim& v, const auto&) {
        if (v.state() != ::sarloc::VICTIM_FOUND && v.state() != ::sarloc::VICTIM_RECOVERED) return;
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& s : v.sources()) {
          if (s.rescuer_id().to_string() == config_.rescuer_id) found_elsewhere_[s.signal_id()] = true;
        }
      });
  // A core daemon's NodeStatus writer losing liveliness means the daemon is gone: fall back
  // at once instead of waiting for the guidance timeout.
  ReaderEvents core_events;
  core_events.on_liveliness = [this](const auto& handle, bool alive) {
    if (alive) return;  // a daemon counts as alive once it published a status
    std::lock_guard<std::mutex> lock(mutex_);
    auto& live = live_core_writers_;
    live.erase(std::remove(live.begin(), live.end(), handle), live.end());
    if (live.empty()) remote_.status.clear();  // a daemon that comes back starts from nothing
  };
  core_status_reader_ = std::make_unique<Reader<::sarloc::NodeStatus>>(
      participant_,
      [this](const ::sarloc::NodeStatus& status, const auto& info) {
        if (status.kind() != ::sarloc::NODE_CORE) return;
        std::lock_guard<std::mutex> lock(mutex_);
        seen_core_ = true;
        auto& live = live_core_writers_;
        if (std::find(live.begin(), live.end(), info.publication_handle) == live.end()) {
          live.push_back(info.publication_handle);
        }
      },
      EndpointOptions{}, core_events);
}

bool RescuerNode::wait_for_daemon(std::chrono::milliseconds timeout) const {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  auto remaining = [&] {
    return std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
  };
  return measurement_writer_.wait_for_readers(1, timeout) && odometry_writer_.wait_for_readers(1, remaining()) &&
         guidance_reader_->wait_for_writers(1, remaining());
}

RescuerNode::~RescuerNode() {
  guidance_reader_.reset();
  estimate_reader_.reset();
  victim_reader_.reset();
  core_status_reader_.reset();
}

EpochResult RescuerNode::epoch(const std::vector<avalanche::Odometry>& odometry,
                               const std::optional<incident::ResponderPosition>& gnss,
                               const std::vector<avalanche::FieldMeasurement>& measurements) {
  EpochResult result;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [signal, found] : found_elsewhere_) {
      if (found) local_.mark_done(signal);
    }
  }
  // Motion first: the daemon must apply the step before this epoch's measurements.
  for (const auto& o : odometry) {
    if (!odometry_writer_.write(to_idl(o))) spdlog::error("DDS refused odometry {}", o.sequence);
    if (auto rejected = local_.add_odometry(o)) spdlog::warn("local search refused odometry: {}", rejected->detail);
  }
  if (gnss && !position_writer_.write(to_idl(*gnss))) spdlog::error("DDS refused the position fix");

  std::optional<avalanche::Guidance> local_guidance;
  std::vector<avalanche::VictimEstimate> local_estimates;
  const std::int64_t published_wall = MissionClock::wall_now_ns();
  for (const auto& m : measurements) {
    if (!measurement_writer_.write(to_idl(m))) spdlog::error("DDS refused measurement of signal {}", m.signal_id);
  }
  for (const auto& m : measurements) {
    auto outcome = local_.process(m);
    if (auto* update = std::get_if<avalanche::SearchUpdate>(&outcome)) {
      local_estimates.push_back(update->estimate);
      if (update->guidance) local_guidance = update->guidance;
    } else {
      spdlog::warn("local search refused a sample: {}", std::get<avalanche::Rejection>(outcome).detail);
    }
  }

  // The target was not heard this epoch (out of range, lost sample): keep heading for it.
  if (!local_guidance) local_guidance = local_.coast(measurements.empty() ? clock_.now() : measurements.front().stamp);

  // Wait for the daemon's answer to this epoch (same measurement sequence).
  const std::uint64_t sequence = measurements.empty() ? 0 : measurements.front().sequence;
  std::unique_lock<std::mutex> lock(mutex_);
  // The daemon's last status of the signal its guidance leads to (under the lock).
  auto guided_signal_status = [&]() -> const Remote::SignalStatus* {
    if (!remote_.guidance) return nullptr;
    const auto it = remote_.status.find(remote_.guidance->signal_id);
    return it == remote_.status.end() ? nullptr : &it->second;
  };
  // Wait only for a daemon believed alive: an unreachable one would make every epoch late.
  if (!measurements.empty() && (was_reachable_ || remote_.answered_mission_time == 0)) {
    cv_.wait_for(lock, std::chrono::milliseconds(static_cast<std::int64_t>(config_.guidance_wait_s * 1000.0)),
                 [&] {
                   // Both halves of the daemon's answer: the guidance and its signal's estimate.
                   if (remote_.guidance_sequence < sequence) return false;
                   const auto* status = guided_signal_status();
                   return status != nullptr && status->sequence >= sequence;
                 });
  }
  const TimestampNs now = clock_.now();
  const auto timeout = static_cast<TimestampNs>(config_.fallback_timeout_s * 1e9);
  const bool answered = remote_.answered_mission_time != 0;
  const bool alive = answered && now - remote_.answered_mission_time <= timeout;
  const bool fresh = remote_.guidance && now - remote_.guidance_mission_time <= timeout;
  // Before any daemon answer, give it fallback_timeout_s from our start to show up.
  const bool grace = !answered && now - started_ <= timeout;
  const bool cores_lost = seen_core_ && live_core_writers_.empty();
  result.daemon_reachable = (alive || grace) && !cores_lost;
  if (remote_.guidance_sequence == sequence && sequence != 0) {
    result.latency_ms = static_cast<double>(remote_.guidance_wall_ns - published_wall) / 1e6;
  }

  auto local_status = [&](std::uint32_t signal) {
    const auto e = local_.estimate(signal);
    return e ? e->status : avalanche::EstimatorStatus::kInitialising;
  };
  bool use_remote = false;
  // The daemon's guidance counts only as the answer to this very epoch (when the target was
  // not heard, only the device coasts).
  if (fresh && !cores_lost && remote_.guidance && remote_.guidance_sequence == sequence && sequence != 0) {
    // The daemon's estimate must answer this very epoch: an older status (or a previous
    // daemon's) says nothing about the filter that produced this guidance.
    const auto* status = guided_signal_status();
    const auto remote_rank = status == nullptr || status->sequence != sequence ? 0 : rank(status->status);
    const auto local_rank = local_guidance ? rank(local_status(local_guidance->signal_id)) : 0;
    use_remote = remote_rank >= local_rank;
  }
  if (use_remote) {
    result.guidance = remote_.guidance;
    result.source = GuidanceSource::kDaemon;
    for (const auto& [signal, status] : remote_.status) result.signals[signal] = status.status;
  } else if (local_guidance) {
    result.guidance = local_guidance;
    result.source = GuidanceSource::kLocal;
  }
  for (const auto& e : local_estimates) {
    if (!use_remote || result.signals.count(e.signal_id) == 0) result.signals[e.signal_id] = e.status;
  }

  if (was_reachable_ && !result.daemon_reachable) {
    ++fallbacks_;
    if (cores_lost) {
      spdlog::warn("{}: core daemon unreachable (its liveliness was lost): guiding on the device", config_.rescuer_id);
    } else {
      spdlog::warn("{}: core daemon unreachable (no answer for {:.1f} s): guiding on the device", config_.rescuer_id,
                   config_.fallback_timeout_s);
    }
  } else if (!was_reachable_ && result.daemon_reachable && answered) {
    spdlog::info("{}: core daemon reachable", config_.rescuer_id);
  }
  was_reachable_ = result.daemon_reachable;
  lock.unlock();

  // Incident command must keep seeing victims while the daemon is away.
  if (!result.daemon_reachable) {
    for (const auto& e : local_estimates) estimate_writer_.write(to_idl(e, sequence));
  }
  return result;
}

}  // namespace sarloc::dds
