#pragma once
// Which of an incident's incident-command instances publishes the picture (hot standby,
// docs/operations.md "Incident command that cannot be lost").
//
// Every instance reads the same inputs (victim estimates, responder positions) and keeps its
// fusion and team tracker warm; only the ACTIVE one publishes the picture (fused_victim,
// team_status, incident_summary, incident_frame). Those topics are OWNERSHIP EXCLUSIVE: every
// reader, an instance's own included, takes an instance's samples only from its strongest live
// writer. So an instance that receives another instance's incident summary knows that one is
// active and at least as strong. The rules (times are wall clock):
//
//   standby -> active   no other instance's summary is being received, and
//                       - the instance that was active was lost (its writer's liveliness lease
//                         ran out, or it left): at once; or it went silent: no summary for
//                         claim_wait_s + 2 x peer_period_s (it publishes one every cycle), in
//                         case the liveliness notice was missed or a late sample re-added it;
//                       - or none was ever heard: claim_wait_s + (instance - 1) x
//                         claim_stagger_s after start (at once when the incident runs a single
//                         instance). claim_wait_s is longer than the 3 s lease, so an instance
//                         (re)started while the active one is dying lets the standby take over
//                         first, and then stays standby.
//   active -> standby   another instance's summary arrives: it outranks this one (a reader only
//                       delivers the stronger writer's samples), e.g. two that claimed at once.
//
// Strength: a standby writes nothing and its writers keep strength 0. The active one raises
// them to active_strength(activated_at, instance): the earlier the activation, the stronger
// (4 less per second since 2025-01-01, from 2e9; the floor of 1 is reached in 2040, after which
// only the instance number orders them), so an instance that activates later (a restarted one
// that did not hear the active one in time) ranks below the incumbent and steps down; within
// one second the lower instance number wins.
//
//   StandbyArbiter arbiter(StandbyConfig{...}, wall_now);
//   arbiter.on_peer_sample("writer-guid", wall_now);  // another instance's IncidentSummary
//   arbiter.on_peer_lost("writer-guid", wall_now);    // its writer's liveliness was lost
//   if (const auto change = arbiter.decide(wall_now)) set_strength(change->strength), ...;
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "sarloc/core/common/types.hpp"

namespace sarloc::incident {

enum class CommandRole : std::uint8_t { kStandby = 0, kActive = 1 };

const char* to_string(CommandRole role);

/// At most this many instances of incident command per incident.
inline constexpr unsigned kMaxCommandInstances = 4;

struct StandbyConfig {
  unsigned instance = 1;         ///< this instance's number, 1..instances (sarloc-command --instance)
  unsigned instances = 1;        ///< instances the incident runs (command.instances)
  double claim_wait_s = 4.0;     ///< wall s without an active instance before claiming (> the 3 s lease)
  double claim_stagger_s = 1.0;  ///< wall s added per instance number above 1
  /// Wall s between the active instance's summaries (command.cycle_s; set by the node).
  double peer_period_s = 1.0;

  /// Throws ConfigError naming the key ("command.instances = 0: must be in [1, 4]").
  void validate() const;
};

/// A change of role decided by StandbyArbiter::decide.
struct RoleChange {
  CommandRole role = CommandRole::kStandby;
  std::uint32_t strength = 0;  ///< ownership strength the picture writers take now
  std::string reason;          ///< for the log
};

class StandbyArbiter {
 public:
  StandbyArbiter(StandbyConfig config, TimestampNs start_wall_ns);

  /// Another instance's incident summary reached this instance's (exclusive) reader.
  void on_peer_sample(const std::string& writer, TimestampNs now);
  /// That writer's liveliness was lost (lease expired, or it left). Unknown writers (a standby
  /// that never wrote) are ignored.
  void on_peer_lost(const std::string& writer, TimestampNs now);

  /// The new role when it changes now, else nothing.
  std::optional<RoleChange> decide(TimestampNs now);

  CommandRole role() const { return role_; }
  /// Ownership strength of this instance's picture writers now (0 while standby).
  std::uint32_t strength() const { return strength_; }
  /// An active peer is being heard.
  bool peer_active() const { return !peers_.empty(); }
  const StandbyConfig& config() const { return config_; }

  /// Strength of an instance that became active at `activated_wall_ns` (see above).
  static std::uint32_t active_strength(TimestampNs activated_wall_ns, unsigned instance);

 private:
  StandbyConfig config_;
  TimestampNs start_;
  CommandRole role_ = CommandRole::kStandby;
  std::uint32_t strength_ = 0;
  std::map<std::string, TimestampNs> peers_;  ///< active writers heard, last sample time
  std::optional<TimestampNs> owner_lost_at_;  ///< when the last active peer was lost
};

}  // namespace sarloc::incident
