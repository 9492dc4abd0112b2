#include "sarloc/core/common/time_units.hpp"
#include "sarloc/core/responder/guidance_arbiter.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <string>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::responder {
namespace {

int rank(EstimatorStatus status) { return static_cast<int>(status); }

// chi2_3(0.999): two estimates of one victim from the same samples farther apart than this
// (with summed covariances) cannot both be right.
constexpr double kConflictGate = 16.266236196238129;

}  // namespace

const char* to_string(GuidanceSource source) {
  switch (source) {
    case GuidanceSource::kNone: return "none";
    case GuidanceSource::kDaemon: return "daemon";
    case GuidanceSource::kLocal: return "local";
    case GuidanceSource::kPlan:
      return "plan";
  }
  return "unknown";
}

GuidanceArbiter::GuidanceArbiter(double fallback_timeout_s, TimestampNs started, int rejoin_epochs)
    : timeout_ns_(seconds_to_ns(fallback_timeout_s)), started_(started), rejoin_epochs_(rejoin_epochs) {
  if (!(fallback_timeout_s > 0.0 && fallback_timeout_s <= 600.0)) {
    throw ConfigError("rescuer.fallback_timeout_s = " + config_value(fallback_timeout_s) + ": must be in (0, 600]");
  }
  if (rejoin_epochs < 1 || rejoin_epochs > 100) {
    throw ConfigError("rescuer.rejoin_epochs = " + config_value(rejoin_epochs) + ": must be in [1, 100]");
  }
}

void GuidanceArbiter::on_daemon_guidance(const Guidance& guidance, std::uint64_t sequence, TimestampNs now,
                                         std::int64_t wall_ns) {
  if (sequence >= guidance_sequence_) {
    guidance_ = guidance;
    guidance_sequence_ = sequence;
    guidance_at_ = now;
    guidance_wall_ns_ = wall_ns;
  }
  answered_at_ = now;
}

void GuidanceArbiter::on_daemon_estimate(std::uint32_t signal_id, EstimatorStatus status, std::uint64_t sequence,
                                         TimestampNs now, const GaussianPosition& relative) {
  status_[signal_id] = {status, sequence, relative};
  answered_at_ = now;
}

bool GuidanceArbiter::conflicts(const VictimEstimate& local, std::uint64_t sequence) const {
  const auto it = status_.find(local.signal_id);
  if (it == status_.end() || it->second.sequence != sequence) return false;
  if (it->second.status < EstimatorStatus::kConverged || local.status < EstimatorStatus::kConverged) return false;
  const Vec3 d = it->second.relative.position - local.relative.position;
  const Mat3 s = it->second.relative.covariance + local.relative.covariance;
  const Eigen::LDLT<Mat3> ldlt(s);
  if (ldlt.info() != Eigen::Success) return true;  // not a covariance: do not trust either
  return d.dot(ldlt.solve(d)) > kConflictGate;
}

void GuidanceArbiter::on_daemons_lost() {
  daemons_lost_ = seen_daemon_;
  status_.clear();
}

const GuidanceArbiter::SignalStatus* GuidanceArbiter::guided_signal_status() const {
  if (!guidance_) return nullptr;
  const auto it = status_.find(guidance_->signal_id);
  return it == status_.end() ? nullptr : &it->second;
}

bool GuidanceArbiter::answered(std::uint64_t sequence) const {
  if (guidance_sequence_ < sequence) return false;
  const auto* status = guided_signal_status();
  return status != nullptr && status->sequence >= sequence;
}

ArbiterDecision GuidanceArbiter::decide(const ArbiterInput& in) {
  ArbiterDecision d;
  const bool answered_ever = answered_at_ != 0;
  const bool alive = answered_ever && in.now - answered_at_ <= timeout_ns_;
  const bool fresh = guidance_ && in.now - guidance_at_ <= timeout_ns_;
  // Before any daemon answer, give it fallback_timeout_s from the start to show up.
  const bool grace = !answered_ever && in.now - started_ <= timeout_ns_;
  d.daemons_lost = daemons_lost_;
  d.daemon_reachable = (alive || grace) && !daemons_lost_;
  const bool this_epoch = in.sequence != 0 && guidance_sequence_ == in.sequence;
  if (this_epoch) d.latency_ms = static_cast<double>(guidance_wall_ns_ - in.published_wall_ns) / 1e6;

  bool use_daemon = false;
  if (fresh && !daemons_lost_ && this_epoch) {
    // An older status (or a previous daemon's) says nothing about the filter behind this guidance.
    const auto* status = guided_signal_status();
    const int daemon_rank = status == nullptr || status->sequence != in.sequence ? 0 : rank(status->status);
    const int local_rank =
        in.local_guidance && in.local_status ? rank(in.local_status(in.local_guidance->signal_id)) : 0;
    use_daemon = daemon_rank >= local_rank;
  }
  for (const auto& local : in.local_estimates) {
    if (in.sequence != 0 && conflicts(local, in.sequence)) d.conflicting_signals.insert(local.signal_id);
  }
  if (use_daemon && d.conflicting_signals.count(guidance_->signal_id) != 0) use_daemon = false;
  daemon_streak_ = use_daemon ? daemon_streak_ + 1 : 0;
  // Hysteresis: back from the device's own guidance only after rejoin_epochs good answers.
  if (use_daemon && followed_ == GuidanceSource::kLocal && in.local_guidance && daemon_streak_ < rejoin_epochs_) {
    use_daemon = false;
  }
  if (use_daemon) {
    d.guidance = guidance_;
    d.source = GuidanceSource::kDaemon;
    for (const auto& [signal, status] : status_) d.daemon_signals[signal] = status.status;
  } else if (in.local_guidance) {
    d.guidance = in.local_guidance;
    d.source = GuidanceSource::kLocal;
  }
  if (d.source != GuidanceSource::kNone) {
    if (followed_ != GuidanceSource::kNone && d.source != followed_) ++switches_;
    followed_ = d.source;
  }
  d.fell_back = was_reachable_ && !d.daemon_reachable;
  d.reconnected = !was_reachable_ && d.daemon_reachable && answered_ever;
  if (d.fell_back) ++fallbacks_;
  was_reachable_ = d.daemon_reachable;
  return d;
}

}  // namespace sarloc::responder
