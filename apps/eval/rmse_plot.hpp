#pragma once
// The RMSE-against-time figure of the firefighter evaluation, drawn as seed 004's Figs. 7-8:
// one panel per initial state (known, unknown), one curve per configuration. Plain SVG, no
// external assets.
#include <string>

#include "sarloc/core/firefighter/firefighter_evaluation.hpp"

namespace sarloc::eval {

std::string rmse_plot_svg(const firefighter::FirefighterSummary& summary, double rmse_every_s);

}  // namespace sarloc::eval
