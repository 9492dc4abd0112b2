#include "sarloc/core/avalanche/pulse_train.hpp"

#include <cmath>
#include <limits>

#include "sarloc/core/avalanche/dipole_model.hpp"

namespace sarloc::avalanche {

TransmitterTiming TransmitterTiming::draw(const ReceiverModelConfig& c, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  TransmitterTiming t;
  t.period_s = 1e-3 * (c.period_min_ms + (c.period_max_ms - c.period_min_ms) * u01(rng));
  t.on_time_s = 1e-3 * (c.on_time_min_ms + (c.on_time_max_ms - c.on_time_min_ms) * u01(rng));
  t.first_start_s = t.period_s * u01(rng);
  t.carrier_offset_hz = c.carrier_tolerance_hz * (2.0 * u01(rng) - 1.0);
  t.phase_rad = 2.0 * kPi * u01(rng);
  return t;
}

std::vector<double> TransmitterTiming::starts_in(double t0, double t1) const {
  std::vector<double> starts;
  // First pulse whose end is after t0.
  double k = std::ceil((t0 - on_time_s - first_start_s) / period_s);
  for (double start = first_start_s + k * period_s; start < t1; start = first_start_s + (++k) * period_s)
    if (start + on_time_s > t0) starts.push_back(start);
  return starts;
}

double pulses_overlap_for_s(const TransmitterTiming& a, const TransmitterTiming& b) {
  // b's start relative to the nearest start of a drifts by (Tb - Ta) per period of a, linearly:
  // the overlap holds until the gap leaves (-on_b, on_a). (That window is narrower than half a
  // period, so the gap cannot wrap back into it.)
  const double first_gap = b.first_start_s - a.first_start_s;
  const double offset = first_gap - a.period_s * std::round(first_gap / a.period_s);
  if (!(offset > -b.on_time_s && offset < a.on_time_s)) return 0.0;
  const double drift = b.period_s - a.period_s;
  if (drift == 0.0) return std::numeric_limits<double>::infinity();
  const double room = drift > 0.0 ? a.on_time_s - offset : offset + b.on_time_s;
  // Pulses k = 0 .. K overlap, K the last whole period before the gap leaves.
  return std::ceil(room / std::fabs(drift)) * a.period_s;
}

namespace {
constexpr double kReferencePulseS = 0.070;  // EN 300 718's shortest on-time: the noise floors' unit
}  // namespace

Vec3 sample_noise_of(const Vec3& pulse_noise, double sample_rate_hz) {
  return pulse_noise * std::sqrt(kReferencePulseS * sample_rate_hz);
}

Vec3 pulse_noise_of(const Vec3& sample_noise, double sample_rate_hz) {
  return sample_noise / std::sqrt(kReferencePulseS * sample_rate_hz);
}

BasebandWindow synthesize(const std::vector<IncomingPulse>& pulses, double t0_s, double duration_s,
                          double sample_rate_hz, const Vec3& pulse_noise, std::mt19937_64& rng) {
  BasebandWindow w;
  w.t0_s = t0_s;
  w.sample_rate_hz = sample_rate_hz;
  w.sample_noise = sample_noise_of(pulse_noise, sample_rate_hz);
  const auto n = static_cast<Eigen::Index>(std::llround(duration_s * sample_rate_hz));
  w.samples.setZero(3, n);
  std::normal_distribution<double> n01(0.0, 1.0);
  for (Eigen::Index k = 0; k < n; ++k) {
    for (int a = 0; a < 3; ++a) {
      const double re = n01(rng);
      const double im = n01(rng);
      w.samples(a, k) = w.sample_noise[a] * std::complex<double>(re, im);
    }
  }
  for (const auto& p : pulses) {
    const auto first = std::max<Eigen::Index>(0, static_cast<Eigen::Index>(std::ceil((p.start_s - t0_s) * sample_rate_hz)));
    const auto last = std::min<Eigen::Index>(n, static_cast<Eigen::Index>(std::ceil((p.end_s - t0_s) * sample_rate_hz)));
    for (Eigen::Index k = first; k < last; ++k) {
      const std::complex<double> carrier = std::polar(1.0, 2.0 * kPi * p.carrier_offset_hz * w.time(k));
      for (int a = 0; a < 3; ++a) w.samples(a, k) += p.amplitude[a] * carrier;
    }
  }
  return w;
}

}  // namespace sarloc::avalanche
