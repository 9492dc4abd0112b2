#pragma once
// The error histograms of the avalanche filter comparison, drawn as seed 000's Figs. 4-5: one
// panel per filter, bins of 0.1 m up to 1 m and one bin holding every error above 1 m (the
// depletion failures). Plain SVG, no external assets.
#include <string>
#include <vector>

#include "sarloc/core/avalanche/evaluation.hpp"

namespace sarloc::eval {

std::string error_histogram_svg(const std::vector<avalanche::EvaluationSummary>& filters);

}  // namespace sarloc::eval
