#pragma once
// `sarloc-eval detector`: the realistic receiver's pulse detector alone, on overlapping pulses
// whose truth is known (core/avalanche detector_bench.hpp): what it lets through to the tracks,
// and how far those amplitudes are from the truth in units of their stated noise.
#include "sarloc/app/cli_app.hpp"
#include <cstdint>
#include <string>

namespace sarloc::eval {

struct DetectorOptions {
  std::string scenario = "all";  ///< single, nested-pair, together or all
  std::uint32_t draws = 200;
  std::uint64_t seed = 1;
  std::string json_path;
};

CLI::App* add_detector_command(CLI::App& app, DetectorOptions& options);
/// Returns a sarloc::app::ExitCode value (0: ran, the figures are reported, not judged; 3: bad
/// setup; 4: --json not writable; 130: interrupted).
int run_detector_command(const DetectorOptions& options);

}  // namespace sarloc::eval
