#pragma once
// A real 3-antenna avalanche-beacon receiver, as opposed to the ideal one of seed 000 (issue 12;
// docs/estimation/avalanche.md, "Receiver model", gives the sources of every default).
//
// What the coils see: every transmitter is one coil, so its field at the receiver is the full
// field of an oscillating magnetic dipole at 457 kHz (quasi-static 1/r^3 term, induction 1/r^2
// term a quarter period out of phase, radiation 1/r term), a complex vector H. The receiver's
// three antennas are unequal (the long x antenna is the most sensitive), each with its own gain
// error and misalignment: the device measures a = G R^T H, G fixed per device.
//
// What the device reports from the complex amplitudes a of one pulse: the major axis of the
// polarisation ellipse, v = Re(a e^{-j theta}) with theta = arg(sum a_i^2) / 2 (the real vector
// that explains most of the pulse's energy). Its sign depends on the carrier phase of that
// pulse, which nothing carries from one pulse to the next: the reported vector is +-v at
// random. An axis whose amplitude is below detect_snr times its noise is reported invalid: its
// phase, hence its sign relative to the other axes, is not measurable.
//
//   ReceiverHardware hw = ReceiverHardware::draw(config, rng);     // once per device
//   Vec3c a = hw.apply(R.transpose() * full_dipole_field(r, m, wavenumber(config)));
//   Vec3 v = principal_axis(a);
#include <complex>
#include <cstdint>
#include <random>
#include <string>

#include "sarloc/core/common/types.hpp"

namespace sarloc::avalanche {

using Vec3c = Eigen::Vector3cd;

enum class ReceiverKind { kIdeal, kRealistic };
/// "ideal" / "realistic"; parse throws ConfigError naming `key`.
std::string to_string(ReceiverKind kind);
ReceiverKind parse_receiver_kind(const std::string& text, const std::string& key);

/// Bit i set: axis i of FieldMeasurement::field carries signal.
inline constexpr std::uint8_t kAllAxes = 0b111;

struct ReceiverModelConfig {
  /// realistic: the receiver the product runs (missions) and the evaluation measures. ideal
  /// (seed 000's separated, signed samples) is for Table I (config/eval/table1.yaml) and for
  /// unit tests of the filter alone.
  ReceiverKind kind = ReceiverKind::kRealistic;
  double carrier_hz = 457000.0;         ///< EN 300 718
  /// Noise of the two short antennas relative to the long one (whose floor is
  /// SimulationConfig::field_noise_floor_A_per_m per 70 ms pulse): 3x the noise is about 0.7x
  /// the range of the long antenna.
  double short_axis_noise_factor = 3.0;
  double detect_snr = 3.0;              ///< an axis below this amplitude / noise is invalid
  double gain_sigma = 0.03;             ///< per-axis gain error (1 sigma, fixed per device)
  double misalignment_sigma_deg = 1.0;  ///< per-axis pointing error (1 sigma, fixed per device)
  /// White noise the device adds to each sample's per-axis noise, times |field|, for its
  /// calibration. 0: the SOG filter carries the gain and pointing errors, fixed per device, as
  /// consider parameters (SogConfig::calibration_gain_sigma). 0.015 stood for them until then,
  /// and also covered the filter's quasi-static field model (SogConfig::field_carrier_hz):
  /// docs/estimation/avalanche.md, "The field a receiver resolves".
  double calibration_relative = 0.0;
  /// The transmitter's carrier keeps its phase from pulse to pulse (none is required to):
  /// the device then carries the sign with its frequency estimate.
  bool phase_coherent = false;
  // Pulse timing of every transmitter, drawn within EN 300 718 (NOTES.md).
  double period_min_ms = 700.0;
  double period_max_ms = 1300.0;
  double on_time_min_ms = 70.0;
  double on_time_max_ms = 200.0;
  double carrier_tolerance_hz = 80.0;   ///< carrier offset drawn in +- this
  /// The device's own oscillator error (1 sigma, fixed per device): it measures every carrier
  /// offset against it, so two receivers see one transmitter's carrier this far apart (10 ppm:
  /// 4.6 Hz at 457 kHz, a crystal's +-30 ppm over temperature at 3 sigma). It states it in every
  /// signal's transmitter signature. Its clock's effect on a period (10 us) is stated, not simulated.
  double oscillator_sigma_ppm = 10.0;
  double sample_rate_hz = 500.0;        ///< complex baseband sampling of each axis
  /// The device's detector refits each pulse as two tones up to this far apart (Hz) when one
  /// tone leaves energy unexplained: two transmitters a cell or two apart that start together
  /// are found as one burst at their mean carrier otherwise (PulseDetectorConfig). 0: never.
  double two_tone_span_hz = 20.0;
  /// The device's detector refits a pulse that one tone does not explain, or that a pulse on its
  /// carrier outlasts, as two pulses on one carrier with their own edges: a pair in lockstep
  /// (PulseDetectorConfig::same_carrier_pairs).
  bool same_carrier_pairs = true;
  /// The device listens without gaps: each window starts with the end of the one before, so a
  /// pulse that crosses from one into the next is heard whole (BasebandWindow::lead_s). false:
  /// windows cut apart, as before issue 58, when a transmitter whose period was within a few ms
  /// of the window's went unheard for minutes (a victim passed 4 m away, seed 20 trial 36).
  bool continuous_listening = true;

  /// Throws ConfigError "simulation.receiver.<key> = value: rule".
  void validate() const;
};

/// k = 2 pi f / c of the carrier (rad/m).
double wavenumber(const ReceiverModelConfig& config);
double carrier_wavenumber(double carrier_hz);

/// Full field of an oscillating magnetic dipole (time factor e^{j w t}, common phase e^{-jkr}
/// dropped): H = [(3 n (n.m) - m)(1/r^3 + j k/r^2) + k^2 (m - n (n.m)) / r] / (4 pi),
/// r = transmitter -> receiver. k = 0 gives DipoleField::field exactly.
Vec3c full_dipole_field(const Vec3& r, const Vec3& m, double k);

/// Major axis of the polarisation ellipse of a: Re(a e^{-j theta}), theta = arg(sum a_i^2)/2.
/// Its sign follows the branch of theta, i.e. the carrier phase of the pulse.
Vec3 principal_axis(const Vec3c& a);
/// Minor axis of the same ellipse: Im(a e^{-j theta}). One transmitter's field is linearly
/// polarised to within (kr)^3 (the induction term shares the quasi-static term's direction; only
/// the radiation term, (kr)^2 smaller, points elsewhere): 0.1 of the major axis at 50 m, 0.007 at
/// 20 m. Two transmitters' pulses summed with different carrier phases are elliptical.
Vec3 minor_axis(const Vec3c& a);

/// Largest minor / major axis ratio of one transmitter's field whose major axis is `major_A_per_m`:
/// it is within r_max = cbrt(2 m_max / (4 pi major)) (the strongest transmitter, on its axis),
/// where the worst orientation reads (k r)^3 / 2; returned with a 20 % margin, 0.6 (k r_max)^3.
double single_transmitter_ellipticity(double major_A_per_m, double k, double moment_max_A_m2);

/// Per-axis gain and pointing errors of one device: a = G h.
struct ReceiverHardware {
  Mat3 gain = Mat3::Identity();
  static ReceiverHardware draw(const ReceiverModelConfig& config, std::mt19937_64& rng);
  Vec3c apply(const Vec3c& h) const { return gain.cast<std::complex<double>>() * h; }
};

/// Per-axis noise floor (A/m, 1 sigma per 70 ms pulse) from the long antenna's floor.
Vec3 axis_noise_floor(const ReceiverModelConfig& config, double long_axis_floor);

}  // namespace sarloc::avalanche
