#include "sarloc/dds/rescuer_node.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "sarloc/core/common/validate.hpp"
#include "sarloc/core/incident/strip_guidance.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/sign_off.hpp"
#include "sarloc/dds/speaker_claim.hpp"

namespace sarloc::dds {
namespace {
// The device's own fixes kept for its estimates: 3600 epochs, an hour at one epoch a second (a
// FOUND estimate keeps the stamp it was found at for the rest of the search).
constexpr std::size_t kOwnFixesKept = 3600;
// The plan's strip is walked from a fix at most this old (mission time).
constexpr TimestampNs kStripFixAgeNs = 5'000'000'000;
}  // namespace

void RescuerNodeConfig::validate() const {
  estimators.validate();
  if (rescuer_id.empty() || rescuer_id.size() > 64) {
    throw ConfigError("rescuer.id = '" + rescuer_id + "': must be 1-64 characters");
  }
  if (team.empty() || team.size() > 64) throw ConfigError("rescuer.team = '" + team + "': must be 1-64 characters");
  if (!(fallback_timeout_s > 0.0 && fallback_timeout_s <= 600.0)) {
    throw ConfigError("rescuer.fallback_timeout_s = " + config_value(fallback_timeout_s) + ": must be in (0, 600]");
  }
  if (!(guidance_wait_s >= 0.0 && guidance_wait_s <= 10.0)) {
    throw ConfigError("rescuer.guidance_wait_s = " + config_value(guidance_wait_s) + ": must be in [0, 10]");
  }
  if (rejoin_epochs < 1 || rejoin_epochs > 100) {
    throw ConfigError("rescuer.rejoin_epochs = " + config_value(rejoin_epochs) + ": must be in [1, 100]");
  }
}

RescuerNode::RescuerNode(std::shared_ptr<Participant> participant, RescuerNodeConfig config, MissionClock clock)
    : config_((config.validate(), std::move(config))),
      clock_(clock),
      participant_(std::move(participant)),
      // The others believe what this device says about its responder by its certificate's name.
      authority_((require_identity(*participant_, config_.rescuer_id, "rescuers[].id"), participant_)),
      local_(estimator::make_estimator(config_.role, config_.rescuer_id, config_.estimators)),
      sample_writers_(participant_, EndpointOptions::in(config_.partitions)),
      odometry_writer_(participant_, EndpointOptions::in(config_.partitions)),
      estimate_writer_(participant_, EndpointOptions::in(config_.partitions)),
      position_writer_(participant_, device_position_options()),
      arbiter_(config_.fallback_timeout_s, clock_.now(), config_.rejoin_epochs),
      recovery_writer_(participant_) {
  guidance_reader_ = std::make_unique<Reader<::sarloc::Guidance>>(
      participant_,
      [this](const ::sarloc::Guidance& g, const auto&) {
        if (g.rescuer_id().to_string() != config_.rescuer_id) return;
        try {
          const auto guidance = to_core(g);
          std::lock_guard<std::mutex> lock(mutex_);
          hear([guidance, sequence = g.measurement_sequence(), now = clock_.now(), wall = MissionClock::wall_now_ns()](
                   responder::GuidanceArbiter& arbiter) { arbiter.on_daemon_guidance(guidance, sequence, now, wall); });
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
        if (const SpeakerClaim claim = speaker_claim(e); !admits(authority_, info.publication_handle, claim)) {
          refusals_.warn(claim.responder_id, "unauthorized_writer",
                         refusal(authority_, info.publication_handle, claim));
          return;
        }
        if (e.status() > ::sarloc::ESTIMATOR_FOUND) return;
        {
          std::lock_guard<std::mutex> lock(mutex_);
          hear([signal = e.signal_id(), status = static_cast<responder::EstimatorStatus>(e.status()),
                sequence = e.measurement_sequence(), now = clock_.now(),
                relative = to_core(e.relative())](responder::GuidanceArbiter& arbiter) {
            arbiter.on_daemon_estimate(signal, status, sequence, now, relative);
          });
        }
        cv_.notify_all();
      },
      EndpointOptions::in(config_.partitions));
  victim_reader_ = std::make_unique<Reader<::sarloc::FusedVictim>>(
      participant_, [this](const ::sarloc::FusedVictim& v, const auto&) {
        if (v.state() != ::sarloc::VICTIM_FOUND && v.state() != ::sarloc::VICTIM_RECOVERED) return;
        const Vec3 where = to_core(v.position()).position;
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& s : v.sources()) {
          if (s.rescuer_id().to_string() != config_.rescuer_id) continue;
          found_elsewhere_.insert(s.signal_id());
          picture_victim_of_[s.signal_id()] = PictureVictim{v.victim_id(), where};
        }
        if (v.state() == ::sarloc::VICTIM_RECOVERED && recovered_seen_.insert(v.victim_id()).second) {
          if (where.allFinite()) recovered_.emplace_back(v.victim_id(), where);
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
    if (live.empty()) {
      hear([](responder::GuidanceArbiter& arbiter) { arbiter.on_daemons_lost(); });
    }
  };
  // A daemon that stops in order disposes its status first (sign_off.hpp): said as a stop.
  core_events.on_instance_gone = [this](const auto& info) {
    if (info.instance_state != eprosima::fastdds::dds::NOT_ALIVE_DISPOSED_INSTANCE_STATE) return;
    std::lock_guard<std::mutex> lock(mutex_);
    auto& live = live_core_writers_;
    if (std::find(live.begin(), live.end(), info.publication_handle) == live.end()) return;
    spdlog::info("{}: a core daemon stopped in order (signed off)", config_.rescuer_id);
    live.erase(std::remove(live.begin(), live.end(), info.publication_handle), live.end());
    if (live.empty()) {
      hear([](responder::GuidanceArbiter& arbiter) { arbiter.on_daemons_lost(); });
    }
  };
  core_status_reader_ = std::make_unique<Reader<::sarloc::NodeStatus>>(
      participant_,
      [this](const ::sarloc::NodeStatus& status, const auto& info) {
        if (status.kind() != ::sarloc::NODE_CORE) return;
        std::lock_guard<std::mutex> lock(mutex_);
        auto& live = live_core_writers_;
        if (std::find(live.begin(), live.end(), info.publication_handle) == live.end()) {
          live.push_back(info.publication_handle);
        }
        hear([](responder::GuidanceArbiter& arbiter) { arbiter.on_daemon_seen(); });
      },
      EndpointOptions{}, core_events);
  // Only incident command may write the plan (the command role, deploy/security/make-certs.sh).
  plan_reader_ =
      std::make_unique<Reader<::sarloc::SearchPlan>>(participant_, [this](const ::sarloc::SearchPlan& p, const auto&) {
        try {
          auto plan = to_core(p);
          std::lock_guard<std::mutex> lock(mutex_);
          plan_ = std::move(plan);
        } catch (const InputError& e) {
          refusals_.warn(config_.rescuer_id, "search_plan", std::string("ignoring a search plan: ") + e.what());
        }
      });
}

void RescuerNode::move_to(const std::vector<std::string>& partitions) {
  guidance_reader_->set_partitions(partitions);
  estimate_reader_->set_partitions(partitions);
  sample_writers_.set_partitions(partitions);
  odometry_writer_.set_partitions(partitions);
  estimate_writer_.set_partitions(partitions);
  config_.partitions = partitions;
}

bool RescuerNode::wait_for_daemon(std::chrono::milliseconds timeout) const {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  auto remaining = [&] {
    return std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
  };
  return sample_writers_.wait_for_readers(1, timeout) && odometry_writer_.wait_for_readers(1, remaining()) &&
         guidance_reader_->wait_for_writers(1, remaining());
}

std::optional<RescuerNode::PictureVictim> RescuerNode::picture_victim_of(std::uint32_t signal) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = picture_victim_of_.find(signal);
  if (it == picture_victim_of_.end()) return std::nullopt;
  return it->second;
}

bool RescuerNode::report_dug_out(std::uint32_t victim_id) {
  ::sarloc::VictimRecovery recovery;
  recovery.victim_id(victim_id);
  recovery.reported_by(config_.rescuer_id);
  recovery.stamp(clock_.now());
  return recovery_writer_.write(recovery);
}

std::vector<std::pair<std::uint32_t, Vec3>> RescuerNode::take_recovered() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::pair<std::uint32_t, Vec3>> out;
  out.swap(recovered_);
  return out;
}

int RescuerNode::fallbacks() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return arbiter_.fallbacks();
}

int RescuerNode::guidance_switches() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return arbiter_.switches();
}

RescuerNode::~RescuerNode() {
  guidance_reader_.reset();
  estimate_reader_.reset();
  victim_reader_.reset();
  core_status_reader_.reset();
  plan_reader_.reset();
}

void RescuerNode::move(const std::vector<responder::Odometry>& odometry) {
  for (const auto& o : odometry) {
    if (!odometry_writer_.write(to_idl(o))) spdlog::error("DDS refused odometry {}", o.sequence);
    const auto outcome = local_->add_odometry(o);
    if (const auto* rejected = std::get_if<responder::Rejection>(&outcome)) {
      spdlog::warn("local estimator refused odometry: {}", rejected->detail);
    }
  }
}

EpochResult RescuerNode::epoch(const std::vector<responder::Odometry>& odometry,
                               const std::optional<responder::ResponderPosition>& fix,
                               const std::vector<estimator::SensorSample>& samples) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const std::uint32_t signal : found_elsewhere_) local_->mark_done(signal);
    // Victims incident command sends another rescuer to (one rescuer per victim).
    if (plan_) {
      local_->leave_to_others(incident::signals_left_to_others(plan_->handed_over, config_.rescuer_id),
                              plan_->stamp + incident::kHandOverLapseNs);
    }
  }
  move(odometry);  // motion first: the daemon must apply the step before this epoch's samples
  position_writer_.assert_liveliness();  // the link is alive while the device runs, fix or not
  if (fix) {
    if (!position_writer_.write(to_idl(*fix))) spdlog::error("DDS refused the position fix");
    if (own_fixes_.empty() || fix->stamp > own_fixes_.back().stamp) own_fixes_.push_back(*fix);
    if (own_fixes_.size() > kOwnFixesKept) own_fixes_.pop_front();
  }

  std::optional<responder::Guidance> local_guidance;
  std::vector<responder::VictimEstimate> local_estimates;
  const std::int64_t published_wall = MissionClock::wall_now_ns();
  for (const auto& s : samples) {
    if (!sample_writers_.write(s)) spdlog::error("DDS refused a sample of sequence {}", estimator::sequence_of(s));
  }
  for (const auto& s : samples) {
    auto outcome = local_->process(s);
    if (auto* out = std::get_if<estimator::EstimatorOutput>(&outcome)) {
      for (auto& e : out->estimates) local_estimates.push_back(std::move(e));
      if (out->guidance) local_guidance = out->guidance;
    } else {
      spdlog::warn("local estimator refused a sample: {}", std::get<responder::Rejection>(outcome).detail);
    }
  }
  // The target was not heard this epoch (out of range, lost sample): keep heading for it.
  if (!local_guidance) local_guidance = local_->coast(samples.empty() ? clock_.now() : estimator::stamp_of(samples.front()));

  // Wait for the daemon's answer to this epoch (same sample sequence).
  const std::uint64_t sequence = samples.empty() ? 0 : estimator::sequence_of(samples.front());
  std::unique_lock<std::mutex> lock(mutex_);
  apply_arbiter_inbox();
  if (!samples.empty() && arbiter_.worth_waiting()) {
    cv_.wait_for(lock, std::chrono::milliseconds(static_cast<std::int64_t>(config_.guidance_wait_s * 1000.0)), [&] {
      apply_arbiter_inbox();
      return arbiter_.answered(sequence);
    });
  }
  responder::ArbiterInput input;
  input.now = clock_.now();
  input.sequence = sequence;
  input.published_wall_ns = published_wall;
  input.local_guidance = local_guidance;
  input.local_estimates = local_estimates;
  input.local_status = [this](std::uint32_t signal) {
    const auto e = local_->estimate_of(signal);
    return e ? e->status : responder::EstimatorStatus::kInitialising;
  };
  const auto decision = arbiter_.decide(input);
  std::optional<responder::Guidance> strip;
  // A fix older than a few steps would walk the rescuer somewhere it no longer is.
  if (!decision.guidance && plan_ && !own_fixes_.empty() && input.now - own_fixes_.back().stamp <= kStripFixAgeNs) {
    incident::StripGuidanceConfig walk;
    walk.step_m = config_.estimators.avalanche_rescuer.search.step_length_m;
    strip = incident::strip_guidance(*plan_, config_.rescuer_id, own_fixes_.back(), walk);
  }
  lock.unlock();

  EpochResult result;
  result.guidance = strip ? strip : decision.guidance;
  result.source = strip ? responder::GuidanceSource::kPlan : decision.source;
  result.daemon_reachable = decision.daemon_reachable;
  result.latency_ms = decision.latency_ms;
  result.signals = decision.daemon_signals;
  result.conflicting_signals = decision.conflicting_signals;
  for (const auto& e : local_estimates) {
    if (decision.source != responder::GuidanceSource::kDaemon || result.signals.count(e.signal_id) == 0) {
      result.signals[e.signal_id] = e.status;
    }
  }
  if (decision.fell_back) {
    if (decision.daemons_lost) {
      spdlog::warn("{}: core daemon unreachable (its liveliness was lost): guiding on the device", config_.rescuer_id);
    } else {
      spdlog::warn("{}: core daemon unreachable (no answer for {:.1f} s): guiding on the device", config_.rescuer_id,
                   config_.fallback_timeout_s);
    }
  } else if (decision.reconnected) {
    spdlog::info("{}: core daemon reachable", config_.rescuer_id);
  }
  for (const std::uint32_t signal : decision.conflicting_signals) {
    if (reported_conflicts_.insert(signal).second) {
      spdlog::warn("{}: signal {}: the core daemon's estimate conflicts with the device's own: guiding on the device, "
                   "both estimates go to incident command", config_.rescuer_id, signal);
    }
  }
  for (auto it = reported_conflicts_.begin(); it != reported_conflicts_.end();) {
    it = decision.conflicting_signals.count(*it) == 0 ? reported_conflicts_.erase(it) : std::next(it);
  }
  // The device's own estimate always goes to incident command: it saw every sample, so it is
  // the one that may confirm a victim there (VictimFusion: the daemon's copy can miss samples
  // in a fade and must agree with it); it also keeps victims in the picture while the daemon
  // is away.
  for (auto& e : local_estimates) {
    e.reporter = own_fix_nearest(e.stamp);
    auto message = to_idl(e, sequence);
    message.from_device(true);
    if (!estimate_writer_.write(message)) spdlog::error("DDS refused the device's estimate of signal {}", e.signal_id);
  }
  return result;
}

void RescuerNode::hear(std::function<void(responder::GuidanceArbiter&)> heard) {
  // A second of epochs brings a handful; only a flood reaches this, and it drops the newest.
  if (arbiter_inbox_.size() >= kArbiterInboxLimit) {
    refusals_.warn(config_.rescuer_id, "inbox_full",
                   config_.rescuer_id + ": the daemon's messages arrive faster than epochs: dropped");
    return;
  }
  arbiter_inbox_.push_back(std::move(heard));
}

void RescuerNode::apply_arbiter_inbox() {
  for (auto& heard : arbiter_inbox_) heard(arbiter_);
  arbiter_inbox_.clear();
}

std::optional<responder::ResponderPosition> RescuerNode::own_fix_nearest(TimestampNs stamp) const {
  const auto after = std::lower_bound(own_fixes_.begin(), own_fixes_.end(), stamp,
                                      [](const responder::ResponderPosition& f, TimestampNs s) { return f.stamp < s; });
  if (after == own_fixes_.end()) return own_fixes_.empty() ? std::nullopt : std::optional(own_fixes_.back());
  if (after == own_fixes_.begin()) return *after;
  const auto before = std::prev(after);
  return stamp - before->stamp < after->stamp - stamp ? *before : *after;
}

bool RescuerNode::sign_off(std::chrono::milliseconds timeout) {
  return dds::sign_off(position_writer_, config_.rescuer_id, timeout);
}

}  // namespace sarloc::dds
