#pragma once
// Where sarloc-rescuer's samples come from: the mission simulator (default; it walks where the
// guidance says) or a recorded sensor file from a real device (guidance is only shown).
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sarloc/core/avalanche/field_measurement.hpp"
#include "sarloc/core/estimator/sensor_sample.hpp"
#include "sarloc/core/incident/geodetic_frame.hpp"
#include "sarloc/core/mission/simulated_rescuer.hpp"
#include "sarloc/core/responder/guidance.hpp"
#include "sarloc/core/responder/odometry.hpp"
#include "sarloc/core/responder/responder_position.hpp"

namespace sarloc::rescuer {

struct SensorEpoch {
  TimestampNs stamp = 0;
  std::vector<responder::Odometry> odometry;  ///< motion since the previous epoch
  std::optional<responder::ResponderPosition> position;
  std::vector<estimator::SensorSample> samples;      ///< this epoch's sensor samples
};

class SensorSource {
 public:
  virtual ~SensorSource() = default;
  /// The samples of the epoch at `stamp`; `followed` is the guidance followed since the
  /// previous epoch. nullopt when the source is exhausted.
  virtual std::optional<SensorEpoch> next(TimestampNs stamp, const std::optional<responder::Guidance>& followed) = 0;
  virtual double distance_walked_m() const = 0;
  /// A source that separates beacon signals itself asks the device's filters through this
  /// (avalanche::SignalSeparator::set_consistency); a recorded file was separated already.
  /// `move` then receives each epoch's motion before the source listens (and the epoch carries
  /// none), so that the filters asked are where the device is.
  virtual void set_consistency(avalanche::FieldConsistency, std::function<void(const responder::Odometry&)> /*move*/) {}
  /// Truth for reports (simulation only): the victim most of a signal's samples came from.
  virtual std::optional<std::size_t> victim_of_signal(std::uint32_t) const { return std::nullopt; }
  /// Truth for reports (simulation only): every victim relative to the antenna now, by index.
  virtual std::vector<Vec3> true_victims_relative() const { return {}; }
  /// Truth for reports (simulation only): the antenna's true position in the incident frame.
  virtual std::optional<Vec3> true_antenna() const { return std::nullopt; }
  /// Simulation only: a victim dug out at `where` (the picture's position); its transmitter,
  /// if one is within `radius_m`, is switched off. Returns its index.
  virtual std::optional<std::size_t> switch_off_transmitter_near(const Vec3& /*where*/, double /*radius_m*/) {
    return std::nullopt;
  }
  /// Simulation only: victim `index`'s transmitter is switched off (another device's dig).
  /// Returns whether it was on.
  virtual bool switch_off_transmitter(std::size_t /*index*/) { return false; }
};

/// The mission simulator: one step per epoch along the followed guidance (no guidance yet:
/// straight ahead, the primary search). Its GNSS receiver reports WGS-84 fixes, which the
/// device converts about the incident's `origin` as it would a real receiver's (gnss_fix.hpp).
class SimulatedSource : public SensorSource {
 public:
  SimulatedSource(const mission::MissionScenario& scenario, const std::string& rescuer_id, double step_length_m,
                  const GeodeticOrigin& origin);
  std::optional<SensorEpoch> next(TimestampNs stamp, const std::optional<responder::Guidance>& followed) override;
  double distance_walked_m() const override { return sim_.distance_walked_m(); }
  void set_consistency(avalanche::FieldConsistency consistency, std::function<void(const responder::Odometry&)> move) override {
    sim_.set_consistency(std::move(consistency));
    move_ = std::move(move);
  }
  std::optional<std::size_t> victim_of_signal(std::uint32_t signal) const override {
    return sim_.victim_of_signal(signal);
  }
  std::vector<Vec3> true_victims_relative() const override {
    std::vector<Vec3> out;
    for (const auto& v : victims_) out.push_back(v.position - sim_.pose().position);
    return out;
  }
  std::optional<Vec3> true_antenna() const override { return sim_.pose().position; }
  std::optional<std::size_t> switch_off_transmitter_near(const Vec3& where, double radius_m) override {
    return sim_.switch_off_transmitter_near(where, radius_m);
  }
  bool switch_off_transmitter(std::size_t index) override { return sim_.switch_off_transmitter(index); }

 private:
  mission::SimulatedRescuer sim_;
  incident::GeodeticFrame frame_;
  std::vector<mission::VictimSpec> victims_;
  double step_length_m_;
  std::optional<TimestampNs> previous_stamp_;
  std::function<void(const responder::Odometry&)> move_;
};

/// A recorded sensor file, JSON lines (docs/configuration.md, "Recorded sensor files"):
///   {"type":"odometry","sequence":1,"interval_start_ns":..,"interval_end_ns":..,
///    "translation":[x,y,z],"rotation_rpy":[r,p,y],"covariance":[36 numbers, row-major]}
///   {"type":"position","stamp_ns":..,"position":[e,n,u],"covariance":[9 numbers]}
///   {"type":"gnss","stamp_ns":..,"latitude_deg":..,"longitude_deg":..,"altitude_m":..,
///    "horizontal_sigma_m":..,"vertical_sigma_m":..}   (a receiver's fix in WGS-84, converted
///    about the incident's origin)
///   {"type":"field","signal_id":1,"sequence":1,"stamp_ns":..,"field":[x,y,z],
///    "noise_stddev":[x,y,z], optional "orientation_rpy":[r,p,y],"orientation_covariance":[9],
///    "valid_axes":0..7 (default 7; 0: a pulse due and not heard), "signal_event":"none|new|reacquired|separated"}
/// An epoch is every line up to and including the field samples sharing one stamp_ns; the
/// file's own stamps are kept. A malformed line is skipped with a warning naming the line
/// number and the field; nothing else is lost.
class RecordedSource : public SensorSource {
 public:
  RecordedSource(const std::string& path, std::string rescuer_id, std::string team, const GeodeticOrigin& origin);
  std::optional<SensorEpoch> next(TimestampNs stamp, const std::optional<responder::Guidance>& followed) override;
  double distance_walked_m() const override { return walked_m_; }
  std::size_t skipped_lines() const { return skipped_; }

 private:
  bool read_line(SensorEpoch& epoch, std::optional<TimestampNs>& field_stamp);

  std::ifstream in_;
  incident::GeodeticFrame frame_;
  std::string path_;
  std::string rescuer_id_;
  std::string team_;
  std::size_t line_number_ = 0;
  std::size_t skipped_ = 0;
  double walked_m_ = 0.0;
  std::optional<std::string> pending_line_;
};

}  // namespace sarloc::rescuer
