#include "sarloc/core/avalanche/receiver_model.hpp"

#include <cmath>
#include <sstream>

#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/avalanche/sensor_simulation.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::avalanche {
namespace {

constexpr double kSpeedOfLight = 299792458.0;

void check(const char* key, double v, double lo, double hi) {
  require(std::isfinite(v) && v >= lo && v <= hi, std::string("simulation.receiver.") + key, v,
          "must be in [" + config_value(lo) + ", " + config_value(hi) + "]");
}

}  // namespace

std::string to_string(ReceiverKind kind) { return kind == ReceiverKind::kIdeal ? "ideal" : "realistic"; }

ReceiverKind parse_receiver_kind(const std::string& text, const std::string& key) {
  if (text == "ideal") return ReceiverKind::kIdeal;
  if (text == "realistic") return ReceiverKind::kRealistic;
  throw ConfigError(key + " = '" + text + "': expected ideal or realistic");
}

void ReceiverModelConfig::validate() const {
  check("carrier_hz", carrier_hz, 1e3, 1e7);
  check("short_axis_noise_factor", short_axis_noise_factor, 1.0, 100.0);
  check("detect_snr", detect_snr, 1.0, 20.0);
  check("gain_sigma", gain_sigma, 0.0, 0.3);
  check("calibration_relative", calibration_relative, 0.0, 0.5);
  check("misalignment_sigma_deg", misalignment_sigma_deg, 0.0, 20.0);
  // EN 300 718 as quoted in NOTES.md: period 1000 +- 300 ms, on-time >= 70 ms, +-80 Hz.
  check("period_min_ms", period_min_ms, 700.0, 1300.0);
  check("period_max_ms", period_max_ms, period_min_ms, 1300.0);
  check("on_time_min_ms", on_time_min_ms, 70.0, 600.0);
  check("on_time_max_ms", on_time_max_ms, on_time_min_ms, 600.0);
  if (on_time_max_ms >= period_min_ms) check("on_time_max_ms", on_time_max_ms, 70.0, period_min_ms - 1.0);
  check("carrier_tolerance_hz", carrier_tolerance_hz, 0.0, 80.0);
  check("oscillator_sigma_ppm", oscillator_sigma_ppm, 0.0, 30.0);
  check("two_tone_span_hz", two_tone_span_hz, 0.0, 100.0);
  // Nyquist for two carriers +-tolerance apart, with margin for the detector's search band.
  check("sample_rate_hz", sample_rate_hz, 2.5 * carrier_tolerance_hz + 50.0, 10000.0);
}

double carrier_wavenumber(double carrier_hz) { return 2.0 * kPi * carrier_hz / kSpeedOfLight; }

double wavenumber(const ReceiverModelConfig& config) { return carrier_wavenumber(config.carrier_hz); }

Vec3c full_dipole_field(const Vec3& r, const Vec3& m, double k) {
  const double rn = r.norm();
  const Vec3 n = r / rn;
  const double nm = n.dot(m);
  const std::complex<double> near(1.0 / (rn * rn * rn), k / (rn * rn));  // 1/r^3 + j k/r^2
  const double far = k * k / rn;
  const Vec3 radial_part = 3.0 * nm * n - m;
  const Vec3 transverse = m - nm * n;
  Vec3c h;
  for (int i = 0; i < 3; ++i) h[i] = (radial_part[i] * near + transverse[i] * far) / (4.0 * kPi);
  return h;
}

namespace {

// a e^{-j theta}, theta = arg(sum a_i^2) / 2: real part along the major axis, imaginary along the minor.
Vec3c ellipse_aligned(const Vec3c& a) {
  const std::complex<double> s = a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
  return a * std::polar(1.0, -0.5 * std::arg(s));
}

}  // namespace

Vec3 principal_axis(const Vec3c& a) { return ellipse_aligned(a).real(); }

Vec3 minor_axis(const Vec3c& a) { return ellipse_aligned(a).imag(); }

double single_transmitter_ellipticity(double major_A_per_m, double k, double moment_max_A_m2) {
  if (!(major_A_per_m > 0.0)) return 1.0;
  const double kr = k * std::cbrt(2.0 * moment_max_A_m2 / (4.0 * kPi * major_A_per_m));
  return std::min(1.0, 0.6 * kr * kr * kr);
}

ReceiverHardware ReceiverHardware::draw(const ReceiverModelConfig& config, std::mt19937_64& rng) {
  const double mis = config.misalignment_sigma_deg * kPi / 180.0;
  ReceiverHardware hw;
  for (int axis = 0; axis < 3; ++axis) {
    const Vec3 g = normal3(rng);  // gain, then the pointing error about the other two axes
    Vec3 dir = Vec3::Unit(axis);
    dir[(axis + 1) % 3] = mis * g[1];
    dir[(axis + 2) % 3] = mis * g[2];
    const double gain = std::clamp(1.0 + config.gain_sigma * g[0], 0.5, 1.5);
    hw.gain.row(axis) = gain * dir.normalized().transpose();
  }
  return hw;
}

Vec3 axis_noise_floor(const ReceiverModelConfig& config, double long_axis_floor) {
  return Vec3(long_axis_floor, config.short_axis_noise_factor * long_axis_floor,
              config.short_axis_noise_factor * long_axis_floor);
}

}  // namespace sarloc::avalanche
