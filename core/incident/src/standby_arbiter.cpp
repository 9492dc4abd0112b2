#include "sarloc/core/common/time_units.hpp"
#include "sarloc/core/incident/standby_arbiter.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::incident {
namespace {

constexpr std::int64_t kStrengthEpochS = 1'735'689'600;  // 2025-01-01T00:00:00Z
constexpr std::int64_t kStrengthCeiling = 2'000'000'000;
constexpr std::int64_t kStrengthPerSecond = 4;            // >= kMaxCommandInstances

}  // namespace

const char* to_string(CommandRole role) { return role == CommandRole::kActive ? "active" : "standby"; }

void StandbyConfig::validate() const {
  require(instances >= 1 && instances <= kMaxCommandInstances, "command.instances", instances,
          "must be in [1, " + std::to_string(kMaxCommandInstances) + "]");
  require(instance >= 1 && instance <= instances, "--instance", instance,
          "must be in [1, command.instances = " + std::to_string(instances) + "]");
  require(std::isfinite(claim_wait_s) && claim_wait_s >= 0.0 && claim_wait_s <= 600.0, "command.claim_wait_s",
          claim_wait_s, "must be in [0, 600]");
  require(std::isfinite(claim_stagger_s) && claim_stagger_s >= 0.0 && claim_stagger_s <= 60.0,
          "command.claim_stagger_s", claim_stagger_s, "must be in [0, 60]");
  require(std::isfinite(peer_period_s) && peer_period_s > 0.0 && peer_period_s <= 60.0, "command.cycle_s",
          peer_period_s, "must be in (0, 60]");
}

StandbyArbiter::StandbyArbiter(StandbyConfig config, TimestampNs start_wall_ns)
    : config_(config), start_(start_wall_ns) {
  config_.validate();
}

std::uint32_t StandbyArbiter::active_strength(TimestampNs activated_wall_ns, unsigned instance) {
  const std::int64_t since = std::max<std::int64_t>(0, activated_wall_ns / 1'000'000'000 - kStrengthEpochS);
  const std::int64_t s = kStrengthCeiling - kStrengthPerSecond * std::min<std::int64_t>(since, kStrengthCeiling) -
                         static_cast<std::int64_t>(std::clamp(instance, 1U, kMaxCommandInstances) - 1);
  return static_cast<std::uint32_t>(std::max<std::int64_t>(1, s));
}

void StandbyArbiter::on_peer_sample(const std::string& writer, TimestampNs now) {
  peers_[writer] = now;
  owner_lost_at_.reset();
}

void StandbyArbiter::on_peer_lost(const std::string& writer, TimestampNs now) {
  if (peers_.erase(writer) == 0) return;
  if (peers_.empty()) owner_lost_at_ = now;
}

std::optional<RoleChange> StandbyArbiter::decide(TimestampNs now) {
  // A peer silent for longer than its lease allows is lost, notice or not.
  const auto silence = seconds_to_ns(config_.claim_wait_s + 2.0 * config_.peer_period_s);
  bool went_silent = false;
  for (auto it = peers_.begin(); it != peers_.end();) {
    if (now - it->second > silence) {
      it = peers_.erase(it);
      went_silent = true;
    } else {
      ++it;
    }
  }
  if (went_silent && peers_.empty()) owner_lost_at_ = now;
  if (role_ == CommandRole::kActive) {
    if (peers_.empty()) return std::nullopt;
    role_ = CommandRole::kStandby;
    strength_ = 0;
    return RoleChange{role_, strength_, "a stronger instance publishes the picture (" + peers_.begin()->first + ")"};
  }
  if (!peers_.empty()) return std::nullopt;
  std::string reason;
  if (owner_lost_at_) {
    reason = "the active instance was lost";
  } else {
    const double wait_s = config_.instances == 1
                              ? 0.0
                              : config_.claim_wait_s + (config_.instance - 1) * config_.claim_stagger_s;
    if (static_cast<double>(now - start_) < wait_s * 1e9) return std::nullopt;
    std::ostringstream os;
    os << "no active instance heard for " << wait_s << " s";
    reason = config_.instances == 1 ? "the only instance" : os.str();
  }
  role_ = CommandRole::kActive;
  strength_ = active_strength(now, config_.instance);
  return RoleChange{role_, strength_, reason};
}

}  // namespace sarloc::incident
