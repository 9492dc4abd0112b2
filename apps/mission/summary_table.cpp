#include "summary_table.hpp"

#include <cstdio>

namespace sarloc::app {
namespace {

std::string optional_text(const std::optional<double>& v, const char* format) {
  if (!v) return "-";
  char buf[32];
  std::snprintf(buf, sizeof(buf), format, *v);
  return buf;
}

std::string position_text(const Vec3& p) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "(%.1f, %.1f, %.1f)", p.x(), p.y(), p.z());
  return buf;
}

// "yes" (FOUND in the picture), "finder" (only its finders' devices know: no picture), "NO".
const char* found_text(const mission::VictimOutcome& v) {
  if (v.found) return "yes";
  return v.found_by_finder() ? "finder" : "NO";
}

std::string finders_text(const mission::VictimOutcome& v) {
  std::string out;
  for (const auto& id : v.finders) out += (out.empty() ? "" : ",") + id;
  return out.empty() ? "-" : out;
}

}  // namespace

void print_summary(const mission::MissionSummary& s, const std::string& run_dir) {
  std::printf("\n%-10s %-26s %-26s %8s %10s %10s %8s %6s %-10s %8s %9s\n", "victim", "true position (E N U) m",
              "fused estimate m", "error m", "finder m", "located s", "found s", "found", "found by", "dug min",
              "survival");
  for (const auto& v : s.victims) {
    std::printf(
        "%-10s %-26s %-26s %8s %10s %10s %8s %6s %-10s %8s %9s\n", v.name.c_str(),
        position_text(v.true_position).c_str(), v.estimate ? position_text(*v.estimate).c_str() : "-",
        optional_text(v.error_m, "%.2f").c_str(), optional_text(v.relative_error_m, "%.2f").c_str(),
        optional_text(v.time_to_locate_s, "%.0f").c_str(), optional_text(v.found_at_s, "%.0f").c_str(), found_text(v),
        finders_text(v).c_str(), optional_text(v.dug_out_min, "%.1f").c_str(),
        optional_text(v.survival ? std::optional<double>(100.0 * *v.survival) : std::nullopt, "%.0f %%").c_str());
  }
  if (s.expected_survivors) {
    std::printf("\nexpected survivors (survival curve at each FOUND victim's dig-out, dug from its FOUND): %.2f of %zu",
                *s.expected_survivors, s.victims.size());
    if (s.unfound_count > 0)
      std::printf("; %zu not found, who could add at most %.2f", s.unfound_count, s.unfound_survival_at_most);
    std::printf("\n");
  }
  std::printf("\n%-10s %18s %10s %18s %22s\n", "rescuer", "distance walked m", "fallbacks", "guidance switches",
              "latency p50/p99 ms");
  for (const auto& id : s.rescuer_ids) {
    const auto it = s.devices.find(id);
    if (it == s.devices.end()) {
      std::printf("%-10s %18s\n", id.c_str(), "(no summary: killed?)");
      continue;
    }
    const auto& d = it->second;
    std::printf("%-10s %18.1f %10d %18d %10.1f / %-10.1f\n", id.c_str(), d.distance_walked_m, d.fallbacks,
                d.guidance_switches, d.latency_p50_ms.value_or(-1.0), d.latency_p99_ms.value_or(-1.0));
  }
  if (!s.firefighters.empty() || !s.firefighters_without_summary.empty()) {
    std::printf("\n%-11s %-6s %8s %7s %10s %12s %9s %11s %6s %9s %9s  %s\n", "firefighter", "team", "walked m",
                "floors", "converge s", "RMSE after m", "map err %", "confirmed %", "DR s", "own max m", "own out %",
                "alarms (delay from the true event)");
    for (const auto& f : s.firefighters) {
      std::string alarms;
      for (const auto& a : f.alarms) {
        char buf[128];
        std::snprintf(buf, sizeof(buf), "%s%s at %.1f s%s", alarms.empty() ? "" : "; ", a.kind.c_str(), a.raised_s,
                      a.delay_s ? (" (+" + optional_text(a.delay_s, "%.2f") + " s)").c_str() : "");
        alarms += buf;
        if (a.cleared_s) alarms += ", cleared at " + optional_text(a.cleared_s, "%.1f") + " s";
      }
      std::string floors;
      for (const auto floor : f.floors_visited) floors += (floors.empty() ? "" : ",") + std::to_string(floor);
      const double own_out = f.own_positions > 0
                                 ? 100.0 * static_cast<double>(f.own_outside_99) / static_cast<double>(f.own_positions)
                                 : 0.0;
      std::printf("%-11s %-6s %8.1f %7s %10s %12s %9.1f %11.1f %6.1f %9s %9.1f  %s\n", f.responder_id.c_str(),
                  f.team.c_str(), f.distance_walked_m, floors.c_str(),
                  optional_text(f.time_to_converge_s, "%.1f").c_str(),
                  optional_text(f.rmse_after_convergence_m, "%.2f").c_str(), 100.0 * f.map_error_share,
                  100.0 * f.confirmed_share, f.dead_reckoning_s, optional_text(f.own_max_error_m, "%.2f").c_str(),
                  own_out, alarms.empty() ? "-" : alarms.c_str());
    }
    for (const auto& id : s.firefighters_without_summary) std::printf("%-10s (no summary: killed?)\n", id.c_str());
    std::printf("\nalarms in the incident picture:");
    if (s.picture_alarms.empty()) std::printf(" none");
    for (const auto& a : s.picture_alarms) {
      std::printf("\n  %u %-10s %-8s raised at %.1f s%s", a.alarm_id, a.kind.c_str(), a.responder_id.c_str(), a.raised_s,
                  a.cleared_s ? (", cleared at " + optional_text(a.cleared_s, "%.1f") + " s").c_str() : "");
    }
    std::printf("\n");
  }
  if (!s.links_at_end.empty()) {
    std::printf("\nlinks in the incident picture at the end:");
    for (const auto& [id, link] : s.links_at_end) std::printf(" %s %s;", id.c_str(), link.c_str());
    std::printf("\n");
  }
  for (const auto& f : s.faults) {
    if (f.handover_after_s) {
      std::printf("\nincident command killed at mission second %.0f: %s took over after %.2f wall s\n", f.at_s,
                  f.taken_over_by.c_str(), *f.handover_after_s);
    }
  }
  if (!s.picture_available) {
    std::printf("\nNO INCIDENT PICTURE at the end (%s): \"found\" is what the picture knew before it was lost; "
                "\"found by\" is what the finders' devices know.\n",
                s.command_alive_at_end ? "no incident command published it" : "no incident command alive");
  }
  std::printf("\n%zu of %zu victims found in the incident picture, %zu by their finders; %zu in the picture; "
              "%.0f mission s in %.0f wall s. Logs: %s\n",
              s.found_count(), s.victims.size(), s.found_by_finder_count(), s.fused_victims.size(), s.mission_s,
              s.wall_s, run_dir.c_str());
}


}  // namespace sarloc::app
