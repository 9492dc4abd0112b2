#pragma once
// sarloc-rescuer for a firefighter (rescuers[].role: firefighter): the boot IMU (simulated, a
// directional search of the mission's building, or a recorded file) through the device's INS; odometry, alarms and
// its own dead-reckoned position published; the daemon's map-aided positions shown, scored
// against the walk's truth for the summary.
#include <string>

#include "sarloc/app/exit_codes.hpp"
#include "sarloc/app/mission_config.hpp"
#include "sarloc/app/node_options.hpp"
#include "sarloc/core/firefighter/imu_source.hpp"

namespace sarloc::rescuer {

/// Runs until the IMU source ends (`source`: "sim", the simulated search, or a recorded IMU
/// file in `format`, imu_file.hpp, whose rate and stance settings the INS takes) or shutdown is
/// requested.
app::ExitCode run_firefighter_device(const app::MissionConfig& mission, const app::FirefighterEntry& firefighter,
                                     const app::NodeOptions& options, const std::string& source,
                                     const firefighter::ImuSourceFormat& format, const std::string& summary_path,
                                     bool quiet);

}  // namespace sarloc::rescuer
