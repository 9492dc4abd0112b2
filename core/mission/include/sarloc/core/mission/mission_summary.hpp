#pragma once
// The outcome of a simulated mission against its truth: per buried victim (matched, error,
// time to locate, found), every victim of the picture (a confirmed one that matches no buried
// victim is a ghost), per rescuer what its device knew, and the injected faults.
// sarloc-mission prints and writes it (apps/common json_io.hpp); the post-mission report
// reuses it.
//
//   MissionSummary s = summarise_mission(scenario, picture_victims, epoch, device_summaries);
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sarloc/core/incident/fused_victim.hpp"
#include "sarloc/core/mission/mission_scenario.hpp"
#include "sarloc/core/responder/victim_estimate.hpp"

namespace sarloc::mission {

/// One victim signal as a rescuer's device last saw it.
struct DeviceSignal {
  std::uint32_t signal_id = 0;
  responder::EstimatorStatus status = responder::EstimatorStatus::kInitialising;
  std::optional<std::size_t> victim_index;     ///< simulation truth: which buried victim
  std::optional<double> relative_error_m;      ///< the device's own error when it was found
  std::optional<double> radius95_m;            ///< the 95 % radius (3-D) it stated then
};

/// What a rescuer's device knew at the end (sarloc-rescuer --summary).
struct DeviceSummary {
  std::string rescuer_id;
  std::size_t epochs = 0;
  double distance_walked_m = 0.0;
  int fallbacks = 0;
  std::map<std::string, std::size_t> guided_by;  ///< epochs per guidance source
  std::size_t daemon_after_fallback = 0;         ///< daemon-guided epochs after the first fallback
  std::size_t latency_samples = 0;
  std::optional<double> latency_p50_ms, latency_p99_ms;  ///< absent without any daemon answer
  std::vector<DeviceSignal> signals;
  std::optional<double> gnss_error_m;            ///< last fix against the true antenna
};

struct VictimOutcome {
  std::string name;
  Vec3 true_position = Vec3::Zero();
  std::optional<std::uint32_t> victim_id;        ///< the matched victim of the picture
  std::optional<Vec3> estimate;
  std::optional<double> error_m;
  std::size_t sources = 0;
  std::optional<double> time_to_locate_s;        ///< mission seconds
  bool found = false;
  std::optional<double> relative_error_m;        ///< best finder device's own error (no GNSS)
  /// Finders whose FOUND was farther from the victim than their stated 95 % radius + 0.5 m.
  std::size_t false_found = 0;
};

struct PictureVictimOutcome {
  std::uint32_t victim_id = 0;
  Vec3 position = Vec3::Zero();
  bool confirmed = false;                        ///< LOCATED or FOUND
  bool found = false;
  std::size_t sources = 0;
  bool matches_a_buried_victim = false;
  bool evidence_conflict = false;                ///< incident command flagged conflicting estimates
};

struct FaultOutcome {
  std::string action;                            ///< "kill" or "restart"
  std::string target;
  double at_s = 0.0;
  bool done = false;
  std::optional<double> link_lost_after_s;       ///< rescuer kills: until command reported it
};

struct MissionSummary {
  std::string mission;
  std::vector<VictimOutcome> victims;            ///< one per buried victim, in scenario order
  std::vector<PictureVictimOutcome> fused_victims;
  bool all_found = false;
  double mission_s = 0.0;
  double wall_s = 0.0;
  std::vector<std::string> rescuer_ids;          ///< scenario order
  std::map<std::string, DeviceSummary> devices;  ///< those that wrote a summary
  std::vector<FaultOutcome> faults;

  std::size_t confirmed_fused_victim_count() const;
  std::size_t found_count() const;
};

/// Matches the picture to the truth (victim_matching.hpp) and fills the summary; mission_s,
/// wall_s and faults are the caller's.
MissionSummary summarise_mission(const std::string& mission_name, const MissionScenario& scenario,
                                 const std::vector<incident::FusedVictim>& picture, TimestampNs epoch,
                                 std::map<std::string, DeviceSummary> devices);

}  // namespace sarloc::mission
