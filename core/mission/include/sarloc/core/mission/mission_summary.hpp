#pragma once
// The outcome of a simulated mission against its truth: per buried victim (matched, error,
// time to locate, found in the picture, and which finders' devices found it: a victim found
// while no incident command was alive is missing from the picture but not from its finder),
// every victim of the picture (a confirmed one that matches no buried victim is a ghost), per
// rescuer what its device knew, and the injected faults.
// sarloc-mission prints and writes it (apps/common json_io.hpp); the post-mission report
// reuses it.
//
//   MissionSummary s = summarise_mission(scenario, picture_victims, epoch, device_summaries);
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sarloc/core/incident/alarm_board.hpp"
#include "sarloc/core/incident/fused_victim.hpp"
#include "sarloc/core/incident/team_status.hpp"
#include "sarloc/core/mission/firefighter_summary.hpp"
#include "sarloc/core/mission/mission_scenario.hpp"
#include "sarloc/core/responder/victim_estimate.hpp"

namespace sarloc::mission {

/// One victim signal a rescuer's device heard during the mission.
struct DeviceSignal {
  std::uint32_t signal_id = 0;
  /// The furthest its estimate got (FOUND stays FOUND after the rescuer walks out of range).
  responder::EstimatorStatus status = responder::EstimatorStatus::kInitialising;
  /// Simulation truth: the buried victim a FOUND named (found_victim.hpp), else the one most of
  /// the signal's samples came from.
  std::optional<std::size_t> victim_index;
  std::optional<double> relative_error_m;      ///< the device's own error when it was found
  std::optional<double> radius95_m;            ///< the 95 % radius (3-D) it stated then
};

/// What a rescuer's device knew at the end (sarloc-rescuer --summary).
struct DeviceSummary {
  std::string rescuer_id;
  std::size_t epochs = 0;
  double distance_walked_m = 0.0;
  int fallbacks = 0;
  int guidance_switches = 0;  ///< epochs whose guidance source (daemon / device) changed
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
  bool found = false;                            ///< FOUND in the incident picture
  std::optional<double> found_at_s;              ///< mission seconds, as the picture says
  /// survival_outlook.hpp: minutes buried when dug out from its FOUND, and the survival curve there.
  std::optional<double> dug_out_min;
  std::optional<double> survival;
  std::optional<double> relative_error_m;        ///< best finder device's own error (no GNSS)
  /// Finders whose FOUND was farther from the victim than their stated 95 % radius + 0.5 m.
  std::size_t false_found = 0;
  /// Rescuers whose device reported this victim's signal FOUND (its summary), by id: what
  /// the finders know, whether or not an incident command was alive to put it in the picture.
  std::vector<std::string> finders;

  bool found_by_finder() const { return !finders.empty(); }
};

struct PictureVictimOutcome {
  std::uint32_t victim_id = 0;
  Vec3 position = Vec3::Zero();
  bool confirmed = false;                        ///< LOCATED or FOUND
  bool found = false;
  bool dug_out = false;                          ///< recovered: reported dug out
  std::vector<std::string> source_names;         ///< "rescuer/signal", for tracing a twin or a ghost
  std::uint32_t possibly_same_as = 0;            ///< FusedVictim::possibly_same_as
  double radius95_m = 0.0;                       ///< the fused position's 95 % radius (worst axis)
  bool matches_a_buried_victim = false;
  bool evidence_conflict = false;                ///< incident command flagged conflicting estimates
  std::optional<double> located_at_s;            ///< mission seconds, as the picture says
  std::optional<double> found_at_s;
};

struct FaultOutcome {
  std::string action;                            ///< "kill" or "restart"
  std::string target;
  double at_s = 0.0;
  bool done = false;
  std::optional<double> link_lost_after_s;       ///< rescuer kills: until command reported it
  /// Incident-command kills: wall seconds until another instance's picture arrived, and its node.
  std::optional<double> handover_after_s;
  std::string taken_over_by;
  /// Incident-command kills: the picture as the mission saw it at the kill.
  std::vector<PictureVictimOutcome> picture_at_kill;
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
  /// Firefighters of a building mission: their devices' summaries (firefighter_summary.hpp),
  /// and the alarms incident command's picture held (kind, responder, mission second raised).
  std::vector<FirefighterDeviceSummary> firefighters;
  std::vector<std::string> firefighters_without_summary;
  struct PictureAlarm {
    std::uint32_t alarm_id = 0;
    std::string kind, responder_id;
    double raised_s = 0.0;
    std::optional<double> cleared_s;
  };
  std::vector<PictureAlarm> picture_alarms;
  /// Each responder's link in the picture once the devices stopped ("alive", "stale", "lost",
  /// "signed_off": incident::to_string): a device stopped in order is signed off, a killed one lost.
  std::map<std::string, std::string> links_at_end;
  /// Whether a sarloc-command process was still running when the mission stopped, and
  /// whether an active one was publishing the picture then: when not, `victims[].found` only
  /// tells what the picture knew before it was lost, and `finders` what the devices know.
  bool command_alive_at_end = true;
  bool picture_available = true;
  /// survival_outlook.hpp (absent until added): the sum of the FOUND victims' survival, and for
  /// the victims never FOUND, how many and the most they could still get together.
  std::optional<double> expected_survivors;
  double unfound_survival_at_most = 0.0;
  std::size_t unfound_count = 0;

  std::size_t confirmed_fused_victim_count() const;
  std::size_t found_count() const;               ///< FOUND in the picture
  std::size_t found_by_finder_count() const;     ///< FOUND by some finder's device
};

/// The picture's victims against the truth (matched to a buried victim or not), times in
/// mission seconds since `epoch`.
std::vector<PictureVictimOutcome> picture_outcomes(const MissionScenario& scenario,
                                                   const std::vector<incident::FusedVictim>& picture,
                                                   TimestampNs epoch);

/// Matches the picture to the truth (victim_matching.hpp) and fills the summary; mission_s,
/// wall_s and faults are the caller's.
MissionSummary summarise_mission(const std::string& mission_name, const MissionScenario& scenario,
                                 const std::vector<incident::FusedVictim>& picture, TimestampNs epoch,
                                 std::map<std::string, DeviceSummary> devices);

/// What a mission saw when it stopped, beside its truth: the picture, the devices' summaries,
/// the faults' outcomes, and its times (sarloc-mission).
struct MissionEnd {
  std::vector<incident::FusedVictim> picture;
  std::map<std::string, DeviceSummary> devices;  ///< avalanche rescuers that wrote a summary
  std::vector<FirefighterDeviceSummary> firefighters;
  std::vector<std::string> firefighters_without_summary;
  std::vector<incident::IncidentAlarm> alarms;         ///< every alarm the picture held
  std::map<std::string, incident::LinkState> links;    ///< once the devices stopped
  std::vector<FaultOutcome> faults;
  double mission_s = 0.0;
  double wall_s = 0.0;
  bool command_alive_at_end = true;
  bool picture_available = true;
  /// survival_outlook.hpp (absent until added): the sum of the FOUND victims' survival, and for
  /// the victims never FOUND, how many and the most they could still get together.
  std::optional<double> expected_survivors;
  double unfound_survival_at_most = 0.0;
  std::size_t unfound_count = 0;
};

/// summarise_mission, and the rest of `end` in the summary's terms (alarm kinds and link
/// states as text, times in mission seconds since `epoch`).
MissionSummary assemble_mission_summary(const std::string& mission_name, const MissionScenario& scenario,
                                        TimestampNs epoch, MissionEnd end);

}  // namespace sarloc::mission
