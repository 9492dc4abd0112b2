#pragma once
// `sarloc-eval ins FILE`: the boot INS on one recorded foot IMU file, read by its source
// description (config/imu/), against the truth the recording has: a closed loop (--loop) or
// footprints (--footprints). Prints what it read, refused and estimated; writes the track
// (--out) and a plot (--plot: top view and height against time).
#include <string>

#include "sarloc/app/cli_app.hpp"

namespace sarloc::eval {

struct InsOptions {
  std::string file;
  std::string source;       ///< an IMU source description; empty: the sarloc boot IMU CSV
  std::string config_path;  ///< its ins: section over the device's INS defaults
  bool loop = false;
  std::string footprints;
  std::string out;
  std::string plot;
  std::string json_path;
};

CLI::App* add_ins_command(CLI::App& app, InsOptions& options);
/// Returns a sarloc::app::ExitCode value: 0 a track; 1 never aligned (no track); 3 a bad source
/// description, recording header or truth file; 4 an output not writable.
int run_ins_command(const InsOptions& options);

}  // namespace sarloc::eval
