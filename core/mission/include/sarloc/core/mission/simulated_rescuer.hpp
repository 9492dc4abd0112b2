#pragma once
// One rescuer's device in a simulated mission: its true pose, its receiver separating the
// signals of the victims it hears (numbered in the order it first separates them, as a real
// transceiver does), its odometry and its GNSS. The realistic receiver (the default) listens to
// the pulses of every victim's transmitter between two epochs and separates them itself
// (avalanche/beacon_receiver.hpp); the ideal one hands over one signed sample per victim within
// detection_range_m.
//
//   SimulatedRescuer sim(scenario, "r1");
//   for (auto& m : sim.measure(stamp)) publish(m);
//   publish(sim.walk(guidance.bearing_rad, 1.0, stamp, next_stamp));
#include <map>
#include <optional>
#include <random>

#include "sarloc/core/avalanche/beacon_receiver.hpp"
#include "sarloc/core/avalanche/sensor_simulation.hpp"
#include "sarloc/core/responder/responder_position.hpp"
#include "sarloc/core/mission/mission_scenario.hpp"

namespace sarloc::mission {

class SimulatedRescuer {
 public:
  SimulatedRescuer(const MissionScenario& scenario, const std::string& rescuer_id);

  /// One measurement epoch at the current pose: what the receiver separated from the pulses of
  /// the listening window that ends at `stamp` (since the previous epoch, 0.1-2 s; 1 s for the
  /// first). The ideal receiver: a sample per victim within detection range.
  std::vector<avalanche::FieldMeasurement> measure(TimestampNs stamp);
  /// Walks one step as guided; returns the odometry over [start, end].
  responder::Odometry walk(double bearing_rad, double step_m, TimestampNs start, TimestampNs end);
  /// A noisy GNSS fix of the antenna in the incident frame.
  responder::ResponderPosition gnss(TimestampNs stamp);

  /// A victim dug out: the transmitter of the victim nearest `where` (truth), if within
  /// `radius_m`, is switched off, as rescuers do on a real dig. Returns its index, or nullopt.
  std::optional<std::size_t> switch_off_transmitter_near(const Vec3& where, double radius_m);
  /// Victim `index`'s transmitter is switched off (another rescuer's dig). Returns whether it
  /// was on; false for an index beyond the scenario's victims.
  bool switch_off_transmitter(std::size_t index);

  /// The realistic receiver's separation asks the device's filters through this
  /// (avalanche::SignalSeparator::set_consistency); the ideal receiver separates nothing.
  void set_consistency(avalanche::FieldConsistency consistency);

  const avalanche::ReceiverPose& pose() const { return pose_; }
  double distance_walked_m() const { return walked_m_; }
  /// Truth for evaluation: which victim this receiver's signal id is (nullopt if unknown).
  std::optional<std::size_t> victim_of_signal(std::uint32_t signal_id) const;
  const RescuerSpec& spec() const { return spec_; }
  /// Realistic receiver: pulses attributed to a signal of another victim (truth), since the
  /// start (each sample carries its window's unattributed pulses).
  std::uint64_t wrong_attributions() const { return wrong_attributions_; }

 private:
  std::vector<avalanche::FieldMeasurement> measure_ideal(TimestampNs stamp,
                                                        const avalanche::OrientationObservation& attitude);

  MissionScenario scenario_;  // a copy: the rescuer outlives any loader
  RescuerSpec spec_;
  avalanche::ReceiverPose pose_;
  std::mt19937_64 rng_;
  std::map<std::size_t, std::uint32_t> signal_of_victim_;  // ideal receiver
  std::vector<bool> switched_off_;                         // by victim index
  std::optional<avalanche::BeaconReceiver> receiver_;      // realistic receiver
  std::vector<avalanche::Beacon> beacons_;
  std::optional<TimestampNs> last_listened_;
  std::uint64_t wrong_attributions_ = 0;
  std::uint64_t measurement_sequence_ = 0;
  std::uint64_t odometry_sequence_ = 0;
  double walked_m_ = 0.0;
  Vec3 gnss_bias_ = Vec3::Zero();
  std::optional<TimestampNs> last_fix_;
};

}  // namespace sarloc::mission
