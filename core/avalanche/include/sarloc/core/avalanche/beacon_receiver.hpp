#pragma once
// A simulated realistic receiver end to end (issue 12): the pulses of every transmitter in
// range reach the coils with the full dipole field, the device's gain and pointing errors, the
// per-pulse fluctuation and a random carrier phase; the coils sum them with each antenna's
// noise (pulse_train.hpp); the device detects and separates them (signal_separator.hpp).
// The simulator knows which transmitter each detected pulse came from, so evaluations count
// wrong attributions; the device never sees that.
//
//   BeaconReceiver receiver(simulation_config, seed);
//   auto heard = receiver.listen(pose, beacons, t0, 1.0);
//   for (const auto& m : to_measurements(heard, "r1", sequence, stamp, attitude)) filter_of(m.signal_id).process(m);
#include <map>
#include <optional>
#include <random>
#include <vector>

#include "sarloc/core/avalanche/pulse_train.hpp"
#include "sarloc/core/avalanche/sensor_simulation.hpp"
#include "sarloc/core/avalanche/signal_separator.hpp"
#include "sarloc/core/avalanche/simulator.hpp"

namespace sarloc::avalanche {

/// A buried transmitter as the simulation knows it.
struct Beacon {
  Vec3 position = Vec3::Zero();  ///< world (m)
  Vec3 moment = Vec3::Zero();    ///< world (A m^2)
  TransmitterTiming timing;
  bool transmitting = true;  ///< false: switched off (its victim dug out), no pulse is sent
};

struct HeardSample {
  SeparatedSample sample;
  /// Truth: the beacon whose pulse put the most into the detector's matched filter for this
  /// pulse (its carrier and interval: overlap energy times the filter's response to the carrier
  /// difference).
  std::optional<std::size_t> transmitter;
  /// Truth: the strongest other beacon whose pulse the detector did not find on its own (one it
  /// found, its joint fit took out of this one) and that the matched filter let in, and its
  /// response over the dominant one's: two fields summed into one sample.
  std::optional<std::size_t> mixed_with;
  double mixed_energy_ratio = 0.0;
  /// Truth: how far the sample is from its dominant transmitter's field as an ideal receiver in
  /// this pose would read it (no gains, no fluctuation), the better sign, over the sample's noise
  /// plus the filter's relative term: sum over valid axes of (z -+ h)^2 / (noise + rel |h|)^2.
  std::optional<double> truth_nis;
};

struct Listening {
  std::vector<HeardSample> samples;
  SeparationReport report;
  std::uint32_t wrong_attributions = 0;  ///< attributed pulses of another beacon than the signal's
  /// Per signal sampled: its transmitter as this device measured it, this device's
  /// oscillator tolerance included (responder/transmitter_signature.hpp).
  std::map<std::uint32_t, responder::TransmitterSignature> transmitters;
};

class BeaconReceiver {
 public:
  /// Draws the device's hardware errors from seed; config.receiver must be realistic.
  BeaconReceiver(SimulationConfig config, std::uint64_t seed);

  /// Stands at `pose` and listens over [t0, t0 + duration) (s).
  Listening listen(const ReceiverPose& pose, const std::vector<Beacon>& beacons, double t0_s, double duration_s);

  SignalSeparator& separator() { return separator_; }
  /// Truth: how far this device's oscillator puts every carrier it measures (Hz).
  double oscillator_offset_hz() const { return oscillator_offset_hz_; }
  /// Truth: the beacon first attributed to a signal (nullopt if none yet).
  std::optional<std::size_t> beacon_of_signal(std::uint32_t signal_id) const;
  /// Truth: the beacon most of a signal's samples came from (nullopt before any): the
  /// transmitter the signal has followed, whichever it started on.
  std::optional<std::size_t> majority_beacon_of_signal(std::uint32_t signal_id) const;

 private:
  SimulationConfig config_;
  std::mt19937_64 rng_;
  ReceiverHardware hardware_;
  Vec3 pulse_noise_;
  double oscillator_offset_hz_;  ///< truth: this device's oscillator error at the carrier
  double k_;
  double lead_s_;  ///< each window's overlap with the previous one: longer than any pulse
  SignalSeparator separator_;
  std::vector<std::pair<std::uint32_t, std::size_t>> truth_;  ///< signal -> beacon
  std::map<std::uint32_t, std::map<std::size_t, std::uint32_t>> samples_of_;  ///< signal -> beacon -> samples
};

/// The window's samples as measurements of one rescuer, all with the window's sequence, stamp,
/// attitude and count of unattributed pulses.
std::vector<FieldMeasurement> to_measurements(const Listening& heard, const std::string& rescuer_id,
                                              std::uint64_t sequence, TimestampNs stamp,
                                              const std::optional<OrientationObservation>& attitude);

}  // namespace sarloc::avalanche
