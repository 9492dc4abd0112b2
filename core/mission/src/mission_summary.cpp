#include "sarloc/core/mission/mission_summary.hpp"

#include <algorithm>

#include "sarloc/core/avalanche/found_victim.hpp"
#include "sarloc/core/common/time_units.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "sarloc/core/mission/victim_matching.hpp"

namespace sarloc::mission {
namespace {

// The diggers' view of a victim: the smallest error of a device that found it, relative to
// that device (no GNSS involved).
std::optional<double> relative_error_of(std::size_t victim, const std::map<std::string, DeviceSummary>& devices) {
  std::optional<double> best;
  for (const auto& [id, device] : devices) {
    for (const auto& s : device.signals) {
      if (s.victim_index != victim || s.status != responder::EstimatorStatus::kFound || !s.relative_error_m) continue;
      if (!best || *s.relative_error_m < *best) best = s.relative_error_m;
    }
  }
  return best;
}

// A finder's FOUND must hold within its own stated uncertainty (+ kFalseFoundMarginM: the
// probe's reach). A device's FOUND names the victim within that reach (found_victim.hpp), so a
// FOUND counted here is near no victim at all.
std::size_t false_found_of(std::size_t victim, const std::map<std::string, DeviceSummary>& devices) {
  std::size_t n = 0;
  for (const auto& [id, device] : devices) {
    for (const auto& s : device.signals) {
      if (s.victim_index != victim || s.status != responder::EstimatorStatus::kFound) continue;
      if (s.relative_error_m && s.radius95_m && *s.relative_error_m > *s.radius95_m + avalanche::kFalseFoundMarginM) ++n;
    }
  }
  return n;
}

std::vector<std::string> finders_of(std::size_t victim, const std::map<std::string, DeviceSummary>& devices) {
  std::vector<std::string> out;  // std::map: by rescuer id
  for (const auto& [id, device] : devices) {
    const bool found = std::any_of(device.signals.begin(), device.signals.end(), [&](const DeviceSignal& s) {
      return s.victim_index == victim && s.status == responder::EstimatorStatus::kFound;
    });
    if (found) out.push_back(id);
  }
  return out;
}

std::optional<double> mission_seconds(TimestampNs t, TimestampNs epoch) {
  if (t == 0) return std::nullopt;
  return ns_to_seconds(t - epoch);
}

}  // namespace

std::size_t MissionSummary::found_by_finder_count() const {
  return static_cast<std::size_t>(
      std::count_if(victims.begin(), victims.end(), [](const auto& v) { return v.found_by_finder(); }));
}

namespace {

// `match`: match_to_truth of the picture.
std::vector<PictureVictimOutcome> outcomes_of(const std::vector<incident::FusedVictim>& picture,
                                              const std::vector<int>& match, TimestampNs epoch) {
  std::vector<PictureVictimOutcome> out;
  for (std::size_t j = 0; j < picture.size(); ++j) {
    const auto& f = picture[j];
    PictureVictimOutcome p;
    p.victim_id = f.victim_id;
    p.position = f.position.position;
    p.confirmed = f.state != incident::VictimState::kUnconfirmed;
    p.found = incident::is_found(f.state);
    p.dug_out = f.state == incident::VictimState::kRecovered;
    for (const auto& vs : f.sources) p.source_names.push_back(vs.rescuer_id + "/" + std::to_string(vs.signal_id));
    p.possibly_same_as = f.possibly_same_as;
    p.radius95_m = radius95_3d(f.position.covariance);
    p.evidence_conflict = f.evidence_conflict;
    p.matches_a_buried_victim = std::find(match.begin(), match.end(), static_cast<int>(j)) != match.end();
    p.located_at_s = mission_seconds(f.located_at, epoch);
    p.found_at_s = mission_seconds(f.found_at, epoch);
    out.push_back(p);
  }
  return out;
}

}  // namespace

std::vector<PictureVictimOutcome> picture_outcomes(const MissionScenario& scenario,
                                                   const std::vector<incident::FusedVictim>& picture,
                                                   TimestampNs epoch) {
  return outcomes_of(picture, match_to_truth(scenario.victims, picture), epoch);
}

std::size_t MissionSummary::confirmed_fused_victim_count() const {
  return static_cast<std::size_t>(
      std::count_if(fused_victims.begin(), fused_victims.end(), [](const auto& v) { return v.confirmed; }));
}

std::size_t MissionSummary::found_count() const {
  return static_cast<std::size_t>(std::count_if(victims.begin(), victims.end(), [](const auto& v) { return v.found; }));
}

MissionSummary summarise_mission(const std::string& mission_name, const MissionScenario& scenario,
                                 const std::vector<incident::FusedVictim>& picture, TimestampNs epoch,
                                 std::map<std::string, DeviceSummary> devices) {
  MissionSummary s;
  s.mission = mission_name;
  const auto match = match_to_truth(scenario.victims, picture);
  s.all_found = true;
  for (std::size_t i = 0; i < scenario.victims.size(); ++i) {
    const auto& truth = scenario.victims[i];
    VictimOutcome v;
    v.name = truth.name;
    v.true_position = truth.position;
    if (match[i] >= 0) {
      const auto& f = picture[static_cast<std::size_t>(match[i])];
      v.victim_id = f.victim_id;
      v.estimate = f.position.position;
      v.error_m = (f.position.position - truth.position).norm();
      v.sources = f.sources.size();
      v.found = incident::is_found(f.state);
      v.time_to_locate_s = mission_seconds(f.located_at, epoch);
      if (v.found) v.found_at_s = mission_seconds(f.found_at, epoch);
    }
    v.relative_error_m = relative_error_of(i, devices);
    v.false_found = false_found_of(i, devices);
    v.finders = finders_of(i, devices);
    s.all_found = s.all_found && v.found;
    s.victims.push_back(std::move(v));
  }
  s.fused_victims = outcomes_of(picture, match, epoch);
  for (const auto& r : scenario.rescuers) s.rescuer_ids.push_back(r.id);
  s.devices = std::move(devices);
  return s;
}

MissionSummary assemble_mission_summary(const std::string& mission_name, const MissionScenario& scenario,
                                        TimestampNs epoch, MissionEnd end) {
  auto summary = summarise_mission(mission_name, scenario, end.picture, epoch, std::move(end.devices));
  summary.firefighters = std::move(end.firefighters);
  summary.firefighters_without_summary = std::move(end.firefighters_without_summary);
  for (const auto& a : end.alarms) {
    MissionSummary::PictureAlarm p;
    p.alarm_id = a.alarm_id;
    p.kind = responder::to_string(a.alarm.kind);
    p.responder_id = a.alarm.responder_id;
    p.raised_s = 1e-9 * static_cast<double>(a.alarm.raised_at - epoch);
    if (!a.alarm.active) p.cleared_s = 1e-9 * static_cast<double>(a.alarm.cleared_at - epoch);
    summary.picture_alarms.push_back(p);
  }
  for (const auto& [id, link] : end.links) summary.links_at_end[id] = incident::to_string(link);
  summary.mission_s = end.mission_s;
  summary.wall_s = end.wall_s;
  summary.command_alive_at_end = end.command_alive_at_end;
  summary.picture_available = end.picture_available;
  summary.faults = std::move(end.faults);
  return summary;
}

}  // namespace sarloc::mission
