#pragma once
// `sarloc-eval plan BUILDING`: reads a floor plan (YAML, or an IMDF directory), prints what it
// holds per floor and draws every floor (--html): how a plan imported from IMDF is checked by
// eye before a mission uses it (docs/configuration.md, "Indoor maps in IMDF").
#include <string>

#include "sarloc/app/cli_app.hpp"

namespace sarloc::eval {

struct PlanOptions {
  std::string building;
  std::string html;
};

CLI::App* add_plan_command(CLI::App& app, PlanOptions& options);
/// Returns a sarloc::app::ExitCode value: 0 read (and drawn); 3 the plan refused (the message
/// names the file and the element); 4 --html not writable.
int run_plan_command(const PlanOptions& options);

}  // namespace sarloc::eval
