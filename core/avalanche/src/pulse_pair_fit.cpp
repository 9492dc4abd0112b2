#include "sarloc/core/avalanche/pulse_pair_fit.hpp"

#include <algorithm>
#include <cmath>

#include "sarloc/core/avalanche/dipole_model.hpp"

namespace sarloc::avalanche {
namespace {

using Complex = std::complex<double>;

// Columns closer than this to collinear (variance inflation 50) are not told apart.
constexpr double kMinIndependence = 0.02;

// Prefix sums of e^{j2pi df t_k}: the Gram entry of two bursts df apart over any overlap.
Eigen::VectorXcd cross_prefix(const BasebandWindow& w, double df) {
  const Eigen::Index n = w.size();
  Eigen::VectorXcd q(n + 1);
  q(0) = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) q(k + 1) = q(k) + std::polar(1.0, 2.0 * kPi * df * w.time(k));
  return q;
}

// Joint energy of two bursts from their projections and Gram entries (sum over the axes of
// c^H G^-1 c); 0 when the columns are nearly collinear.
double pair_energy(const Eigen::Vector3cd& cx, const Eigen::Vector3cd& cy, double gxx, double gyy, Complex gxy) {
  const double det = gxx * gyy - std::norm(gxy);
  if (det <= kMinIndependence * gxx * gyy) return 0.0;
  double e = 0.0;
  for (int a = 0; a < 3; ++a)
    e += gyy * std::norm(cx[a]) + gxx * std::norm(cy[a]) - 2.0 * (std::conj(cx[a]) * gxy * cy[a]).real();
  return e / det;
}

}  // namespace

WhitenedSamples demodulated_prefix(const WhitenedSamples& whitened, const BasebandWindow& w, double f) {
  const Eigen::Index n = whitened.cols();
  WhitenedSamples prefix(3, n + 1);
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

PulsePairFit::PulsePairFit(const WhitenedSamples& whitened, const BasebandWindow& window) : z_(whitened), w_(window) {}

Eigen::Vector3cd PulsePairFit::projection(const ToneBurst& b) const {
  Eigen::Vector3cd c = Eigen::Vector3cd::Zero();
  for (Eigen::Index k = b.begin; k < b.end; ++k) c += z_.col(k) * std::polar(1.0, -2.0 * kPi * b.carrier_hz * w_.time(k));
  return c;
}

namespace {

Complex gram(const BasebandWindow& w, const ToneBurst& x, const ToneBurst& y) {
  Complex g = 0.0;
  for (Eigen::Index k = std::max(x.begin, y.begin); k < std::min(x.end, y.end); ++k)
    g += std::polar(1.0, 2.0 * kPi * (y.carrier_hz - x.carrier_hz) * w.time(k));
  return g;
}

}  // namespace

double PulsePairFit::energy(const ToneBurst& x, const ToneBurst& y) const {
  return pair_energy(projection(x), projection(y), static_cast<double>(x.end - x.begin),
                     static_cast<double>(y.end - y.begin), gram(w_, x, y));
}

ToneBurst PulsePairFit::best_single(Eigen::Index lo, Eigen::Index hi, double carrier_hz, const BurstLimits& limits) const {
  ToneBurst best{carrier_hz, lo, lo, 0.0};
  for (double f = carrier_hz - limits.carrier_span_hz; f <= carrier_hz + limits.carrier_span_hz + 1e-9;
       f += limits.carrier_step_hz) {
    const WhitenedSamples p = demodulated_prefix(z_, w_, f);
    for (Eigen::Index a = lo; a + limits.min_length <= hi; ++a)
      for (Eigen::Index b = a + limits.min_length; b <= std::min(hi, a + limits.max_length); ++b) {
        const double e = (p.col(b) - p.col(a)).squaredNorm() / static_cast<double>(b - a);
        if (e > best.energy) best = {f, a, b, e};
      }
  }
  return best;
}

ToneBurst PulsePairFit::best_interval_with(const ToneBurst& x, const Eigen::Vector3cd& cx, double f, Eigen::Index a_lo,
                                           Eigen::Index a_hi, Eigen::Index b_lo, Eigen::Index b_hi,
                                           const BurstLimits& limits) const {
  const WhitenedSamples p = demodulated_prefix(z_, w_, f);
  const Eigen::VectorXcd q = cross_prefix(w_, f - x.carrier_hz);  // conj(x column) * y column
  const double gxx = static_cast<double>(x.end - x.begin);
  ToneBurst best{f, 0, 0, 0.0};
  for (Eigen::Index a = a_lo; a <= a_hi; ++a)
    for (Eigen::Index b = std::max(b_lo, a + limits.min_length); b <= std::min(b_hi, a + limits.max_length); ++b) {
      const Eigen::Index o_lo = std::max(a, x.begin), o_hi = std::min(b, x.end);
      const Complex gxy = o_hi > o_lo ? q(o_hi) - q(o_lo) : Complex(0.0);
      const Eigen::Vector3cd cy = p.col(b) - p.col(a);
      const double e = pair_energy(cx, cy, gxx, static_cast<double>(b - a), gxy);
      if (e > best.energy) best = {f, a, b, e};
    }
  return best;
}

ToneBurst PulsePairFit::best_partner(const ToneBurst& x, ToneBurst y, Eigen::Index lo, Eigen::Index hi,
                                     const BurstLimits& limits, Eigen::Index slack) const {
  const Eigen::Vector3cd cx = projection(x);
  const bool anywhere = slack < 0;
  const Eigen::Index a_lo = anywhere ? lo : std::max(lo, y.begin - slack);
  const Eigen::Index a_hi = anywhere ? hi - limits.min_length : std::min(hi - limits.min_length, y.begin + slack);
  const Eigen::Index b_lo = anywhere ? lo + limits.min_length : std::max(lo + limits.min_length, y.end - slack);
  const Eigen::Index b_hi = anywhere ? hi : std::min(hi, y.end + slack);
  // Interval on a coarse carrier grid (5 carriers over the span), then the carrier on the fine one.
  ToneBurst best = y;
  best.energy = 0.0;
  const double coarse = limits.carrier_span_hz / 2.0;
  for (int i = -2; i <= 2; ++i) {
    const ToneBurst c = best_interval_with(x, cx, y.carrier_hz + i * coarse, a_lo, a_hi, b_lo, b_hi, limits);
    if (c.energy > best.energy) best = c;
  }
  if (best.energy <= 0.0) return y;
  const double gxx = static_cast<double>(x.end - x.begin), gyy = static_cast<double>(best.end - best.begin);
  ToneBurst fine = best;
  for (double f = best.carrier_hz - coarse; f <= best.carrier_hz + coarse + 1e-9; f += limits.carrier_step_hz) {
    ToneBurst trial{f, best.begin, best.end, 0.0};
    trial.energy = pair_energy(cx, projection(trial), gxx, gyy, gram(w_, x, trial));
    if (trial.energy > fine.energy) fine = trial;
  }
  return fine;
}

std::pair<ToneBurst, ToneBurst> PulsePairFit::best_spanning_pair(Eigen::Index begin, Eigen::Index end, double f,
                                                                 const BurstLimits& limits) const {
  const WhitenedSamples p = demodulated_prefix(z_, w_, f);
  std::pair<ToneBurst, ToneBurst> best{{f, begin, begin, 0.0}, {f, end, end, 0.0}};
  auto consider = [&](Eigen::Index xa, Eigen::Index xb, Eigen::Index ya, Eigen::Index yb) {
    if (!limits.fits(xa, xb) || !limits.fits(ya, yb)) return;
    const Eigen::Index overlap = std::max<Eigen::Index>(0, std::min(xb, yb) - std::max(xa, ya));
    const double e = pair_energy(p.col(xb) - p.col(xa), p.col(yb) - p.col(ya), static_cast<double>(xb - xa),
                                 static_cast<double>(yb - ya), Complex(static_cast<double>(overlap), 0.0));
    if (e > best.first.energy) best = {{f, xa, xb, e}, {f, ya, yb, e}};
  };
  for (Eigen::Index u = begin + 1; u < end; ++u)
    for (Eigen::Index v = begin + 1; v < end; ++v) consider(begin, u, v, end);  // staggered, or apart
  for (Eigen::Index u = begin; u < end; ++u)
    for (Eigen::Index v = u + 1; v <= end; ++v)
      if (v - u < end - begin) consider(begin, end, u, v);  // nested
  return best;
}

std::pair<ToneBurst, ToneBurst> PulsePairFit::polish_edges(ToneBurst x, ToneBurst y, Eigen::Index lo, Eigen::Index hi,
                                                           const BurstLimits& limits, Eigen::Index slack) const {
  const WhitenedSamples px = demodulated_prefix(z_, w_, x.carrier_hz), py = demodulated_prefix(z_, w_, y.carrier_hz);
  const Eigen::VectorXcd q = cross_prefix(w_, y.carrier_hz - x.carrier_hz);
  auto range = [&](Eigen::Index at) { return std::make_pair(std::max(lo, at - slack), std::min(hi, at + slack)); };
  const auto [xa_lo, xa_hi] = range(x.begin);
  const auto [xb_lo, xb_hi] = range(x.end);
  const auto [ya_lo, ya_hi] = range(y.begin);
  const auto [yb_lo, yb_hi] = range(y.end);
  std::pair<ToneBurst, ToneBurst> best{x, y};
  best.first.energy = best.second.energy = energy(x, y);
  for (Eigen::Index xa = xa_lo; xa <= xa_hi; ++xa)
    for (Eigen::Index xb = xb_lo; xb <= xb_hi; ++xb) {
      if (!limits.fits(xa, xb)) continue;
      const Eigen::Vector3cd cx = px.col(xb) - px.col(xa);
      for (Eigen::Index ya = ya_lo; ya <= ya_hi; ++ya)
        for (Eigen::Index yb = yb_lo; yb <= yb_hi; ++yb) {
          if (!limits.fits(ya, yb)) continue;
          const Eigen::Index o_lo = std::max(xa, ya), o_hi = std::min(xb, yb);
          const Complex gxy = o_hi > o_lo ? q(o_hi) - q(o_lo) : Complex(0.0);
          const double e = pair_energy(cx, py.col(yb) - py.col(ya), static_cast<double>(xb - xa),
                                       static_cast<double>(yb - ya), gxy);
          if (e > best.first.energy) {
            best = {{x.carrier_hz, xa, xb, e}, {y.carrier_hz, ya, yb, e}};
          }
        }
    }
  return best;
}

std::pair<ToneBurst, ToneBurst> PulsePairFit::refine(ToneBurst x, ToneBurst y, Eigen::Index lo, Eigen::Index hi,
                                                     const BurstLimits& limits, int rounds, Eigen::Index slack) const {
  for (int r = 0; r < rounds; ++r) {
    y = best_partner(x, y, lo, hi, limits, slack);
    x = best_partner(y, x, lo, hi, limits, slack);
  }
  x.energy = y.energy = energy(x, y);
  return {x, y};
}

}  // namespace sarloc::avalanche
