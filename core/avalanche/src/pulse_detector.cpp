#include "sarloc/core/avalanche/pulse_detector.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <optional>
#include <tuple>

#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/avalanche/pulse_pair_fit.hpp"
#include "sarloc/core/common/chi_square.hpp"

namespace sarloc::avalanche {
namespace {

using Complex = std::complex<double>;
using Samples = WhitenedSamples;

// 30 dB: what a one-burst model of a real pulse may miss. A two-burst refit is kept when it beats
// one burst by the detection threshold plus this share of it.
constexpr double kModelFloor = 1e-3;
// Two bursts on one carrier that overlap by more than this noise inflation are one pulse with a
// neighbour's leakage fitted twice (the bench's `together`: a lone transmitter's pulse split into
// two nearly equal bursts), not a pair.
constexpr double kMaxPairInflation = 4.0;

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

struct Found {
  double f;
  Eigen::Index a, b;
  double t;
  bool blended = false;
  bool split = false;  ///< one of a same-carrier pair refitted jointly: statistic from the fit
};

// Columns: each pulse's carrier on its interval.
Eigen::MatrixXcd design_matrix(const std::vector<Found>& pulses, const BasebandWindow& w) {
  Eigen::MatrixXcd design = Eigen::MatrixXcd::Zero(w.size(), static_cast<Eigen::Index>(pulses.size()));
  for (Eigen::Index j = 0; j < design.cols(); ++j)
    for (Eigen::Index k = pulses[j].a; k < pulses[j].b; ++k) design(k, j) = carrier(pulses[j].f, w.time(k));
  return design;
}

// The samples less the joint least-squares fit of the pulses.
Samples residual_of(const Samples& original, const BasebandWindow& w, const std::vector<Found>& pulses) {
  if (pulses.empty()) return original;
  const Eigen::MatrixXcd design = design_matrix(pulses, w);
  const Eigen::MatrixXcd coeffs = (design.adjoint() * design).ldlt().solve(design.adjoint() * original.transpose());
  return original - (design * coeffs).transpose();
}

// The samples less the joint least-squares fit of every pulse but those listed.
Samples without_others(const Samples& original, const BasebandWindow& w, const std::vector<Found>& pulses,
                       const std::vector<std::size_t>& keep) {
  std::vector<Found> others;
  for (std::size_t j = 0; j < pulses.size(); ++j)
    if (std::find(keep.begin(), keep.end(), j) == keep.end()) others.push_back(pulses[j]);
  return residual_of(original, w, others);
}

// The most of pulse p's statistic that its cancellation may leave in burst [a, b) at carrier f
// (PulseDetectorConfig::sidelobe_ratio): near its carrier a fraction of it, falling with the
// sidelobes of a burst as long as their overlap, and an edge one sample off inside the burst.
double residual_bound(const Found& p, double f, Eigen::Index a, Eigen::Index b, Eigen::Index overlap,
                      const PulseDetectorConfig& c, double fs) {
  const double cells = std::fabs(p.f - f) * static_cast<double>(overlap) / fs;
  const double sidelobes = std::max(c.far_sidelobe_ratio, c.sidelobe_ratio * std::min(1.0, 1.0 / (kPi * kPi * cells * cells)));
  const int edges = (p.a > a && p.a < b ? 1 : 0) + (p.b > a && p.b < b ? 1 : 0);
  return p.t * (sidelobes + edges / (static_cast<double>(p.b - p.a) * static_cast<double>(b - a)));
}

bool same_cell(const Found& p, const Found& q, double fs) {
  const auto shorter = std::max<Eigen::Index>(1, std::min(p.b - p.a, q.b - q.a));
  return std::fabs(p.f - q.f) < std::max(3.0, fs / static_cast<double>(shorter));
}

// A burst's length between the shortest fragment and the longest on-time; its carrier refined
// within +- span_hz on the fine grid.
BurstLimits burst_limits(const PulseDetectorConfig& c, double fs, double span_hz) {
  BurstLimits limits;
  limits.min_length = std::max<Eigen::Index>(4, std::lround(c.min_fragment_s * fs));
  limits.max_length = static_cast<Eigen::Index>(std::lround(c.max_on_time_s * fs));
  limits.carrier_span_hz = span_hz;
  limits.carrier_step_hz = c.fine_step_hz;
  return limits;
}

// A real pulse is at least the matched window long unless the window's edge cuts it.
bool whole_pulse(const ToneBurst& b, Eigen::Index matched, Eigen::Index n) {
  return b.end - b.begin >= matched || b.begin == 0 || b.end == n;
}

// The most energy one burst in [lo, hi) captures at any of these carriers (each held).
double best_single_at(const PulsePairFit& fit, std::initializer_list<double> carriers, Eigen::Index lo, Eigen::Index hi,
                      BurstLimits limits) {
  limits.carrier_span_hz = 0.0;
  double best = 0.0;
  for (double f : carriers) best = std::max(best, fit.best_single(lo, hi, f, limits).energy);
  return best;
}

// Two bursts are kept over one when they capture more by the detection threshold plus kModelFloor.
bool beats_one_burst(double pair_energy, double single, double threshold) {
  return pair_energy - single > threshold + kModelFloor * single;
}

// Two transmitters on one carrier, overlapping (pulse_pair_fit.hpp). Candidates: a blended pulse
// (its partner searched for), or two pieces within one frequency cell that abut (successive
// cancellation carves an overlapping pair at the other's edge). The pair is refitted jointly and
// kept when it captures more than the best single burst by the detection threshold plus a
// 30 dB model floor; otherwise they are flagged blended (their fields are mixtures). A burst
// under a pulse below blend_ratio is not tried: tried, it split more than it should (3 victims,
// seed 1: ghosts 4 -> 7).
void resolve_same_carrier_pairs(std::vector<Found>& pulses, const Samples& original, const BasebandWindow& w,
                                const PulseDetectorConfig& c, double threshold) {
  const double fs = w.sample_rate_hz;
  const Eigen::Index n = w.size();
  const auto matched = static_cast<Eigen::Index>(std::lround(c.min_on_time_s * fs));
  const BurstLimits limits = burst_limits(c, fs, 1.0);
  BurstLimits partner_search = limits;
  partner_search.carrier_span_hz = 4.0;  // a partner up to a cell away
  constexpr Eigen::Index kAbut = 2;      // samples
  const Eigen::Index margin = limits.max_length / 2;

  for (std::size_t i = 0; i < pulses.size(); ++i) {
    if (pulses[i].split) continue;
    std::optional<std::size_t> mate;
    for (std::size_t j = 0; j < pulses.size(); ++j) {
      if (j == i || pulses[j].split || !same_cell(pulses[i], pulses[j], fs)) continue;
      if (std::abs(pulses[j].a - pulses[i].b) <= kAbut || std::abs(pulses[i].a - pulses[j].b) <= kAbut) mate = j;
    }
    if (!mate && !pulses[i].blended) continue;
    std::vector<std::size_t> members{i};
    if (mate) members.push_back(*mate);
    const Samples z = without_others(original, w, pulses, members);
    const PulsePairFit fit(z, w);
    ToneBurst x{pulses[i].f, pulses[i].a, pulses[i].b, 0.0};
    Eigen::Index lo = x.begin, hi = x.end;
    ToneBurst y;
    if (mate) {
      y = {pulses[*mate].f, pulses[*mate].a, pulses[*mate].b, 0.0};
      lo = std::min(lo, y.begin);
      hi = std::max(hi, y.end);
    }
    lo = std::max<Eigen::Index>(0, lo - margin);
    hi = std::min(n, hi + margin);
    if (!mate) y = fit.best_partner(x, x, lo, hi, partner_search, -1);
    const auto [rx, ry] = fit.refine(x, y, lo, hi, limits);
    const double single = best_single_at(fit, {rx.carrier_hz, ry.carrier_hz, pulses[i].f}, lo, hi, limits);
    const bool kept = beats_one_burst(rx.energy, single, threshold) && whole_pulse(rx, matched, n) && whole_pulse(ry, matched, n);
    if (!kept) {
      for (std::size_t m : members) pulses[m].blended = true;
      continue;
    }
    pulses[i] = {rx.carrier_hz, rx.begin, rx.end, pulses[i].t, false, true};
    if (mate) pulses[*mate] = {ry.carrier_hz, ry.begin, ry.end, pulses[*mate].t, false, true};
    else pulses.push_back({ry.carrier_hz, ry.begin, ry.end, 0.0, false, true});
  }
}

struct OneTone {
  double captured = 0.0;  ///< energy one tone at the pulse's carrier captures on its interval
  double left = 0.0;      ///< what it leaves there beyond the noise's 6 per sample (whitened)
};

OneTone one_tone_fit(const Samples& z, const BasebandWindow& w, const Found& p) {
  const Samples prefix = demodulated_prefix(z, w, p.f);
  const auto length = static_cast<double>(p.b - p.a);
  const double captured = statistic(prefix, p.a, p.b);
  return {captured, z.middleCols(p.a, p.b - p.a).squaredNorm() - captured - 6.0 * (length - 1.0)};
}

// One tone leaves energy on the pulse beyond the threshold, 30 dB of the tone and 5 sigma of the
// noise (12 real components per sample): something else is in it.
bool leaves_energy(const OneTone& one, const Found& p, double threshold) {
  const auto length = static_cast<double>(p.b - p.a);
  return one.left > threshold + kModelFloor * one.captured + 5.0 * std::sqrt(12.0 * length);
}

// A pulse on the same carrier that overlaps this one and outlasts it shows as energy at its
// carrier running out from one of its edges. The union of the pulse and the strongest such burst
// (from its start backwards or from its end onwards, within [lo, hi)) whose statistic exceeds
// the threshold, 30 dB of the pulse and what an edge a sample off leaves (that sample's share of
// the pulse, twice); nullopt if none.
std::optional<std::pair<Eigen::Index, Eigen::Index>> outlasting_span(const Samples& z, const BasebandWindow& w,
                                                                     const Found& p, Eigen::Index lo, Eigen::Index hi,
                                                                     double captured, double threshold) {
  constexpr Eigen::Index kShortest = 2;  // samples
  constexpr double kCarrierSearchHz = 40.0, kCarrierStepHz = 0.5, kCarrierMatchHz = 3.0;
  const Samples prefix = demodulated_prefix(z, w, p.f);
  const auto length = static_cast<double>(p.b - p.a);
  std::optional<std::pair<Eigen::Index, Eigen::Index>> span;
  double best = 0.0;
  auto consider = [&](Eigen::Index a, Eigen::Index b) {
    const double edge = 2.0 * captured / (length * static_cast<double>(b - a));
    const double excess = statistic(prefix, a, b) - (threshold + kModelFloor * captured + edge);
    if (excess > best) {
      best = excess;
      span = std::make_pair(std::min(a, p.a), std::max(b, p.b));
    }
  };
  for (Eigen::Index a = p.a - kShortest; a >= lo; --a) consider(a, p.a);
  for (Eigen::Index b = p.b + kShortest; b <= hi; ++b) consider(p.b, b);
  if (!span) return span;
  // Its energy must peak at the pulse's carrier: what the others' cancellation leaves (transmitters
  // a cell or more away) peaks at theirs (bench `together`: 10-40 Hz off, where a pair in lockstep
  // peaks within 1 Hz).
  const Eigen::Index u = span->first < p.a ? span->first : p.b, v = span->first < p.a ? p.a : span->second;
  double peak_hz = p.f, peak = 0.0;
  for (double f = p.f - kCarrierSearchHz; f <= p.f + kCarrierSearchHz + 1e-9; f += kCarrierStepHz) {
    Eigen::Vector3cd sum = Eigen::Vector3cd::Zero();
    for (Eigen::Index k = u; k < v; ++k) sum += z.col(k) * std::conj(carrier(f, w.time(k)));
    if (sum.squaredNorm() > peak) {
      peak = sum.squaredNorm();
      peak_hz = f;
    }
  }
  if (std::fabs(peak_hz - p.f) > kCarrierMatchHz) return std::nullopt;
  return span;
}

// The single bursts' spectrum around f (a 2 Hz grid, each its best interval in [lo, hi)): two
// tones show as peaks at their own carriers next to their blend's at the mean. Returns the
// strongest peaks and the best single burst's energy.
std::pair<std::vector<ToneBurst>, double> single_burst_peaks(const PulsePairFit& fit, double f, double span_hz,
                                                             Eigen::Index lo, Eigen::Index hi, BurstLimits at_f) {
  constexpr double kGridHz = 2.0;    // a fifth of a 100 ms pulse's cell
  constexpr std::size_t kPeaks = 3;  // the two tones' and their blend's
  at_f.carrier_span_hz = 0.0;
  std::vector<ToneBurst> spectrum;
  for (double g = f - span_hz; g <= f + span_hz + 1e-9; g += kGridHz) spectrum.push_back(fit.best_single(lo, hi, g, at_f));
  std::vector<ToneBurst> peaks;
  double single = 0.0;
  for (std::size_t k = 0; k < spectrum.size(); ++k) {
    single = std::max(single, spectrum[k].energy);
    const bool peak = (k == 0 || spectrum[k].energy > spectrum[k - 1].energy) &&
                      (k + 1 == spectrum.size() || spectrum[k].energy >= spectrum[k + 1].energy);
    if (peak) peaks.push_back(spectrum[k]);
  }
  std::sort(peaks.begin(), peaks.end(), [](const ToneBurst& u, const ToneBurst& v) { return u.energy > v.energy; });
  if (peaks.size() > kPeaks) peaks.resize(kPeaks);
  return {peaks, single};
}

// Where a two-tone fit starts: each anchor (the pulse, each peak) with its partner searched
// around it (centres 6 Hz apart, interval anywhere), and every two of the peaks.
std::vector<std::pair<ToneBurst, ToneBurst>> two_tone_starts(const PulsePairFit& fit, const ToneBurst& pulse,
                                                             const std::vector<ToneBurst>& peaks, double span_hz,
                                                             Eigen::Index lo, Eigen::Index hi, BurstLimits around) {
  constexpr double kCentreStepHz = 6.0;
  around.carrier_span_hz = 4.0;  // best_partner's coarse grid: 2 Hz steps, so every 2 Hz is tried
  std::vector<std::pair<ToneBurst, ToneBurst>> starts;
  std::vector<ToneBurst> anchors{pulse};
  anchors.insert(anchors.end(), peaks.begin(), peaks.end());
  for (const ToneBurst& anchor : anchors) {
    ToneBurst partner = anchor;
    partner.energy = 0.0;
    for (double offset = -span_hz; offset <= span_hz + 1e-9; offset += kCentreStepHz) {
      ToneBurst from = anchor;
      from.carrier_hz += offset;
      const ToneBurst candidate = fit.best_partner(anchor, from, lo, hi, around, -1);
      if (candidate.energy > partner.energy) partner = candidate;
    }
    if (partner.energy > 0.0) starts.emplace_back(anchor, partner);
  }
  for (std::size_t u = 0; u < peaks.size(); ++u)
    for (std::size_t v = u + 1; v < peaks.size(); ++v) starts.emplace_back(peaks[u], peaks[v]);
  return starts;
}

// A start refined, then its four edges polished jointly with the carriers refitted at them
// (alternating refinement stalls where one burst's edge covers the other's tail).
std::pair<ToneBurst, ToneBurst> refined_two_tones(const PulsePairFit& fit, const std::pair<ToneBurst, ToneBurst>& start,
                                                  Eigen::Index lo, Eigen::Index hi, const BurstLimits& limits) {
  constexpr int kRounds = 5;
  constexpr Eigen::Index kPolishSlack = 6;
  constexpr int kPolishRounds = 4;
  auto [x, y] = fit.refine(start.first, start.second, lo, hi, limits, kRounds);
  for (int round = 0; round < kPolishRounds && x.energy > 0.0; ++round) {
    const double before = x.energy;
    std::tie(x, y) = fit.polish_edges(x, y, lo, hi, limits, kPolishSlack);
    std::tie(x, y) = fit.refine(x, y, lo, hi, limits, 1, 0);
    if (x.energy <= before * (1.0 + 1e-9)) break;
  }
  return {x, y};
}

// How much noisier two bursts on one carrier are fitted together than each alone: 1 / (1 - the
// share of their lengths they overlap by).
double pair_inflation(const ToneBurst& x, const ToneBurst& y) {
  const auto overlap = static_cast<double>(std::max<Eigen::Index>(0, std::min(x.end, y.end) - std::max(x.begin, y.begin)));
  const double shared = overlap * overlap / (static_cast<double>(x.end - x.begin) * static_cast<double>(y.end - y.begin));
  return shared < 1.0 ? 1.0 / (1.0 - shared) : std::numeric_limits<double>::infinity();
}

// Unsplit pulses in pulse i's frequency cell that overlap it or abut it: what successive
// cancellation carves a pair on one carrier into.
std::vector<std::size_t> cell_mates(const std::vector<Found>& pulses, std::size_t i, double fs) {
  constexpr Eigen::Index kAbut = 2;  // samples
  std::vector<std::size_t> mates;
  for (std::size_t j = 0; j < pulses.size(); ++j) {
    const Found& q = pulses[j];
    if (j == i || q.split || !same_cell(pulses[i], q, fs)) continue;
    if (std::min(q.b, pulses[i].b) + kAbut >= std::max(q.a, pulses[i].a)) mates.push_back(j);
  }
  return mates;
}

// A pulse that one tone leaves energy in holds two transmitters' pulses (docs/estimation/
// avalanche.md, "Two tones that start together" and "Pairs in lockstep"):
//  - two tones a cell or two apart that start together, found as one burst at their mean
//    carrier: the matched window cannot resolve them and every refinement after it is local.
//    Starts: two_tone_starts; tones under 5 Hz apart are the next case's;
//  - two pulses on one carrier with different edges, as a pair in lockstep gives at every pulse:
//    one burst on their union or the pieces successive cancellation carved it into. Start: the
//    best split of the union over every interior edge (PulsePairFit::best_spanning_pair).
// The screens: one tone at the pulse's carrier leaves energy on its interval and its same-cell
// mates' (leaves_energy); or, for a same-carrier pair only, a pulse on its carrier outlasts it
// (outlasting_span: the union is then the span searched). Every start is refined and polished;
// the best is kept when it captures more than the best single burst by the detection threshold
// plus kModelFloor, each of its bursts is a whole pulse (the matched window long, unless the
// window cuts it), and a same-carrier pair overlaps by less than kMaxPairInflation. A tone within
// a cell of another pulse it overlaps is that pulse's leakage, not a new tone. A pulse outlasted
// by another on its carrier and not split is flagged blended: its field is a mixture.
void split_two_burst_pulses(std::vector<Found>& pulses, const Samples& original, const BasebandWindow& w,
                           const PulseDetectorConfig& c, double threshold) {
  if (c.two_tone_span_hz <= 0.0 && !c.same_carrier_pairs) return;
  constexpr double kMinSeparationHz = 5.0;
  const double fs = w.sample_rate_hz;
  const Eigen::Index n = w.size();
  const auto matched = static_cast<Eigen::Index>(std::lround(c.min_on_time_s * fs));
  const BurstLimits limits = burst_limits(c, fs, 2.0);  // refinement around each start: the 2 Hz grid's gaps
  const Eigen::Index margin = limits.max_length / 2;
  auto whole = [&](const ToneBurst& b) { return whole_pulse(b, matched, n); };
  const std::size_t found = pulses.size();
  for (std::size_t i = 0; i < found; ++i) {
    const Found p = pulses[i];
    if (p.split) continue;
    const std::vector<std::size_t> mates = cell_mates(pulses, i, fs);
    std::vector<std::size_t> members{i};
    members.insert(members.end(), mates.begin(), mates.end());
    Found span = p;
    for (std::size_t m : mates) {
      span.a = std::min(span.a, pulses[m].a);
      span.b = std::max(span.b, pulses[m].b);
    }
    const Samples z = without_others(original, w, pulses, members);
    const OneTone one = one_tone_fit(z, w, span);
    const Eigen::Index lo = std::max<Eigen::Index>(0, span.a - margin), hi = std::min(n, span.b + margin);
    const auto outlasting =
        c.same_carrier_pairs ? outlasting_span(z, w, span, lo, hi, one.captured, threshold) : std::nullopt;
    const bool interior = leaves_energy(one, span, threshold);
    if (!interior && !outlasting) continue;
    if (outlasting) std::tie(span.a, span.b) = *outlasting;
    const PulsePairFit fit(z, w);
    auto [peaks, single] = single_burst_peaks(fit, p.f, c.two_tone_span_hz, lo, hi, limits);
    auto leaks = [&](const ToneBurst& b) {
      const Found f{b.carrier_hz, b.begin, b.end, 0.0};
      for (std::size_t j = 0; j < pulses.size(); ++j) {
        const Found& q = pulses[j];
        if (std::find(members.begin(), members.end(), j) == members.end() && std::min(q.b, f.b) > std::max(q.a, f.a) &&
            same_cell(q, f, fs))
          return true;
      }
      return false;
    };
    ToneBurst x, y;
    auto consider = [&](const std::pair<ToneBurst, ToneBurst>& start, bool same_carrier) {
      const auto [cx, cy] = refined_two_tones(fit, start, lo, hi, limits);
      if (cx.energy <= x.energy || !whole(cx) || !whole(cy) || leaks(cx) || leaks(cy)) return;
      if (!same_carrier && std::fabs(cx.carrier_hz - cy.carrier_hz) < kMinSeparationHz) return;
      if (same_carrier && pair_inflation(cx, cy) > kMaxPairInflation) return;
      x = cx;
      y = cy;
    };
    if (interior && c.two_tone_span_hz > 0.0)  // two tones leave energy inside; a pulse outlasting it is a pair's
      for (const auto& start : two_tone_starts(fit, {p.f, p.a, p.b, 0.0}, peaks, c.two_tone_span_hz, lo, hi, limits))
        consider(start, false);
    if (c.same_carrier_pairs) {
      const auto start = fit.best_spanning_pair(span.a, span.b, p.f, limits);
      if (start.first.energy > 0.0) consider(start, true);
    }
    if (x.energy > 0.0) single = std::max(single, best_single_at(fit, {x.carrier_hz, y.carrier_hz}, lo, hi, limits));
    if (x.energy <= 0.0 || !beats_one_burst(x.energy, single, threshold)) {
      // Outlasted by a pulse on its carrier that no pair separates: its field is a mixture.
      if (outlasting)
        for (std::size_t m : members) pulses[m].blended = true;
      continue;
    }
    pulses[i] = {x.carrier_hz, x.begin, x.end, p.t, false, true};
    if (mates.empty()) {
      pulses.push_back({y.carrier_hz, y.begin, y.end, 0.0, false, true});
      continue;
    }
    pulses[mates.front()] = {y.carrier_hz, y.begin, y.end, pulses[mates.front()].t, false, true};
    for (std::size_t k = 1; k < mates.size(); ++k) pulses[mates[k]].blended = true;  // the pair explains it
  }
}

// Successive cancellation of a same-carrier pair leaves, where the pair's sum changes amplitude
// at an edge, energy a cell or two off their carrier; found first, that energy becomes pulses of
// its own, and with them cancelled the pulse looks like one tone (bench `lockstep-pair`: a pair
// 1.2 Hz apart found as one burst plus bursts 10 and 14 Hz off, all mixtures). A pulse with weaker
// pulses overlapping it within near_carrier_cells of its carrier is screened again with those
// left in: if one tone leaves energy, it is refitted as a same-carrier pair
// (PulsePairFit::best_spanning_pair), and kept only when the pair beats one burst as above AND
// explains every one of those neighbours (none above the threshold in what the pair leaves): a
// real transmitter there is never traded for the pair.
void absorb_pair_sidebands(std::vector<Found>& pulses, const Samples& original, const BasebandWindow& w,
                           const PulseDetectorConfig& c, double threshold) {
  if (!c.same_carrier_pairs) return;
  const double fs = w.sample_rate_hz;
  const Eigen::Index n = w.size();
  const auto matched = static_cast<Eigen::Index>(std::lround(c.min_on_time_s * fs));
  const BurstLimits limits = burst_limits(c, fs, 2.0);
  const Eigen::Index margin = limits.max_length / 2;
  auto whole = [&](const ToneBurst& b) { return whole_pulse(b, matched, n); };
  std::vector<bool> absorbed(pulses.size(), false);
  const std::size_t found = pulses.size();
  for (std::size_t i = 0; i < found; ++i) {
    const Found p = pulses[i];
    if (p.split || absorbed[i]) continue;
    std::vector<std::size_t> near;
    for (std::size_t j = 0; j < found; ++j) {
      const Found& q = pulses[j];
      const Eigen::Index overlap = std::min(q.b, p.b) - std::max(q.a, p.a);
      if (j == i || q.split || absorbed[j] || overlap <= 0 || q.t >= p.t) continue;
      if (std::fabs(q.f - p.f) < c.near_carrier_cells * fs / static_cast<double>(overlap)) near.push_back(j);
    }
    if (near.empty()) continue;
    std::vector<std::size_t> members{i};
    members.insert(members.end(), near.begin(), near.end());
    const Samples z = without_others(original, w, pulses, members);
    if (!leaves_energy(one_tone_fit(z, w, p), p, threshold)) continue;
    const PulsePairFit fit(z, w);
    const Eigen::Index lo = std::max<Eigen::Index>(0, p.a - margin), hi = std::min(n, p.b + margin);
    const auto start = fit.best_spanning_pair(p.a, p.b, p.f, limits);
    if (start.first.energy <= 0.0) continue;
    const auto [x, y] = refined_two_tones(fit, start, lo, hi, limits);
    if (x.energy <= 0.0 || !whole(x) || !whole(y) || pair_inflation(x, y) > kMaxPairInflation) continue;
    if (!beats_one_burst(x.energy, best_single_at(fit, {p.f, x.carrier_hz, y.carrier_hz}, lo, hi, limits), threshold))
      continue;
    const Samples left = residual_of(z, w, {{x.carrier_hz, x.begin, x.end, 0.0}, {y.carrier_hz, y.begin, y.end, 0.0}});
    const bool explained = std::all_of(near.begin(), near.end(), [&](std::size_t j) {
      return statistic(demodulated_prefix(left, w, pulses[j].f), pulses[j].a, pulses[j].b) < threshold;
    });
    if (!explained) continue;
    pulses[i] = {x.carrier_hz, x.begin, x.end, p.t, false, true};
    pulses.push_back({y.carrier_hz, y.begin, y.end, 0.0, false, true});
    for (std::size_t j : near) absorbed[j] = true;
  }
  std::vector<Found> kept;
  for (std::size_t j = 0; j < pulses.size(); ++j)
    if (j >= absorbed.size() || !absorbed[j]) kept.push_back(pulses[j]);
  pulses = std::move(kept);
}

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
    if (cand.b - cand.a < fragment) {  // no interval left to refine (a burst at the window's edge)
      if (++current == bands.size()) break;
      continue;
    }
    // What remains of a pulse already found (its carrier or edges a fraction off) is not a new one.
    // Nor is a burst overlapping a pulse within one frequency cell of their overlap (not
    // resolvable), nor a much weaker one: what cancelling a strong pulse whose carrier or edges
    // were estimated a fraction off leaves (residual_bound).
    // Within a few cells of any pulse's carrier, the residual of a pair taken for one pulse
    // (two carriers within a cell) may be there: only the flat bound holds.
    const double cell_hz = fs / static_cast<double>(cand.b - cand.a);
    const bool near_a_carrier = std::any_of(pulses.begin(), pulses.end(), [&](const Found& p) {
      return std::fabs(p.f - cand.f) < c.near_carrier_cells * cell_hz;
    });
    bool residual = false;
    for (Found& p : pulses) {
      const auto overlap = std::min(cand.b, p.b) - std::max(cand.a, p.a);
      if (overlap <= 0) continue;
      const double resolution_hz = fs / static_cast<double>(overlap);  // one cell of the overlap
      const double df = std::fabs(p.f - cand.f);
      const bool unresolved = df < std::max(3.0, resolution_hz);
      if (unresolved && cand.t >= c.blend_ratio * p.t) p.blended = true;
      const double bound = near_a_carrier ? c.sidelobe_ratio * p.t : residual_bound(p, cand.f, cand.a, cand.b, overlap, c, fs);
      if (unresolved || cand.t < bound) residual = true;
    }
    std::vector<Found> fitted = pulses;
    fitted.push_back({cand.f, cand.a, cand.b, cand.t, false});
    if (!residual) pulses = fitted;
    // Cancel every pulse found so far from the original by a joint fit (a pulse fitted alone
    // under another's overlap carries its leakage, and the residual would hold ghosts).
    whitened = residual_of(original, w, fitted);
  }
  if (pulses.empty()) return found;
  // The two-burst refit first: it searches a same-carrier pair's every edge, where the pair
  // resolution that follows (for what is still blended) refines locally from the pieces.
  split_two_burst_pulses(pulses, original, w, c, bands.front().threshold);
  absorb_pair_sidebands(pulses, original, w, c, bands.front().threshold);
  resolve_same_carrier_pairs(pulses, original, w, c, bands.front().threshold);

  // Joint least squares on the original samples: columns = each pulse's carrier on its interval.
  const auto m = static_cast<Eigen::Index>(pulses.size());
  const Eigen::MatrixXcd design = design_matrix(pulses, w);
  const Eigen::MatrixXcd gram = design.adjoint() * design;
  const Eigen::MatrixXcd gram_inv = gram.inverse();
  const Eigen::MatrixXcd coeffs = gram_inv * (design.adjoint() * original.transpose());  // m x 3 (whitened)
  for (Eigen::Index j = 0; j < m; ++j) {
    DetectedPulse d;
    d.start_s = w.time(pulses[j].a);
    d.end_s = w.time(pulses[j].b);
    d.carrier_offset_hz = pulses[j].f;
    d.statistic = pulses[j].t;
    if (pulses[j].split) {  // its own energy in the joint fit (whitened amplitude^2 x length)
      d.statistic = 0.0;
      for (int a = 0; a < 3; ++a) d.statistic += std::norm(coeffs(j, a)) * static_cast<double>(pulses[j].b - pulses[j].a);
    }
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
