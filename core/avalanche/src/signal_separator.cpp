#include "sarloc/core/avalanche/signal_separator.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"

namespace sarloc::avalanche {
namespace {

void check(const char* key, double v, double lo, double hi) {
  if (!std::isfinite(v) || v < lo || v > hi) {
    std::ostringstream os;
    os << "separator." << key << " = " << v << ": must be in [" << lo << ", " << hi << "]";
    throw ConfigError(os.str());
  }
}

}  // namespace

const char* to_string(SignalEvent event) {
  switch (event) {
    case SignalEvent::kNone: return "none";
    case SignalEvent::kNew: return "new";
    case SignalEvent::kReacquired: return "reacquired";
    case SignalEvent::kSeparated: return "separated";
  }
  return "none";
}

const char* to_string(TrackChange change) {
  switch (change) {
    case TrackChange::kNew: return "new";
    case TrackChange::kLost: return "lost";
    case TrackChange::kMerged: return "merged";
    case TrackChange::kReacquired: return "reacquired";
    case TrackChange::kSeparated: return "separated";
    case TrackChange::kForgotten: return "forgotten";
  }
  return "new";
}

void SeparatorConfig::validate() const {
  check("detect_snr", detect_snr, 1.0, 20.0);
  check("carrier_match_hz", carrier_match_hz, 0.1, 40.0);
  check("carrier_match_weak_hz", carrier_match_weak_hz, 0.0, 1000.0);
  check("timing_tolerance_s", timing_tolerance_s, 0.002, 0.2);
  check("timing_drift_s", timing_drift_s, 0.0, 0.05);
  check("timing_tolerance_weak_s", timing_tolerance_weak_s, 0.0, 100.0);
  check("max_variance_inflation", max_variance_inflation, 1.0, 100.0);
  check("lost_after_s", lost_after_s, 1.0, 600.0);
  check("forget_after_s", forget_after_s, lost_after_s, 86400.0);
  check("log_likelihood_margin", log_likelihood_margin, 0.0, 1000.0);
  check("max_signals", max_signals, 1, 64);
  check("detector.min_on_time_s", detector.min_on_time_s, 0.01, 1.0);
  check("detector.max_on_time_s", detector.max_on_time_s, detector.min_on_time_s, 1.0);
  check("detector.search_band_hz", detector.search_band_hz, 1.0, 1000.0);
  check("detector.coarse_step_hz", detector.coarse_step_hz, 0.1, 20.0);
  check("detector.fine_step_hz", detector.fine_step_hz, 0.001, detector.coarse_step_hz);
  check("detector.false_alarms_per_window", detector.false_alarms_per_window, 1e-9, 0.5);
  check("detector.max_pulses", detector.max_pulses, 1, 32);
}

SignalSeparator::SignalSeparator(SeparatorConfig config) : config_((config.validate(), std::move(config))) {}

std::optional<double> SignalSeparator::carrier_of(std::uint32_t signal_id) const {
  for (const auto& t : tracks_)
    if (t.id == signal_id) return t.carrier_hz;
  return std::nullopt;
}

bool SignalSeparator::timing_fits(const Track& t, const DetectedPulse& p) const {
  if (!t.last_start_s || !t.on_time_s) return true;  // timing not learnt yet: the carrier decides
  // Edges of a weak pulse are found less precisely: the tolerance grows as 1 / statistic.
  const double tol_base = config_.timing_tolerance_s + config_.timing_tolerance_weak_s / std::max(p.statistic, 1.0);
  // A pulse longer than the track's on-time holds another pulse on the same carrier.
  if (!p.truncated() && p.end_s - p.start_s > *t.on_time_s + 2.0 * tol_base) return false;
  if (!t.period_s) return true;
  const double period = *t.period_s;
  const double reference = p.truncated_start ? p.end_s - *t.on_time_s : p.start_s;
  const double k = std::round((reference - *t.last_start_s) / period);
  const double predicted_start = *t.last_start_s + k * period;
  const double tol = tol_base + config_.timing_drift_s * std::fabs(k);
  if (!p.truncated_start && std::fabs(p.start_s - predicted_start) > tol) return false;
  if (!p.truncated_end && std::fabs(p.end_s - (predicted_start + *t.on_time_s)) > tol) return false;
  return true;
}

void SignalSeparator::learn(Track& t, const DetectedPulse& p) {
  const double w = std::max(p.statistic, 1.0);
  t.carrier_hz = (t.carrier_hz * t.carrier_weight + p.carrier_offset_hz * w) / (t.carrier_weight + w);
  t.carrier_weight = std::min(t.carrier_weight + w, 1e4);  // keeps following a slow drift
  t.last_heard_s = p.end_s;
  if (p.truncated()) return;
  const double on = p.end_s - p.start_s;
  t.on_time_s = t.on_time_s ? 0.8 * *t.on_time_s + 0.2 * on : on;
  if (t.last_start_s) {
    const double gap = p.start_s - *t.last_start_s;
    if (t.period_s) {
      const double k = std::round(gap / *t.period_s);
      if (k >= 1.0 && std::fabs(gap - k * *t.period_s) <= config_.timing_tolerance_s + config_.timing_drift_s * k)
        *t.period_s += 0.3 * (gap / k - *t.period_s);
    } else if (gap >= 0.65 && gap <= 1.35) {
      t.period_s = gap;  // two consecutive clean pulses (a standard period is 0.7-1.3 s)
    }
  }
  t.last_start_s = p.start_s;
}

SeparatedSample SignalSeparator::sample_of(const DetectedPulse& p, std::uint32_t id, std::size_t index) const {
  SeparatedSample s;
  s.signal_id = id;
  s.pulse = index;
  Vec3c valid = Vec3c::Zero();
  for (int a = 0; a < 3; ++a) {
    if (std::abs(p.amplitude[a]) >= config_.detect_snr * p.amplitude_noise[a]) {
      s.valid_axes = static_cast<std::uint8_t>(s.valid_axes | (1U << a));
      valid[a] = p.amplitude[a];
    }
  }
  s.field = principal_axis(valid);
  s.noise = p.amplitude_noise;
  return s;
}

SeparationReport SignalSeparator::process(const BasebandWindow& window) {
  SeparationReport r;
  std::vector<double> carriers;
  for (const auto& t : tracks_) carriers.push_back(t.carrier_hz);
  r.pulses = detect_pulses(window, config_.detector, carriers);
  r.attributed.assign(r.pulses.size(), std::nullopt);
  const double window_end = window.time(window.size());
  // Strongest first: a weak pulse never takes a track from a strong one.
  std::vector<std::size_t> order(r.pulses.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return r.pulses[a].statistic > r.pulses[b].statistic; });
  auto merge = [&](std::vector<Track*>& tracks, double time) {
    for (Track* t : tracks) {
      if (!t->merged) r.events.push_back({t->id, TrackChange::kMerged, time});
      t->merged = true;
    }
  };
  for (std::size_t i : order) {
    const DetectedPulse& p = r.pulses[i];
    std::vector<Track*> carrier_matches, candidates;
    for (auto& t : tracks_) {
      // A weak pulse's carrier (and a young track's) is known less precisely: ~1 / sqrt(statistic).
      const double tolerance = config_.carrier_match_hz +
                               config_.carrier_match_weak_hz / std::sqrt(std::max(1.0, std::min(p.statistic, t.carrier_weight)));
      if (std::fabs(t.carrier_hz - p.carrier_offset_hz) > tolerance) continue;
      carrier_matches.push_back(&t);
      if (timing_fits(t, p)) candidates.push_back(&t);
    }
    if (p.variance_inflation > config_.max_variance_inflation) {
      merge(carrier_matches, p.start_s);  // overlapping on the same carrier: not separable
      continue;
    }
    Track* chosen = nullptr;
    if (candidates.size() == 1) {
      chosen = candidates.front();
    } else if (candidates.size() > 1) {
      // Carrier and timing both fit several tracks: only each track's filter can tell.
      if (consistency_) {
        const SeparatedSample probe = sample_of(p, 0, i);
        std::vector<std::pair<double, Track*>> scored;
        for (Track* t : candidates)
          if (auto ll = consistency_(t->id, probe.field, probe.noise, probe.valid_axes)) scored.emplace_back(*ll, t);
        std::sort(scored.begin(), scored.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
        if (scored.size() == candidates.size() && scored[0].first - scored[1].first > config_.log_likelihood_margin)
          chosen = scored[0].second;
      }
      if (chosen == nullptr) {
        merge(candidates, p.start_s);
        continue;
      }
    } else if (carrier_matches.empty() && !p.truncated() && tracks_.size() < config_.max_signals) {
      Track t;
      t.id = next_id_++;
      t.carrier_hz = p.carrier_offset_hz;
      tracks_.reserve(config_.max_signals);
      tracks_.push_back(t);
      chosen = &tracks_.back();
    }
    if (chosen == nullptr) continue;  // on a known carrier at the wrong time, or no room
    // One pulse per track and window unless they are a period apart (a 0.7 s period can give two).
    const bool clash = std::any_of(r.attributed.begin(), r.attributed.end(), [&](const auto& a) {
      if (!a || *a != chosen->id) return false;
      const auto j = static_cast<std::size_t>(&a - r.attributed.data());
      return std::fabs(r.pulses[j].start_s - p.start_s) < 0.5;
    });
    if (clash) continue;
    r.attributed[i] = chosen->id;
    if (chosen->lost) {
      chosen->lost = false;
      chosen->pending = SignalEvent::kReacquired;
      r.events.push_back({chosen->id, TrackChange::kReacquired, p.start_s});
    }
    if (chosen->merged) {
      chosen->merged = false;
      if (chosen->pending == SignalEvent::kNone) chosen->pending = SignalEvent::kSeparated;
      r.events.push_back({chosen->id, TrackChange::kSeparated, p.start_s});
    }
    const bool confirmed = chosen->period_s.has_value();
    learn(*chosen, p);
    if (!confirmed && chosen->period_s) r.events.push_back({chosen->id, TrackChange::kNew, p.start_s});
  }
  for (std::size_t i = 0; i < r.pulses.size(); ++i)
    if (!r.attributed[i]) ++r.unattributed;

  // One sample per signal: its strongest attributed pulse of the window. A track is confirmed
  // by its second pulse a period later: a one-off burst (a residual, a false alarm) never
  // becomes a signal.
  for (auto& t : tracks_) {
    if (!t.period_s) continue;
    std::optional<std::size_t> best;
    for (std::size_t i = 0; i < r.pulses.size(); ++i)
      if (r.attributed[i] == t.id && (!best || r.pulses[i].statistic > r.pulses[*best].statistic)) best = i;
    if (!best) continue;
    SeparatedSample s = sample_of(r.pulses[*best], t.id, *best);
    if (s.valid_axes == 0) continue;
    s.event = t.pending;
    t.pending = SignalEvent::kNone;
    r.samples.push_back(s);
  }
  // Silence: lost, then forgotten.
  for (auto& t : tracks_) {
    if (t.period_s && !t.lost && window_end - t.last_heard_s > config_.lost_after_s) {
      t.lost = true;
      r.events.push_back({t.id, TrackChange::kLost, window_end});
    }
  }
  for (auto it = tracks_.begin(); it != tracks_.end();) {
    if (!it->period_s && window_end - it->last_heard_s > 2.0 * 1.35) {
      it = tracks_.erase(it);  // never confirmed: dropped quietly
    } else if (window_end - it->last_heard_s > config_.forget_after_s) {
      r.events.push_back({it->id, TrackChange::kForgotten, window_end});
      it = tracks_.erase(it);
    } else {
      ++it;
    }
  }
  return r;
}

}  // namespace sarloc::avalanche
