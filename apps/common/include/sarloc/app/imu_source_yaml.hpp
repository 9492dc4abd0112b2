#pragma once
// An IMU source description (config/imu/*.yaml, docs/configuration.md "IMU sources") read into
// firefighter::ImuSourceFormat: a new foot-mounted sensor is one of these files, not code.
//
//   imu_source:
//     name: x-io NGIMU
//     header: true                       # the first line names the columns
//     time: {column: "Time (s)", unit: s}  # or no time: and rate_hz: 820
//     accel: {columns: [ax, ay, az], unit: g}          # g | m/s^2
//     gyro: {columns: [gx, gy, gz], unit: deg/s}       # deg/s | rad/s
//     axes: [x, -y, -z]                  # boot x, y, z from signed sensor axes (z down here)
//     range: {accel_g: 16, gyro_deg_s: 2000, beyond: clip}   # clip | refuse
#include <string>

#include "sarloc/app/yaml_reader.hpp"
#include "sarloc/core/firefighter/imu_source.hpp"

namespace sarloc::app {

/// The `imu_source:` section of `yaml`; ConfigError names the key and the value.
firefighter::ImuSourceFormat read_imu_source(YamlReader& yaml);
/// A source description file; ConfigError names the file, the key and the value.
firefighter::ImuSourceFormat load_imu_source(const std::string& path);

}  // namespace sarloc::app
