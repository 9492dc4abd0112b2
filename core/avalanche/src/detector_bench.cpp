#include "sarloc/core/avalanche/detector_bench.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/avalanche/pulse_train.hpp"
#include "sarloc/core/avalanche/receiver_model.hpp"
#include "sarloc/core/avalanche/sensor_simulation.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/statistics.hpp"

namespace sarloc::avalanche {
namespace {

constexpr double kSampleRateHz = 500.0;
constexpr double kWindowS = 0.5;
constexpr double kMatchHz = 3.0;  // a detected pulse is a transmitter's within this of its carrier
constexpr double kLongAxisNoise = 1e-3;  // A/m per 70 ms pulse; the short axes from the receiver model

Vec3c field(std::mt19937_64& rng, double amplitude) {
  std::uniform_real_distribution<double> phase(0.0, 2.0 * kPi);
  const Vec3 direction = normal3(rng).normalized();
  return (direction * amplitude).cast<std::complex<double>>() * std::polar(1.0, phase(rng));
}

std::vector<IncomingPulse> draw(DetectorScenario scenario, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto db = [&](double lo, double hi) { return kLongAxisNoise * std::pow(10.0, (lo + (hi - lo) * u(rng)) / 20.0); };
  std::vector<IncomingPulse> pulses;
  if (scenario == DetectorScenario::kSingle) {
    const double start = 0.1 + 0.2 * u(rng), on = 0.07 + 0.13 * u(rng);
    pulses.push_back({0, start, start + on, -60.0 + 120.0 * u(rng), field(rng, db(20.0, 70.0))});
  } else if (scenario == DetectorScenario::kNestedPair) {
    const double carrier = -60.0 + 120.0 * u(rng), gap = 0.5 + 2.5 * u(rng);
    const double outer = 0.08 + 0.12 * u(rng), inner = 0.07 + (outer - 0.075) * u(rng);
    const double start = 0.1 + 0.2 * u(rng);
    const double inner_start = u(rng) < 0.5 ? start + outer - inner : start + (outer - inner) * u(rng);
    const double a = db(40.0, 70.0);
    pulses.push_back({0, start, start + outer, carrier, field(rng, a)});
    pulses.push_back({1, inner_start, inner_start + inner, carrier + gap, field(rng, a * std::pow(10.0, -0.75 * u(rng)))});
  } else if (scenario == DetectorScenario::kLockstepPair) {
    // As the multiple-burial evaluation draws a pair (multi_burial.cpp): on-times 70-200 ms,
    // starts within +-0.3 on-times, carriers within a tenth of a cell.
    const double carrier = -60.0 + 120.0 * u(rng), gap = 1.5 * u(rng);
    const double first_on = 0.07 + 0.13 * u(rng), second_on = 0.07 + 0.13 * u(rng);
    const double start = 0.1 + 0.1 * u(rng), second_start = start + 0.3 * first_on * (2.0 * u(rng) - 1.0);
    const double a = db(40.0, 70.0);
    pulses.push_back({0, start, start + first_on, carrier, field(rng, a)});
    pulses.push_back({1, second_start, second_start + second_on, carrier + gap, field(rng, a * std::pow(10.0, -0.75 * u(rng)))});
  } else {
    const double carriers[4] = {-6.0, 50.0, 65.0, 78.0};  // 12-84 Hz apart: cells of their overlap
    const double start = 0.1 + 0.2 * u(rng);
    for (std::size_t i = 0; i < 4; ++i) {
      const double s = start + 0.008 * (u(rng) - 0.5), on = 0.1 + 0.06 * u(rng);
      pulses.push_back({i, s, s + on, carriers[i] + 0.3 * (u(rng) - 0.5), field(rng, db(40.0, 70.0))});
    }
  }
  return pulses;
}

// The transmitter a detected pulse holds: within kMatchHz and overlapping it, the nearest edges.
const IncomingPulse* truth_of(const DetectedPulse& d, const std::vector<IncomingPulse>& pulses) {
  const IncomingPulse* best = nullptr;
  double best_edges = 0.0;
  for (const auto& p : pulses) {
    const double overlap = std::min(p.end_s, d.end_s) - std::max(p.start_s, d.start_s);
    if (overlap <= 0.0 || std::fabs(p.carrier_offset_hz - d.carrier_offset_hz) > kMatchHz) continue;
    const double edges = std::fabs(p.start_s - d.start_s) + std::fabs(p.end_s - d.end_s);
    if (!best || edges < best_edges) {
      best = &p;
      best_edges = edges;
    }
  }
  return best;
}

// Sample index of a time: the simulator turns a pulse on at the first sample at or after it.
long sample_of(double t_s) { return static_cast<long>(std::ceil(t_s * kSampleRateHz - 1e-9)); }

}  // namespace

const char* to_string(DetectorScenario scenario) {
  switch (scenario) {
    case DetectorScenario::kSingle: return "single";
    case DetectorScenario::kNestedPair: return "nested-pair";
    case DetectorScenario::kTogether: return "together";
    case DetectorScenario::kLockstepPair: return "lockstep-pair";
  }
  return "?";
}

void DetectorBenchSetup::validate() const {
  if (draws < 1 || draws > 100000) {
    std::ostringstream os;
    os << "detector_bench.draws = " << draws << ": must be in [1, 100000]";
    throw ConfigError(os.str());
  }
  separator.validate();
}

DetectorBenchResult run_detector_bench(const DetectorBenchSetup& setup, const std::function<void()>& on_draw,
                                       const std::function<bool()>& cancelled) {
  setup.validate();
  const SignalSeparator separator(setup.separator);
  const Vec3 pulse_noise = axis_noise_floor(ReceiverModelConfig{}, kLongAxisNoise);
  std::mt19937_64 rng(setup.seed);
  DetectorBenchResult r;
  std::vector<double> carrier_errors;
  std::uint32_t exact = 0;
  for (std::uint32_t i = 0; i < setup.draws && !(cancelled && cancelled()); ++i) {
    const std::vector<IncomingPulse> truth = draw(setup.scenario, rng);
    const BasebandWindow window = synthesize(truth, 0.0, kWindowS, kSampleRateHz, pulse_noise, rng);
    const std::vector<DetectedPulse> detected = detect_pulses(window, setup.separator.detector);
    ++r.draws;
    if (on_draw) on_draw();
    r.transmitters += static_cast<std::uint32_t>(truth.size());
    for (const DetectedPulse& d : detected) {
      ++r.pulses;
      const IncomingPulse* p = truth_of(d, truth);
      const bool through = !separator.unseparable(d);
      if (!p) ++r.spurious;
      if (!through) continue;
      ++r.let_through;
      if (!p) {
        ++r.let_through_spurious;
        continue;
      }
      // Up to a common phase: a carrier a little off turns the phase referred to t = 0, and the
      // field the tracks take (its principal axis, sign unknown) does not depend on it.
      const std::complex<double> turn = std::polar(1.0, std::arg(p->amplitude.dot(d.amplitude)));
      const Vec3c error = d.amplitude - p->amplitude * turn;
      double squared = 0.0;
      for (int a = 0; a < 3; ++a) squared += std::norm(error[a]) / (d.amplitude_noise[a] * d.amplitude_noise[a]);
      r.error_sigma.push_back(std::sqrt(squared / 6.0));
      r.error_relative.push_back(error.norm() / p->amplitude.norm());
      carrier_errors.push_back(std::fabs(d.carrier_offset_hz - p->carrier_offset_hz));
      if (sample_of(d.start_s) == sample_of(p->start_s) && sample_of(d.end_s) == sample_of(p->end_s)) ++exact;
    }
  }
  std::sort(r.error_sigma.begin(), r.error_sigma.end());
  std::sort(r.error_relative.begin(), r.error_relative.end());
  for (double e : r.error_relative)
    if (e > 0.05) ++r.beyond_5_percent;
  for (double e : r.error_sigma) {
    if (e > 10.0) ++r.beyond_10_sigma;
    if (e > 50.0) ++r.beyond_50_sigma;
  }
  if (!carrier_errors.empty()) {
    r.carrier_error_median_hz = percentile(carrier_errors, 0.5);
    r.edges_exact_share = static_cast<double>(exact) / static_cast<double>(r.error_sigma.size());
  }
  return r;
}

}  // namespace sarloc::avalanche
