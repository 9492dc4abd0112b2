#include "sarloc/core/avalanche/pulse_detector.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/common/chi_square.hpp"

namespace sarloc::avalanche {
namespace {

using Complex = std::complex<double>;
using Samples = Eigen::Matrix<Complex, 3, Eigen::Dynamic>;

// Prefix sums of the whitened samples demodulated at f: P(:, n) = sum_{k<n} z(:, k) e^{-j2pi f t_k}.
Samples demodulated_prefix(const Samples& whitened, const BasebandWindow& w, double f) {
  const Eigen::Index n = whitened.cols();
  Samples prefix(3, n + 1);
  prefix.col(0).setZero();
  const Complex step = std::polar(1.0, -2.0 * kPi * f / w.sample_rate_hz);
  Complex rot = std::polar(1.0, -2.0 * kPi * f * w.t0_s);
  for (Eigen::Index k = 0; k < n; ++k) {
    prefix.col(k + 1) = prefix.col(k) + whitened.col(k) * rot;
    rot *= step;
    if ((k & 63) == 63) rot /= std::abs(rot);  // keep |rot| = 1 over long windows
  }
  return prefix;
}

// |sum over [a, b)|^2 / length, summed over the axes: chi-square with 6 dof under noise
// (each whitened real component has unit variance).
double statistic(const Samples& prefix, Eigen::Index a, Eigen::Index b) {
  return (prefix.col(b) - prefix.col(a)).squaredNorm() / static_cast<double>(b - a);
}

struct Candidate {
  double f = 0.0;
  Eigen::Index a = 0, b = 0;
  double t = 0.0;
};

// Best interval [a, b) for carrier f, within the bounds, maximising the statistic.
Candidate best_interval(const Samples& whitened, const BasebandWindow& w, double f, Eigen::Index a_lo,
                        Eigen::Index a_hi, Eigen::Index b_lo, Eigen::Index b_hi, Eigen::Index min_len) {
  const Samples prefix = demodulated_prefix(whitened, w, f);
  Candidate best{f, 0, 0, -1.0};
  for (Eigen::Index a = a_lo; a <= a_hi; ++a)
    for (Eigen::Index b = std::max(b_lo, a + min_len); b <= b_hi; ++b) {
      const double t = statistic(prefix, a, b);
      if (t > best.t) best = {f, a, b, t};
    }
  return best;
}

Complex carrier(double f, double t) { return std::polar(1.0, 2.0 * kPi * f * t); }

}  // namespace

std::vector<DetectedPulse> detect_pulses(const BasebandWindow& w, const PulseDetectorConfig& c,
                                         const std::vector<double>& tracked_carriers) {
  std::vector<DetectedPulse> found;
  const Eigen::Index n = w.size();
  const double fs = w.sample_rate_hz;
  const auto matched = static_cast<Eigen::Index>(std::lround(c.min_on_time_s * fs));
  const auto longest = static_cast<Eigen::Index>(std::lround(c.max_on_time_s * fs));
  const auto fragment = std::max<Eigen::Index>(4, std::lround(c.min_fragment_s * fs));
  if (n < fragment) return found;
  Samples whitened = w.samples;
  for (int a = 0; a < 3; ++a) whitened.row(a) /= w.sample_noise[a];
  const Samples original = whitened;

  // Search bands: the whole band first, then each tracked carrier's narrow band with the
  // threshold its own number of tests allows.
  struct Band {
    double lo, hi, threshold;
  };
  auto band = [&](double lo, double hi) {
    const int freqs = static_cast<int>(std::floor((hi - lo) / c.coarse_step_hz)) + 1;
    const double tests = static_cast<double>(freqs) * static_cast<double>(n);
    return Band{lo, hi, chi_square_quantile(1.0 - c.false_alarms_per_window / tests, 6.0)};
  };
  std::vector<Band> bands{band(-c.search_band_hz, c.search_band_hz)};
  for (double f : tracked_carriers) bands.push_back(band(f - c.tracked_band_hz, f + c.tracked_band_hz));
  std::size_t current = 0;

  struct Found {
    double f;
    Eigen::Index a, b;
    double t;
    bool blended = false;
  };
  std::vector<Found> pulses;
  for (std::uint32_t iteration = 0; iteration < 2 * c.max_pulses + bands.size() && pulses.size() < c.max_pulses;
       ++iteration) {
    // Coarse matched filter: 70 ms windows (clipped at the window's edges, for pulses cut by them).
    Candidate best{0.0, 0, 0, -1.0};
    const Band& b = bands[current];
    for (double f = b.lo; f <= b.hi + 1e-9; f += c.coarse_step_hz) {
      const Samples prefix = demodulated_prefix(whitened, w, f);
      for (Eigen::Index a = fragment - matched; a <= n - fragment; ++a) {
        const Eigen::Index lo = std::max<Eigen::Index>(0, a), hi = std::min(n, a + matched);
        if (hi - lo < fragment) continue;
        const double t = statistic(prefix, lo, hi);
        if (t > best.t) best = {f, lo, hi, t};
      }
    }
    if (best.t < b.threshold) {
      if (++current == bands.size()) break;
      continue;
    }
    // Refine: the on-interval around the matched window, then the carrier, then the interval.
    const Eigen::Index slack = 4;
    auto refine_interval = [&](const Candidate& from) {
      const Eigen::Index a_lo = std::max<Eigen::Index>(0, from.b - longest);
      const Eigen::Index a_hi = std::min(from.a + slack, from.b - fragment);
      const Eigen::Index b_lo = std::max(from.b - slack, from.a + fragment);
      const Eigen::Index b_hi = std::min(n, from.a + longest);
      return best_interval(whitened, w, from.f, a_lo, a_hi, b_lo, b_hi, fragment);
    };
    Candidate cand = refine_interval(best);
    Candidate fine = cand;
    for (double df = -c.coarse_step_hz; df <= c.coarse_step_hz + 1e-9; df += c.fine_step_hz) {
      const Samples prefix = demodulated_prefix(whitened, w, cand.f + df);
      const double t = statistic(prefix, cand.a, cand.b);
      if (t > fine.t) fine = {cand.f + df, cand.a, cand.b, t};
    }
    cand = refine_interval(fine);
    // Cancel every pulse found so far from the original by a joint fit (a pulse fitted alone
    // under another's overlap carries its leakage, and the residual would hold ghosts).
    auto cancel = [&](const std::vector<Found>& fitted) {
      const auto m = static_cast<Eigen::Index>(fitted.size());
      Eigen::MatrixXcd design = Eigen::MatrixXcd::Zero(n, m);
      for (Eigen::Index j = 0; j < m; ++j)
        for (Eigen::Index k = fitted[j].a; k < fitted[j].b; ++k) design(k, j) = carrier(fitted[j].f, w.time(k));
      const Eigen::MatrixXcd coeffs = (design.adjoint() * design).ldlt().solve(design.adjoint() * original.transpose());
      whitened = original - (design * coeffs).transpose();
    };
    // What remains of a pulse already found (its carrier or edges a fraction off) is not a new one.
    // Nor is a burst overlapping a pulse within one frequency cell of their overlap (not
    // resolvable), nor a much weaker one: the sidelobes of a strong pulse whose carrier was
    // estimated a fraction of a hertz off.
    bool residual = false;
    for (Found& p : pulses) {
      const auto overlap = std::min(cand.b, p.b) - std::max(cand.a, p.a);
      if (overlap <= 0) continue;
      const double resolution_hz = fs / static_cast<double>(overlap);  // one cell of the overlap
      const double df = std::fabs(p.f - cand.f);
      const bool unresolved = df < std::max(3.0, resolution_hz);
      if (unresolved && cand.t >= c.blend_ratio * p.t) p.blended = true;
      if (unresolved || cand.t < c.sidelobe_ratio * p.t) residual = true;
    }
    std::vector<Found> fitted = pulses;
    fitted.push_back({cand.f, cand.a, cand.b, cand.t, false});
    if (!residual) pulses = fitted;
    cancel(fitted);
  }
  if (pulses.empty()) return found;

  // Joint least squares on the original samples: columns = each pulse's carrier on its interval.
  const auto m = static_cast<Eigen::Index>(pulses.size());
  Eigen::MatrixXcd design = Eigen::MatrixXcd::Zero(n, m);
  for (Eigen::Index j = 0; j < m; ++j)
    for (Eigen::Index k = pulses[j].a; k < pulses[j].b; ++k) design(k, j) = carrier(pulses[j].f, w.time(k));
  const Eigen::MatrixXcd gram = design.adjoint() * design;
  const Eigen::MatrixXcd gram_inv = gram.inverse();
  const Eigen::MatrixXcd coeffs = gram_inv * (design.adjoint() * original.transpose());  // m x 3 (whitened)
  for (Eigen::Index j = 0; j < m; ++j) {
    DetectedPulse d;
    d.start_s = w.time(pulses[j].a);
    d.end_s = w.time(pulses[j].b);
    d.carrier_offset_hz = pulses[j].f;
    d.statistic = pulses[j].t;
    const double own = 1.0 / static_cast<double>(pulses[j].b - pulses[j].a);
    const double joint = std::max(gram_inv(j, j).real(), own);
    d.variance_inflation = joint / own;
    for (int a = 0; a < 3; ++a) {
      d.amplitude[a] = coeffs(j, a) * w.sample_noise[a];
      d.amplitude_noise[a] = w.sample_noise[a] * std::sqrt(joint);
    }
    d.blended = pulses[j].blended;
    d.truncated_start = pulses[j].a == 0;
    d.truncated_end = pulses[j].b == n;
    found.push_back(d);
  }
  std::sort(found.begin(), found.end(), [](const DetectedPulse& x, const DetectedPulse& y) { return x.start_s < y.start_s; });
  return found;
}

}  // namespace sarloc::avalanche
