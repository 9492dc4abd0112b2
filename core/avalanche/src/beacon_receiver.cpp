#include "sarloc/core/avalanche/beacon_receiver.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <utility>
#include <vector>

#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/common/seeds.hpp"

namespace sarloc::avalanche {
namespace {

// An incoming pulse whose share of a detected one is under this fraction of the largest is not
// summed into it (30 dB below it: under the receiver's sidelobes).
constexpr double kNegligibleShare = 1e-3;
// A detected pulse whose largest share is under this fraction of its own energy is noise.
constexpr double kNoiseShare = 0.1;

SeparatorConfig separator_config(const SimulationConfig& c) {
  SeparatorConfig s;
  s.detect_snr = c.receiver.detect_snr;
  s.calibration_relative = c.receiver.calibration_relative;
  s.detector.search_band_hz = c.receiver.carrier_tolerance_hz + 20.0;
  s.detector.max_on_time_s = 1e-3 * c.receiver.on_time_max_ms * 1.1;
  s.wavenumber_rad_per_m = wavenumber(c.receiver);
  s.moment_max_A_m2 = c.standard.moment_max();
  s.detector.two_tone_span_hz = c.receiver.two_tone_span_hz;
  s.detector.same_carrier_pairs = c.receiver.same_carrier_pairs;
  return s;
}

// Drawn from its own stream, so that the device's other hardware draws stay those of a device
// without it (the carriers it hears, hence what it detects, do change).
double draw_oscillator_offset_hz(const ReceiverModelConfig& c, std::uint64_t seed) {
  std::mt19937_64 rng(derive_seed(seed, 0x05C11A7011ULL));
  return std::normal_distribution<double>(0.0, c.oscillator_sigma_ppm * 1e-6 * c.carrier_hz)(rng);
}

// Truth of what the detector heard: each detected pulse's amplitude is the joint least-squares
// fit of every detected pulse (its carrier on its interval) to the window, so it holds
// (G^-1 D^H U)_ip of each incoming pulse p's amplitude, U_p the incoming pulse's unit tone on
// its own interval. Per detected pulse: (share of energy |x_ip|^2 |a_p|^2, p), largest first,
// shares under kNegligibleShare of the largest dropped. Exact for the fit the detector makes
// (pulse_detector.cpp), edges and carriers as it found them; labelling by overlap energy alone
// named the wrong transmitter whenever a stronger pulse a cell away overlapped part of a weaker
// one that the detector had resolved (4 victims, seed 11: one sample in twenty).
std::vector<std::vector<std::pair<double, std::size_t>>> pulse_sources(const BasebandWindow& w,
                                                                       const std::vector<DetectedPulse>& detected,
                                                                       const std::vector<IncomingPulse>& incoming) {
  std::vector<std::vector<std::pair<double, std::size_t>>> out(detected.size());
  if (detected.empty() || incoming.empty()) return out;
  auto index_of = [&](double t) {
    return std::clamp<Eigen::Index>(static_cast<Eigen::Index>(std::ceil((t - w.t0_s) * w.sample_rate_hz - 1e-9)), 0,
                                    w.size());
  };
  auto tone = [&](double f, double start, double end) {
    Eigen::VectorXcd v = Eigen::VectorXcd::Zero(w.size());
    for (Eigen::Index k = index_of(start); k < index_of(end); ++k) v(k) = std::polar(1.0, 2.0 * kPi * f * w.time(k));
    return v;
  };
  Eigen::MatrixXcd design(w.size(), static_cast<Eigen::Index>(detected.size()));
  for (std::size_t i = 0; i < detected.size(); ++i)
    design.col(static_cast<Eigen::Index>(i)) =
        tone(detected[i].carrier_offset_hz, detected[i].start_s, detected[i].end_s);
  Eigen::MatrixXcd arrived(w.size(), static_cast<Eigen::Index>(incoming.size()));
  for (std::size_t p = 0; p < incoming.size(); ++p)
    arrived.col(static_cast<Eigen::Index>(p)) =
        tone(incoming[p].carrier_offset_hz, incoming[p].start_s, incoming[p].end_s);
  const Eigen::MatrixXcd x = (design.adjoint() * design).ldlt().solve(design.adjoint() * arrived);
  for (std::size_t i = 0; i < detected.size(); ++i) {
    for (std::size_t p = 0; p < incoming.size(); ++p) {
      const double share = std::norm(x(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(p))) *
                           incoming[p].amplitude.squaredNorm();
      if (share > 0.0) out[i].emplace_back(share, p);
    }
    std::sort(out[i].begin(), out[i].end(), std::greater<>());
    // Noise that the detector took for a pulse: no transmitter's share comes near its amplitude.
    if (!out[i].empty() && out[i].front().first < kNoiseShare * detected[i].amplitude.squaredNorm()) out[i].clear();
    if (!out[i].empty()) {
      const double floor = kNegligibleShare * out[i].front().first;
      out[i].erase(std::remove_if(out[i].begin(), out[i].end(), [&](const auto& e) { return e.first < floor; }),
                   out[i].end());
    }
  }
  return out;
}

}  // namespace

BeaconReceiver::BeaconReceiver(SimulationConfig config, std::uint64_t seed)
    : config_((config.validate(), std::move(config))),
      rng_(seed),
      hardware_(ReceiverHardware::draw(config_.receiver, rng_)),
      pulse_noise_(axis_noise_floor(config_.receiver, config_.field_noise_floor_A_per_m)),
      oscillator_offset_hz_(draw_oscillator_offset_hz(config_.receiver, seed)),
      k_(wavenumber(config_.receiver)),
      lead_s_(config_.receiver.continuous_listening ? 1e-3 * config_.receiver.on_time_max_ms + 0.05 : 0.0),
      separator_(separator_config(config_)) {}

Listening BeaconReceiver::listen(const ReceiverPose& pose, const std::vector<Beacon>& beacons, double t0_s,
                                 double duration_s) {
  const Mat3 r_world = rotation_from_rpy(pose.rpy);
  std::uniform_real_distribution<double> phase(0.0, 2.0 * kPi);
  std::vector<IncomingPulse> pulses;
  std::vector<Vec3> ideal(beacons.size());  // truth for HeardSample::truth_nis
  for (std::size_t b = 0; b < beacons.size(); ++b) {
    const Beacon& beacon = beacons[b];
    const Vec3c h_world = full_dipole_field(pose.position - beacon.position, beacon.moment, k_);
    Vec3c h_device = r_world.transpose().cast<std::complex<double>>() * h_world;
    ideal[b] = h_device.real();
    if (!beacon.transmitting) continue;
    const double magnitude = h_device.norm();
    for (double start : beacon.timing.starts_in(t0_s - lead_s_, t0_s + duration_s)) {
      // Pulse-to-pulse fluctuation in phase with the pulse (5 % of |H| per axis, as the ideal
      // receiver's), the device's gains, then the carrier phase of this pulse.
      const Vec3 fluctuation = config_.field_noise().relative * magnitude * normal3(rng_);
      const Vec3c a = hardware_.apply(h_device + fluctuation.cast<std::complex<double>>());
      const double phi = config_.receiver.phase_coherent ? beacon.timing.phase_rad : phase(rng_);
      IncomingPulse p;
      p.transmitter = b;
      p.start_s = start;
      p.end_s = start + beacon.timing.on_time_s;
      p.carrier_offset_hz = beacon.timing.carrier_offset_hz - oscillator_offset_hz_;  // as this device hears it
      p.amplitude = a * std::polar(1.0, phi);
      pulses.push_back(p);
    }
  }
  // The device listens without gaps: each window begins with the end of the previous one, so a
  // pulse crossing from one into the next is heard whole (BasebandWindow::lead_s). Windows cut
  // apart lost every pulse of a transmitter whose period was within a few ms of the window's,
  // for minutes: a victim 4 m away never heard (seed 20, trial 36).
  BasebandWindow window =
      synthesize(pulses, t0_s - lead_s_, duration_s + lead_s_, config_.receiver.sample_rate_hz, pulse_noise_, rng_);
  window.lead_s = lead_s_;
  Listening out;
  out.report = separator_.process(window);
  // Truth of each detected pulse: how much of each incoming pulse the detector's final joint
  // least-squares fit put into it (pulse_sources). The largest share is its transmitter.
  const std::vector<std::vector<std::pair<double, std::size_t>>> shares =
      pulse_sources(window, out.report.pulses, pulses);
  auto dominant = [&](std::size_t i) -> std::optional<std::size_t> {
    if (shares[i].empty()) return std::nullopt;
    return pulses[shares[i].front().second].transmitter;
  };
  for (std::size_t i = 0; i < out.report.pulses.size(); ++i) {
    if (!out.report.attributed[i]) continue;
    const std::uint32_t signal = *out.report.attributed[i];
    const auto truth = dominant(i);
    const auto known = beacon_of_signal(signal);
    if (!known && truth) truth_.emplace_back(signal, *truth);
    else if (known && truth != known) ++out.wrong_attributions;
  }
  for (const auto& s : out.report.samples) {
    HeardSample& h = out.samples.emplace_back();
    h.sample = s;
    h.transmitter = dominant(s.pulse);
    if (h.transmitter) {
      const Vec3& truth = ideal[*h.transmitter];
      double plus = 0.0, minus = 0.0;
      for (int a = 0; a < 3; ++a) {
        if ((s.valid_axes & (1U << a)) == 0) continue;
        const double sigma = config_.field_noise().sigma(truth.norm(), s.noise[a]);
        plus += std::pow((s.field[a] - truth[a]) / sigma, 2);
        minus += std::pow((s.field[a] + truth[a]) / sigma, 2);
      }
      h.truth_nis = std::min(plus, minus);
    }
    // Summed into it: the largest share of another transmitter's pulse.
    for (const auto& [share, k] : shares[s.pulse]) {
      if (pulses[k].transmitter == h.transmitter) continue;
      h.mixed_with = pulses[k].transmitter;
      h.mixed_energy_ratio = share / shares[s.pulse].front().first;
      break;
    }
    if (out.samples.back().transmitter) ++samples_of_[s.signal_id][*out.samples.back().transmitter];
  }
  // What the device says of each transmitter, its own oscillator's tolerance added: the
  // carrier's in Hz, the period's relative (the clock runs on the same crystal).
  const double ppm = config_.receiver.oscillator_sigma_ppm * 1e-6;
  auto stated = [&](std::uint32_t signal) {
    auto s = separator_.signature_of(signal);
    if (!s) return;
    if (s->carrier_known()) s->carrier_sigma_hz = std::hypot(s->carrier_sigma_hz, ppm * config_.receiver.carrier_hz);
    if (s->period_known()) s->period_sigma_s = std::hypot(s->period_sigma_s, ppm * s->period_s);
    out.transmitters[signal] = *s;
  };
  for (const auto& s : out.report.samples) stated(s.signal_id);  // a miss carries no signature
  return out;
}

std::optional<std::size_t> BeaconReceiver::majority_beacon_of_signal(std::uint32_t signal_id) const {
  const auto it = samples_of_.find(signal_id);
  if (it == samples_of_.end() || it->second.empty()) return std::nullopt;
  const auto most = std::max_element(it->second.begin(), it->second.end(),
                                     [](const auto& a, const auto& b) { return a.second < b.second; });
  return most->first;
}

std::optional<std::size_t> BeaconReceiver::beacon_of_signal(std::uint32_t signal_id) const {
  for (const auto& [signal, beacon] : truth_)
    if (signal == signal_id) return beacon;
  return std::nullopt;
}

std::vector<FieldMeasurement> to_measurements(const Listening& heard, const std::string& rescuer_id,
                                              std::uint64_t sequence, TimestampNs stamp,
                                              const std::optional<OrientationObservation>& attitude) {
  std::vector<FieldMeasurement> out;
  for (const auto& h : heard.samples) {
    FieldMeasurement m;
    m.rescuer_id = rescuer_id;
    m.signal_id = h.sample.signal_id;
    m.sequence = sequence;
    m.stamp = stamp;
    m.field = h.sample.field;
    m.noise_stddev = h.sample.noise;
    m.valid_axes = h.sample.valid_axes;
    m.event = h.sample.event;
    if (const auto t = heard.transmitters.find(m.signal_id); t != heard.transmitters.end()) m.transmitter = t->second;
    m.unattributed_pulses = heard.report.unattributed;
    m.orientation = attitude;
    out.push_back(m);
  }
  for (const auto& miss : heard.report.misses) {
    FieldMeasurement m;  // a pulse due, not heard: valid_axes 0 (SogFilter::process)
    m.rescuer_id = rescuer_id;
    m.signal_id = miss.signal_id;
    m.sequence = sequence;
    m.stamp = stamp;
    m.field = Vec3::Zero();
    m.noise_stddev = miss.noise;
    m.valid_axes = 0;
    m.unattributed_pulses = heard.report.unattributed;
    m.orientation = attitude;
    out.push_back(m);
  }
  return out;
}

}  // namespace sarloc::avalanche
