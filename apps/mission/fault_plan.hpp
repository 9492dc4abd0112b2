#pragma once
// sarloc-mission's fault injection as a plan: which process to kill or restart at which
// mission second (--kill TARGET@SECONDS, --restart TARGET@SECONDS), and what the picture showed
// afterwards (how long until incident command reported a killed device's link lost; how long
// until another incident-command instance published the picture). No processes and no DDS:
// the mission's loop asks due() what to do now and reports what it saw (observe_*), with the
// time of its steady clock, so a fake clock tests it.
//
//   auto plan = FaultPlan::parse({"core@40", "r2@60"}, {"core@55"});
//   for (Fault* f : plan.due(mission_s, now)) act_on(*f);
//   plan.observe_links(picture_links, now);
#include <chrono>
#include <map>
#include <string>
#include <vector>

#include "sarloc/core/incident/fused_victim.hpp"
#include "sarloc/core/incident/team_status.hpp"
#include "sarloc/core/mission/mission_summary.hpp"

namespace sarloc::app {

struct Fault {
  using TimePoint = std::chrono::steady_clock::time_point;
  bool restart = false;  ///< --restart (start again what an earlier --kill stopped) instead of --kill
  std::string target;    ///< "core", "command" (the active instance) or a device id
  double at_s = 0.0;     ///< mission seconds
  bool done = false;
  TimePoint when{};
  double link_lost_after_s = -1.0;  ///< device kills: wall seconds until command reported it lost
  // Incident-command faults.
  unsigned instance = 0;           ///< which sarloc-command instance (1..); restarts: the one killed last
  std::string killed_participant;  ///< its DDS participant (GUID prefix), if known
  double handover_after_s = -1.0;  ///< wall seconds until another instance's picture arrived
  std::string taken_over_by;       ///< that instance's node id
  std::vector<incident::FusedVictim> picture_at_kill;

  bool is_device_kill() const { return !restart && target != "core" && target != "command"; }
  bool is_command_kill() const { return !restart && target == "command"; }
};

/// "TARGET@SECONDS" of --kill (restart false) or --restart; throws ConfigError naming the option.
Fault parse_fault(const std::string& text, bool restart);

class FaultPlan {
 public:
  using TimePoint = Fault::TimePoint;

  FaultPlan() = default;
  /// Throws ConfigError for a malformed item, or a restart of anything but core or command.
  static FaultPlan parse(const std::vector<std::string>& kills, const std::vector<std::string>& restarts);

  /// The faults due at `mission_s`, in the order given, marked done at `now`. A command
  /// restart names the instance the latest command kill stopped (0: none was killed).
  std::vector<Fault*> due(double mission_s, TimePoint now);

  /// The picture's links now: a killed device reported lost is timed once.
  void observe_links(const std::map<std::string, incident::LinkState>& links, TimePoint now);
  /// The picture's publisher now (`owner`, publishing since `owner_since`, node `owner_node`):
  /// a command kill is handed over once another participant publishes after the kill.
  void observe_publisher(const std::string& owner, TimePoint owner_since, const std::string& owner_node);

  /// A fault done less than `patience` ago still waits for what it should show: a killed
  /// device's link lost; a killed command's handover when the incident runs several instances.
  bool awaiting_observation(TimePoint now, unsigned command_instances,
                            std::chrono::seconds patience = std::chrono::seconds(30)) const;
  /// A device of this id was killed (and not restarted: devices are not restarted).
  bool killed(const std::string& device_id) const;

  const std::vector<Fault>& faults() const { return faults_; }
  /// The outcomes as the summary reports them (picture at each kill matched to the truth).
  std::vector<mission::FaultOutcome> outcomes(const mission::MissionScenario& scenario, TimestampNs epoch) const;

 private:
  std::vector<Fault> faults_;
};

}  // namespace sarloc::app
