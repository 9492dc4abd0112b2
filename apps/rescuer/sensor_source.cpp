#include "sensor_source.hpp"

#include <spdlog/spdlog.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/incident/gnss_fix.hpp"

namespace sarloc::rescuer {

SimulatedSource::SimulatedSource(const mission::MissionScenario& scenario, const std::string& rescuer_id,
                                 double step_length_m, const GeodeticOrigin& origin)
    : sim_(scenario, rescuer_id), frame_(origin), victims_(scenario.victims), step_length_m_(step_length_m) {}

std::optional<SensorEpoch> SimulatedSource::next(TimestampNs stamp, const std::optional<responder::Guidance>& followed) {
  SensorEpoch epoch;
  epoch.stamp = stamp;
  if (previous_stamp_) {
    const double bearing = followed ? followed->bearing_rad : 0.0;
    const double step = followed ? followed->step_m : step_length_m_;
    responder::Odometry walked = sim_.walk(bearing, step, *previous_stamp_, stamp);
    if (move_) move_(walked);  // the filters the separation asks move before it listens
    else epoch.odometry.push_back(std::move(walked));
  }
  previous_stamp_ = stamp;
  responder::ResponderPosition fix = sim_.gnss(stamp);
  // What the receiver reports (WGS-84), then the device's conversion of it, as on a real device.
  fix.position = incident::in_incident_frame(frame_, incident::as_receiver_fix(frame_, stamp, fix.position));
  epoch.position = std::move(fix);
  for (auto& m : sim_.measure(stamp)) epoch.samples.emplace_back(std::move(m));
  return epoch;
}

namespace {

using nlohmann::json;

template <int N>
Eigen::Matrix<double, N, 1> vector_field(const json& j, const char* key) {
  if (!j.contains(key) || !j[key].is_array() || j[key].size() != N) {
    throw InputError(std::string(key) + ": expected " + std::to_string(N) + " numbers");
  }
  Eigen::Matrix<double, N, 1> v;
  for (int i = 0; i < N; ++i) {
    if (!j[key][static_cast<std::size_t>(i)].is_number()) throw InputError(std::string(key) + "[" + std::to_string(i) + "]: not a number");
    v[i] = j[key][static_cast<std::size_t>(i)].get<double>();
  }
  if (!v.allFinite()) throw InputError(std::string(key) + ": non-finite value");
  return v;
}

template <int N>
Eigen::Matrix<double, N, N> matrix_field(const json& j, const char* key) {
  const auto flat = vector_field<N * N>(j, key);
  Eigen::Matrix<double, N, N> m;
  for (int r = 0; r < N; ++r)
    for (int c = 0; c < N; ++c) m(r, c) = flat[r * N + c];
  return m;
}

template <class T>
T number_field(const json& j, const char* key) {
  if (!j.contains(key) || !j[key].is_number()) throw InputError(std::string(key) + ": missing or not a number");
  return j[key].get<T>();
}

avalanche::SignalEvent signal_event_field(const json& j) {
  const std::string name = j["signal_event"].is_string() ? j["signal_event"].get<std::string>() : "";
  for (auto e : {avalanche::SignalEvent::kNone, avalanche::SignalEvent::kNew, avalanche::SignalEvent::kReacquired,
                 avalanche::SignalEvent::kSeparated}) {
    if (name == to_string(e)) return e;
  }
  throw InputError("signal_event = '" + name + "': expected none, new, reacquired or separated");
}

}  // namespace

RecordedSource::RecordedSource(const std::string& path, std::string rescuer_id, std::string team,
                               const GeodeticOrigin& origin)
    : in_(path), frame_(origin), path_(path), rescuer_id_(std::move(rescuer_id)), team_(std::move(team)) {
  if (!in_) throw ConfigError("--source = '" + path + "': cannot open the recorded sensor file");
}

// Reads one line into `epoch`; returns false at the first field line of the NEXT epoch
// (kept for the next call) or at the end of the file.
bool RecordedSource::read_line(SensorEpoch& epoch, std::optional<TimestampNs>& field_stamp) {
  std::string line;
  if (pending_line_) {
    line = *pending_line_;
    pending_line_.reset();
  } else {
    if (!std::getline(in_, line)) return false;
    ++line_number_;
  }
  if (line.find_first_not_of(" \t\r") == std::string::npos) return true;
  try {
    const json j = json::parse(line);
    const std::string type = j.value("type", "");
    // The epoch ends with its field samples: anything after them starts the next one.
    if (field_stamp && (type != "field" || j.value("stamp_ns", TimestampNs{0}) != *field_stamp)) {
      pending_line_ = line;
      return false;
    }
    if (type == "field") {
      avalanche::FieldMeasurement m;
      m.rescuer_id = rescuer_id_;
      m.signal_id = number_field<std::uint32_t>(j, "signal_id");
      m.sequence = number_field<std::uint64_t>(j, "sequence");
      m.stamp = number_field<TimestampNs>(j, "stamp_ns");
      m.field = vector_field<3>(j, "field");
      m.noise_stddev = vector_field<3>(j, "noise_stddev");
      if (j.contains("valid_axes")) {
        const auto axes = number_field<int>(j, "valid_axes");
        if (axes < 0 || axes > 7)
          throw InputError("valid_axes = " + std::to_string(axes) + ": a mask of bits 0-2 (0..7; 0: a pulse due, not heard)");
        m.valid_axes = static_cast<std::uint8_t>(axes);
      }
      if (j.contains("signal_event")) m.event = signal_event_field(j);
      if (j.contains("orientation_rpy")) {
        m.orientation = avalanche::OrientationObservation{vector_field<3>(j, "orientation_rpy"),
                                                          matrix_field<3>(j, "orientation_covariance")};
      }
      field_stamp = m.stamp;
      epoch.stamp = m.stamp;
      epoch.samples.emplace_back(m);
    } else if (type == "odometry") {
      responder::Odometry o;
      o.rescuer_id = rescuer_id_;
      o.sequence = number_field<std::uint64_t>(j, "sequence");
      o.interval_start = number_field<TimestampNs>(j, "interval_start_ns");
      o.interval_end = number_field<TimestampNs>(j, "interval_end_ns");
      o.translation = vector_field<3>(j, "translation");
      o.rotation_rpy = vector_field<3>(j, "rotation_rpy");
      o.covariance = matrix_field<6>(j, "covariance");
      o.source = responder::OdometrySource::kOther;
      walked_m_ += o.translation.norm();
      epoch.odometry.push_back(o);
    } else if (type == "position") {
      responder::ResponderPosition p;
      p.responder_id = rescuer_id_;
      p.team_id = team_;
      p.stamp = number_field<TimestampNs>(j, "stamp_ns");
      p.position.position = vector_field<3>(j, "position");
      p.position.covariance = matrix_field<3>(j, "covariance");
      p.source = responder::PositionSource::kGnss;
      epoch.position = p;
    } else if (type == "gnss") {
      incident::GnssFix fix;
      fix.stamp = number_field<TimestampNs>(j, "stamp_ns");
      fix.position.latitude_deg = number_field<double>(j, "latitude_deg");
      fix.position.longitude_deg = number_field<double>(j, "longitude_deg");
      fix.position.altitude_m = number_field<double>(j, "altitude_m");
      fix.horizontal_sigma_m = number_field<double>(j, "horizontal_sigma_m");
      fix.vertical_sigma_m = number_field<double>(j, "vertical_sigma_m");
      responder::ResponderPosition p;
      p.responder_id = rescuer_id_;
      p.team_id = team_;
      p.stamp = fix.stamp;
      p.position = incident::in_incident_frame(frame_, fix);
      p.source = responder::PositionSource::kGnss;
      epoch.position = p;
    } else {
      throw InputError("type = '" + type + "': expected field, odometry, position or gnss");
    }
  } catch (const std::exception& e) {
    ++skipped_;
    spdlog::warn("{}:{}: skipped: {}", path_, line_number_, e.what());
  }
  return true;
}

std::optional<SensorEpoch> RecordedSource::next(TimestampNs /*stamp*/, const std::optional<responder::Guidance>&) {
  SensorEpoch epoch;
  std::optional<TimestampNs> field_stamp;
  while (read_line(epoch, field_stamp)) {
  }
  if (epoch.samples.empty() && epoch.odometry.empty() && !epoch.position) return std::nullopt;
  return epoch;
}

}  // namespace sarloc::rescuer
