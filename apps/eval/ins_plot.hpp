#pragma once
// The plot of one INS run on a recording: its top view (stances marked, footprint truth if
// given) and its height against time. Plain SVG, no external assets.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "sarloc/core/firefighter/ins_recording.hpp"

namespace sarloc::eval {

/// With footprints, the track is drawn stride-aligned into their frame (turned by turn_rad about
/// its start, which goes to footprint 0).
std::string ins_plot_svg(const firefighter::InsRecording& run, const std::string& title,
                         const std::vector<Eigen::Vector2d>& footprints, double turn_rad = 0.0);

}  // namespace sarloc::eval
