#include "fault_plan.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::app {

Fault parse_fault(const std::string& text, bool restart) {
  const std::string option = restart ? "--restart" : "--kill";
  const auto at = text.rfind('@');
  if (at == std::string::npos || at == 0) throw ConfigError(option + " = '" + text + "': expected TARGET@SECONDS");
  Fault f;
  f.restart = restart;
  f.target = text.substr(0, at);
  try {
    f.at_s = std::stod(text.substr(at + 1));
  } catch (const std::exception&) {
    throw ConfigError(option + " = '" + text + "': '" + text.substr(at + 1) + "' is not a number of seconds");
  }
  if (!(f.at_s >= 0.0)) throw ConfigError(option + " = '" + text + "': time must be >= 0");
  if (restart && f.target != "core" && f.target != "command") {
    throw ConfigError(option + " = '" + text + "': only core or command can be restarted");
  }
  return f;
}

FaultPlan FaultPlan::parse(const std::vector<std::string>& kills, const std::vector<std::string>& restarts) {
  FaultPlan plan;
  for (const auto& k : kills) plan.faults_.push_back(parse_fault(k, false));
  for (const auto& r : restarts) plan.faults_.push_back(parse_fault(r, true));
  return plan;
}

std::vector<Fault*> FaultPlan::due(double mission_s, TimePoint now) {
  std::vector<Fault*> due;
  for (auto& f : faults_) {
    if (f.done || mission_s < f.at_s) continue;
    f.done = true;
    f.when = now;
    if (f.restart && f.target == "command") {
      f.instance = 0;
      for (const auto& k : faults_) {
        if (k.is_command_kill() && k.done && k.instance > 0) f.instance = k.instance;
      }
    }
    due.push_back(&f);
  }
  return due;
}

void FaultPlan::observe_links(const std::map<std::string, incident::LinkState>& links, TimePoint now) {
  for (auto& f : faults_) {
    if (!f.done || f.link_lost_after_s >= 0.0 || !f.is_device_kill()) continue;
    const auto it = links.find(f.target);
    if (it == links.end() || it->second != incident::LinkState::kLost) continue;
    f.link_lost_after_s = std::chrono::duration<double>(now - f.when).count();
    spdlog::info("incident command reports the link to {} lost after {:.1f} s", f.target, f.link_lost_after_s);
  }
}

void FaultPlan::observe_publisher(const std::string& owner, TimePoint owner_since, const std::string& owner_node) {
  for (auto& f : faults_) {
    if (!f.done || !f.is_command_kill() || f.handover_after_s >= 0.0) continue;
    // Handed over: the picture comes from another participant than the killed one, since after the kill.
    if (owner.empty() || owner == f.killed_participant || owner_since <= f.when) continue;
    f.handover_after_s = std::chrono::duration<double>(owner_since - f.when).count();
    f.taken_over_by = owner_node.empty() ? owner : owner_node;
    spdlog::info("{} took the incident picture over {:.2f} s after the kill", f.taken_over_by, f.handover_after_s);
  }
}

bool FaultPlan::awaiting_observation(TimePoint now, unsigned command_instances, std::chrono::seconds patience) const {
  return std::any_of(faults_.begin(), faults_.end(), [&](const Fault& f) {
    const bool pending = (f.is_device_kill() && f.link_lost_after_s < 0.0) ||
                         (f.is_command_kill() && f.handover_after_s < 0.0 && command_instances > 1);
    return f.done && pending && now - f.when < patience;
  });
}

bool FaultPlan::killed(const std::string& device_id) const {
  return std::any_of(faults_.begin(), faults_.end(),
                     [&](const Fault& f) { return f.done && f.is_device_kill() && f.target == device_id; });
}

std::vector<mission::FaultOutcome> FaultPlan::outcomes(const mission::MissionScenario& scenario,
                                                       TimestampNs epoch) const {
  std::vector<mission::FaultOutcome> out;
  for (const auto& f : faults_) {
    mission::FaultOutcome outcome;
    outcome.action = f.restart ? "restart" : "kill";
    outcome.target = f.target;
    outcome.at_s = f.at_s;
    outcome.done = f.done;
    if (f.link_lost_after_s >= 0.0) outcome.link_lost_after_s = f.link_lost_after_s;
    if (f.handover_after_s >= 0.0) outcome.handover_after_s = f.handover_after_s;
    outcome.taken_over_by = f.taken_over_by;
    outcome.picture_at_kill = mission::picture_outcomes(scenario, f.picture_at_kill, epoch);
    out.push_back(outcome);
  }
  return out;
}

}  // namespace sarloc::app
