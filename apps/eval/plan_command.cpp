#include "plan_command.hpp"

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>

#include "sarloc/app/exit_codes.hpp"
#include "sarloc/app/floor_plan_svg.hpp"
#include "sarloc/app/floor_plan_yaml.hpp"
#include "sarloc/core/common/errors.hpp"

namespace sarloc::eval {

using app::ExitCode;
using app::to_int;

CLI::App* add_plan_command(CLI::App& app, PlanOptions& options) {
  auto* cmd = app.add_subcommand("plan", "read a floor plan (YAML or an IMDF directory), list and draw its floors");
  cmd->add_option("building", options.building, "config/buildings/*.yaml or an IMDF directory (*.imdf/)")->required();
  cmd->add_option("--html", options.html, "draw every floor to this HTML file (one map per floor)");
  return cmd;
}

int run_plan_command(const PlanOptions& options) {
  firefighter::FloorPlan plan;
  try {
    plan = app::load_floor_plan(options.building);
  } catch (const Error& e) {
    spdlog::error("{}", e.what());
    return to_int(ExitCode::kConfig);
  }
  firefighter::Vec2 min, max;
  plan.bounds(min, max);
  std::printf("Building %s: %zu floors, %zu entries, %zu flights; plan box [%.2f, %.2f] to [%.2f, %.2f] m\n",
              plan.name.c_str(), plan.floors.size(), plan.entries.size(), plan.stairs.size(), min.x(), min.y(), max.x(),
              max.y());
  for (const auto& f : plan.floors) {
    double length = 0.0;
    for (const auto& w : f.walls) length += (w.b - w.a).norm();
    std::printf("  floor %-12s %6.2f m: %3zu walls (%.1f m), %3zu doors and openings, %3zu furniture\n", f.id.c_str(),
                f.elevation_m, f.walls.size(), length, f.doors.size(), f.furniture.size());
  }
  for (const auto& e : plan.entries) {
    std::printf("  entry %-12s floor %s, door %s, at [%.2f, %.2f] m facing %.0f deg\n", e.id.c_str(), e.floor.c_str(),
                e.door.c_str(), e.position.x(), e.position.y(), e.heading_rad * 180.0 / 3.14159265358979);
  }
  for (const auto& s : plan.stairs) {
    std::printf("  flight %-11s %s -> %s, [%.2f, %.2f] to [%.2f, %.2f] m, %.2f m wide\n", s.id.c_str(),
                s.lower_floor.c_str(), s.upper_floor.c_str(), s.bottom.x(), s.bottom.y(), s.top.x(), s.top.y(),
                s.width_m);
  }
  if (!options.html.empty()) {
    std::ofstream out(options.html);
    out << app::floor_plan_svg(plan);
    if (!out.flush()) {
      spdlog::error("cannot write --html {}", options.html);
      return to_int(ExitCode::kRuntime);
    }
    std::printf("Drawn: %s\n", options.html.c_str());
  }
  return to_int(ExitCode::kOk);
}

}  // namespace sarloc::eval
