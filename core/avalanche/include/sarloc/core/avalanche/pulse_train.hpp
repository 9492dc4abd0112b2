#pragma once
// Avalanche transmitters pulse: each has its own period (700-1300 ms), on-time (>= 70 ms) and
// carrier offset (+-80 Hz) within EN 300 718, and the receiver's coils sum whatever pulses are
// on at each instant. This file draws the timing and synthesises what the three coils give
// after mixing the 457 kHz carrier down: complex baseband samples per axis, with the noise of
// each antenna (receiver_model.hpp).
//
//   TransmitterTiming timing = TransmitterTiming::draw(config, rng);     // once per transmitter
//   for (double start : timing.starts_in(t0, t1)) pulses.push_back({...});
//   BasebandWindow window = synthesize(pulses, t0, t1 - t0, config, pulse_noise, rng);
#include <complex>
#include <random>
#include <vector>

#include "sarloc/core/avalanche/receiver_model.hpp"

namespace sarloc::avalanche {

struct TransmitterTiming {
  double period_s = 1.0;
  double on_time_s = 0.1;
  double first_start_s = 0.0;     ///< start of the pulse train (any pulse start is first + k period)
  double carrier_offset_hz = 0.0;  ///< from 457 kHz
  double phase_rad = 0.0;          ///< carrier phase of a phase-coherent transmitter

  /// Within the config's bounds, the first pulse somewhere in the first period.
  static TransmitterTiming draw(const ReceiverModelConfig& config, std::mt19937_64& rng);
  /// Starts of the pulses that are on at some time in [t0, t1).
  std::vector<double> starts_in(double t0, double t1) const;
};

/// How long (s, from a's first pulse) every pulse of `a` overlaps a pulse of `b` in time: 0 if
/// their first pulses do not overlap, infinity for equal periods that do. Two trains whose periods
/// differ by 0.2 ms and that start overlapped stay so for about on-time / 0.2 ms periods (10 min
/// at 130 ms): all that time the receiver hears every pulse of one summed with the other's.
double pulses_overlap_for_s(const TransmitterTiming& a, const TransmitterTiming& b);

/// One pulse as it reaches the antennas: s_i(t) = amplitude_i e^{j 2 pi f t} (t absolute, s)
/// for t in [start, end), zero otherwise.
struct IncomingPulse {
  std::size_t transmitter = 0;
  double start_s = 0.0;
  double end_s = 0.0;
  double carrier_offset_hz = 0.0;
  Vec3c amplitude = Vec3c::Zero();  ///< per axis, device frame, hardware applied (A/m)
};

/// Complex baseband samples of the three axes over one listening window.
struct BasebandWindow {
  double t0_s = 0.0;
  double sample_rate_hz = 500.0;
  Eigen::Matrix<std::complex<double>, 3, Eigen::Dynamic> samples;
  Vec3 sample_noise = Vec3::Zero();  ///< per axis, 1 sigma of each real component of a sample
  /// The first lead_s of the window were the end of the previous one: a device listens without
  /// gaps, and a pulse that crosses from one window into the next is heard whole in the window
  /// where it ends (SignalSeparator::process). 0: a window on its own.
  double lead_s = 0.0;
  Eigen::Index size() const { return samples.cols(); }
  double time(Eigen::Index n) const { return t0_s + static_cast<double>(n) / sample_rate_hz; }
  /// Where the new part of the window begins: pulses that ended before it were heard already.
  double new_from_s() const { return t0_s + lead_s; }
};

/// Noise per sample that gives `pulse_noise` (1 sigma per axis) on the amplitude of a 70 ms
/// pulse integrated coherently: sigma_sample = sigma_pulse sqrt(70 ms * sample rate).
Vec3 sample_noise_of(const Vec3& pulse_noise, double sample_rate_hz);
/// Its inverse: the noise of a 70 ms pulse's amplitude from the noise per sample.
Vec3 pulse_noise_of(const Vec3& sample_noise, double sample_rate_hz);

/// The coils' sum of every pulse over [t0, t0 + duration) plus each axis's white noise.
BasebandWindow synthesize(const std::vector<IncomingPulse>& pulses, double t0_s, double duration_s,
                          double sample_rate_hz, const Vec3& pulse_noise, std::mt19937_64& rng);

}  // namespace sarloc::avalanche
