#include "sarloc/core/avalanche/signal_separator.hpp"

#include <algorithm>
#include <bitset>
#include <cmath>
#include <numeric>
#include <sstream>
#include <utility>

#include "sarloc/core/avalanche/receiver_model.hpp"
#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::avalanche {
namespace {

void check(const char* key, double v, double lo, double hi) {
  require(std::isfinite(v) && v >= lo && v <= hi, std::string("separator.") + key, v,
          "must be in [" + config_value(lo) + ", " + config_value(hi) + "]");
}

}  // namespace

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
  check("calibration_relative", calibration_relative, 0.0, 0.5);
  check("carrier_match_hz", carrier_match_hz, 0.1, 40.0);
  check("carrier_match_weak_hz", carrier_match_weak_hz, 0.0, 1000.0);
  check("edge_sigma_s", edge_sigma_s, 1e-4, 0.1);
  check("edge_sigma_weak_s", edge_sigma_weak_s, 0.0, 100.0);
  check("timing_gate_sigmas", timing_gate_sigmas, 1.0, 10.0);
  check("on_time_tolerance_s", on_time_tolerance_s, 0.0, 0.5);
  check("timing.min_period_s", timing.min_period_s, 0.1, 5.0);
  check("timing.max_period_s", timing.max_period_s, timing.min_period_s, 5.0);
  check("timing.clock_jitter_s", timing.clock_jitter_s, 0.0, 0.1);
  check("timing.reanchor_period_sigma_s", timing.reanchor_period_sigma_s, 0.0, 0.5);
  check("max_variance_inflation", max_variance_inflation, 1.0, 100.0);
  check("channel_ellipticity", channel_ellipticity, 0.0, 1.0);
  check("wavenumber_rad_per_m", wavenumber_rad_per_m, 0.0, 1.0);
  check("moment_max_A_m2", moment_max_A_m2, 1e-6, 10.0);
  check("lost_after_s", lost_after_s, 1.0, 600.0);
  check("forget_after_s", forget_after_s, lost_after_s, 86400.0);
  check("log_likelihood_margin", log_likelihood_margin, 0.0, 1000.0);
  check("reanchor_gate_probability", reanchor_gate_probability, 0.5, 1.0 - 1e-12);
  check("max_signals", max_signals, 1, 64);
  check("shadow_confirm_pulses", shadow_confirm_pulses, 2, 20);
  check("detector.min_on_time_s", detector.min_on_time_s, 0.01, 1.0);
  check("detector.max_on_time_s", detector.max_on_time_s, detector.min_on_time_s, 1.0);
  check("detector.search_band_hz", detector.search_band_hz, 1.0, 1000.0);
  check("detector.coarse_step_hz", detector.coarse_step_hz, 0.1, 20.0);
  check("detector.fine_step_hz", detector.fine_step_hz, 0.001, detector.coarse_step_hz);
  check("detector.false_alarms_per_window", detector.false_alarms_per_window, 1e-9, 0.5);
  check("detector.max_pulses", detector.max_pulses, 1, 32);
  check("detector.sidelobe_ratio", detector.sidelobe_ratio, detector.far_sidelobe_ratio, 1.0);
  check("detector.far_sidelobe_ratio", detector.far_sidelobe_ratio, 1e-9, 1.0);
  check("detector.near_carrier_cells", detector.near_carrier_cells, 0.0, 100.0);
  check("detector.blend_ratio", detector.blend_ratio, detector.sidelobe_ratio, 1.0);
  check("detector.two_tone_span_hz", detector.two_tone_span_hz, 0.0, 100.0);
}

SignalSeparator::SignalSeparator(SeparatorConfig config) : config_((config.validate(), std::move(config))) {
  tracks_.reserve(config_.max_signals);  // process() holds pointers into it while adding a track
  for (int axes = 1; axes <= 3; ++axes) reanchor_gate_[axes] = chi_square_quantile(config_.reanchor_gate_probability, axes);
}

const SignalSeparator::Track* SignalSeparator::find(std::uint32_t id) const {
  for (const auto& t : tracks_)
    if (t.id == id) return &t;
  return nullptr;
}

SignalSeparator::Track* SignalSeparator::find(std::uint32_t id) {
  return const_cast<Track*>(std::as_const(*this).find(id));
}

std::optional<double> SignalSeparator::carrier_of(std::uint32_t signal_id) const {
  for (const auto& t : tracks_)
    if (t.id == signal_id) return t.carrier_hz;
  return std::nullopt;
}

std::optional<responder::TransmitterSignature> SignalSeparator::signature_of(std::uint32_t signal_id) const {
  const Track* t = find(signal_id);
  if (t == nullptr) return std::nullopt;
  responder::TransmitterSignature s;
  s.carrier_offset_hz = t->carrier_hz;
  if (t->carrier_pulses >= 2) {
    // The fine grid's step is the floor: pulses that agree exactly still say no more than it.
    const double spread = std::sqrt(t->carrier_pulse_m2 / (t->carrier_pulses - 1));
    s.carrier_sigma_hz = std::max(spread, config_.detector.fine_step_hz) / std::sqrt(static_cast<double>(t->carrier_pulses));
  }
  if (t->timing.has_period() && !t->retimed) {
    s.period_s = t->timing.period_s();
    s.period_sigma_s = t->timing.period_sigma_s();
  }
  return s;
}

double SignalSeparator::edge_sigma(const DetectedPulse& p) const {
  return config_.edge_sigma_s + config_.edge_sigma_weak_s / std::max(p.statistic, 1.0);
}

std::optional<std::pair<double, double>> SignalSeparator::start_of(const Track& t, const DetectedPulse& p) const {
  if (!p.truncated_start) return std::make_pair(p.start_s, edge_sigma(p));
  if (p.truncated_end || !t.on_time_s) return std::nullopt;
  return std::make_pair(p.end_s - *t.on_time_s, 2.0 * edge_sigma(p));  // end and learnt on-time
}

bool SignalSeparator::timing_fits(const Track& t, const DetectedPulse& p) const {
  if (!t.on_time_s) return true;  // timing not learnt yet: the carrier decides
  // A pulse longer than the track's on-time holds another pulse on the same carrier.
  const double edges = std::sqrt(2.0) * edge_sigma(p);
  if (!p.truncated() &&
      p.end_s - p.start_s > *t.on_time_s + config_.timing_gate_sigmas * edges + config_.on_time_tolerance_s)
    return false;
  const auto start = start_of(t, p);
  if (!start) return true;
  const auto fit = t.timing.fit(start->first, start->second);
  return !fit || fit->sigmas() <= config_.timing_gate_sigmas;
}

bool SignalSeparator::on_carrier(const Track& t, const DetectedPulse& p) const {
  // A weak pulse's carrier (and a young track's) is known less precisely: ~1 / sqrt(statistic).
  const double tolerance = config_.carrier_match_hz +
                           config_.carrier_match_weak_hz / std::sqrt(std::max(1.0, std::min(p.statistic, t.carrier_weight)));
  return std::fabs(t.carrier_hz - p.carrier_offset_hz) <= tolerance;
}

std::optional<std::pair<double, double>> SignalSeparator::whole_pulse_due(const Track& t, double w0, double w1) const {
  if (!t.timing.has_period() || !t.on_time_s) return std::nullopt;
  const double gate = config_.timing_gate_sigmas;
  const double on = *t.on_time_s + config_.on_time_tolerance_s;
  const double period = t.timing.period_s();
  // Any phase: a window longer than a period plus an on-time holds a whole pulse.
  if (period + gate * t.timing.period_sigma_s() + on <= w1 - w0) return std::make_pair(w0, w1);
  if (!t.timing.has_phase()) return std::nullopt;
  for (double near = w0; near < w1 + period; near += 0.5 * period) {
    const auto fit = t.timing.fit(near, 0.0);
    if (!fit) return std::nullopt;
    const double start = near - fit->innovation_s;
    const double spread = gate * std::sqrt(fit->variance_s2);
    if (start - spread >= w0 && start + on + spread <= w1) return std::make_pair(start - spread, start + on + spread);
  }
  return std::nullopt;
}

SignalSeparator::Track& SignalSeparator::start_track(const DetectedPulse& p, const std::vector<Track*>& carrier_matches) {
  Track t;
  t.id = next_id_++;
  t.carrier_hz = p.carrier_offset_hz;
  t.timing = PulseTiming(config_.timing);
  t.shadow = !carrier_matches.empty();
  for (const Track* m : carrier_matches) t.mates_at_start.emplace_back(m->id, m->heard);
  tracks_.push_back(t);  // capacity reserved: pointers into tracks_ stay valid
  return tracks_.back();
}

void SignalSeparator::learn(Track& t, const DetectedPulse& p) {
  // Weighted by statistic, but no pulse counts for more than a tenth of the track's history: at
  // close range (statistic 1e9 and more) one burst measured off (a residual next to a strong
  // pulse) otherwise moved the track's carrier onto itself, and the transmitter's own pulses
  // no longer matched it (seen: one transmitter tracked as two signals, found twice).
  const double w = std::clamp(p.statistic, 1.0, 1e3);
  t.carrier_hz = (t.carrier_hz * t.carrier_weight + p.carrier_offset_hz * w) / (t.carrier_weight + w);
  t.carrier_weight = std::min(t.carrier_weight + w, 1e4);  // keeps following a slow drift
  ++t.carrier_pulses;
  const double delta = p.carrier_offset_hz - t.carrier_pulse_mean;
  t.carrier_pulse_mean += delta / t.carrier_pulses;
  t.carrier_pulse_m2 += delta * (p.carrier_offset_hz - t.carrier_pulse_mean);
  t.last_heard_s = p.end_s;
  ++t.heard;
  if (!p.truncated()) {
    const double on = p.end_s - p.start_s;
    t.on_time_s = (t.on_time_s.value_or(0.0) * t.on_time_weight + on * w) / (t.on_time_weight + w);  // same cap
    t.on_time_weight = std::min(t.on_time_weight + w, 1e4);
  }
  if (const auto start = start_of(t, p)) t.timing.update(start->first, start->second);
  if (t.period_before_reanchor && t.timing.has_period()) {
    // Seen live (four within 5 m): a signal of C reanchored on another transmitter's pulses,
    // its period 1.00495 -> 1.00002 s with a sigma of 0.3 ms, stated as C's.
    const auto [before, before_sigma] = *t.period_before_reanchor;
    const double sigma = t.timing.period_sigma_s();
    if (std::fabs(t.timing.period_s() - before) > 4.0 * std::hypot(before_sigma, sigma)) {
      t.retimed = true;
      t.period_before_reanchor.reset();
    } else if (sigma <= before_sigma) {
      t.period_before_reanchor.reset();  // its own timing again, as well known as before
    }
  }
}

bool SignalSeparator::clear_of_timing(const Track& t, const DetectedPulse& p) const {
  // Only a mate that knows its timing and was heard on it within the last period and a half
  // can say the pulse is not its own (one silent longer may have drifted off its timing).
  if (!t.timing.has_period() || t.lost || !t.on_time_s) return false;
  if (p.start_s - t.last_heard_s > 1.5 * t.timing.period_s()) return false;
  const auto start = start_of(t, p);
  if (!start) return false;
  const auto fit = t.timing.fit(start->first, start->second);
  if (!fit) return false;
  // The pulse must not touch the mate's predicted pulse (its learnt on-time, widened by the
  // gate): a piece of the mate's own pulse repeats with it and would look interleaved.
  const double margin = config_.timing_gate_sigmas * std::sqrt(fit->variance_s2) + config_.on_time_tolerance_s;
  const bool after = fit->innovation_s > *t.on_time_s + margin;
  const bool before = fit->innovation_s + (p.end_s - p.start_s) < -margin;
  return after || before;
}

bool SignalSeparator::heard_at_once(const Track& t, const DetectedPulse& p, const SeparationReport& r) const {
  for (std::size_t j = 0; j < r.pulses.size(); ++j) {
    if (r.attributed[j] != t.id) continue;
    const DetectedPulse& q = r.pulses[j];
    if (q.truncated() || q.end_s - q.start_s < config_.detector.min_on_time_s) continue;
    const double overlap = std::min(p.end_s, q.end_s) - std::max(p.start_s, q.start_s);
    if (overlap < 0.5 * config_.detector.min_on_time_s) continue;
    // Distinct edges: two pieces of one burst would share at least one.
    const double gate = config_.timing_gate_sigmas * std::hypot(edge_sigma(p), edge_sigma(q)) + config_.on_time_tolerance_s;
    if (std::fabs(p.start_s - q.start_s) > gate && std::fabs(p.end_s - q.end_s) > gate) return true;
  }
  return false;
}

bool SignalSeparator::another_transmitter(const std::vector<Track*>& mates, const DetectedPulse& p,
                                          const SeparationReport& r) const {
  return std::all_of(mates.begin(), mates.end(),
                     [&](const Track* t) { return clear_of_timing(*t, p) || heard_at_once(*t, p, r); });
}

SignalSeparator::Track* SignalSeparator::lost_owner(const std::vector<Track*>& matches, const DetectedPulse& p,
                                                    const SeparationReport& r) const {
  // Seen: a deep transmitter 2.2 Hz from a found one lost its track while their pulses overlapped,
  // then pulsed clear of the found one's timing, 70 dB above the noise, for 500 s; with two
  // tracks on the carrier none was re-anchored, and the rescuer stood on it unable to find it.
  std::vector<Track*> lost, others;
  for (Track* t : matches) (t->lost ? lost : others).push_back(t);
  if (lost.empty()) return nullptr;
  // Several lost on the carrier: the timing cannot say which; if all but one are repeats of it,
  // they are one transmitter (original_of_repeats).
  Track* owner = lost.size() == 1 ? lost.front() : original_of_repeats(lost, p);
  if (owner == nullptr || !another_transmitter(others, p, r) || !explains(*owner, p)) return nullptr;
  return owner;
}

bool SignalSeparator::explains(const Track& t, const DetectedPulse& p) const {
  // Seen: a found signal's track, lost for 5 s while the rescuer walked on, was re-anchored on
  // the pulses of an unfound transmitter 2 Hz from it and 2.2 m away; that transmitter's pulses
  // then went to a filter that takes no more samples, and the found one's, unclaimed, started a
  // new signal that was found a second time.
  if (!consistency_) return true;
  const SeparatedSample probe = sample_of(p, 0, 0);
  const auto axes = std::bitset<3>(probe.valid_axes).count();
  if (axes == 0) return true;
  const auto fit = consistency_(t.id, probe.field, probe.noise, probe.valid_axes);
  return !fit || fit->nis <= reanchor_gate_[axes];
}

SignalSeparator::Track* SignalSeparator::chosen_by_filters(const std::vector<Track*>& candidates,
                                                            const DetectedPulse& p) const {
  if (!consistency_) return nullptr;
  const SeparatedSample probe = sample_of(p, 0, 0);
  std::vector<std::pair<double, Track*>> scored;
  for (Track* t : candidates)
    if (auto fit = consistency_(t->id, probe.field, probe.noise, probe.valid_axes)) scored.emplace_back(fit->log_likelihood, t);
  if (scored.size() != candidates.size()) return nullptr;  // a track without a filter yet
  std::sort(scored.begin(), scored.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  return scored[0].first - scored[1].first > config_.log_likelihood_margin ? scored[0].second : nullptr;
}

SignalSeparator::Track* SignalSeparator::original_of_repeats(const std::vector<Track*>& lost, const DetectedPulse& p) const {
  // One transmitter split into two signals (a track started again on it) leaves two tracks on
  // its carrier whose filters both explain its pulses. Both lost while another transmitter's
  // pulses overlapped its own, neither was re-anchored when it was heard clear again, and the
  // rescuer stood over the victim with one sample every 20-50 s (4 victims, seed 9, trial 15).
  // The rescuer's filters, which compare position and moment, name the repeat
  // (FieldFit::repeat_of): the pulse goes to the one track that is no repeat of another.
  // Only for lost tracks, and not by the likelihood margin: tracks of two transmitters in
  // lockstep, whose filters both mixed their pulses, are lost together too, and choosing
  // between them by the margin fed one filter both transmitters (4 victims, seed 11, trial 51:
  // two ghosts, each FOUND between the two victims 1.2 Hz apart).
  if (!consistency_) return nullptr;
  const SeparatedSample probe = sample_of(p, 0, 0);
  Track* original = nullptr;
  for (Track* t : lost) {
    const auto fit = consistency_(t->id, probe.field, probe.noise, probe.valid_axes);
    if (!fit) return nullptr;  // a track without a filter: nothing to compare
    const bool repeat_of_another =
        std::any_of(lost.begin(), lost.end(), [&](const Track* o) { return o != t && o->id == fit->repeat_of; });
    if (repeat_of_another) continue;
    if (original != nullptr) return nullptr;  // two that are no repeat of each other: cannot tell
    original = t;
  }
  return original;
}

bool SignalSeparator::interleaved(const Track& shadow) const {
  if (!shadow.timing.has_period() || shadow.heard < config_.shadow_confirm_pulses) return false;
  return std::any_of(shadow.mates_at_start.begin(), shadow.mates_at_start.end(), [&](const auto& m) {
    const Track* mate = find(m.first);
    return mate != nullptr && !mate->lost && !mate->shadow && mate->heard >= m.second + config_.shadow_confirm_pulses;
  });
}

void SignalSeparator::settle_shadows(SeparationReport& r, double window_end) {
  std::vector<std::uint32_t> retired;
  for (auto& s : tracks_) {
    if (!s.shadow) continue;
    if (interleaved(s)) {
      s.shadow = false;
      s.mates_at_start.clear();
      r.events.push_back({s.id, TrackChange::kNew, window_end});
      continue;
    }
    if (window_end - s.last_heard_s > config_.lost_after_s) {
      retired.push_back(s.id);  // never published: dropped quietly
      continue;
    }
    if (!s.timing.has_period()) continue;
    // Every mate silent while the shadow is heard on its own period: it is the mate, re-timed.
    Track* heir = nullptr;
    bool mate_heard = false;
    for (const auto& m : s.mates_at_start) {
      Track* mate = find(m.first);
      if (mate == nullptr) continue;
      if (!mate->lost) mate_heard = true;
      else if (heir == nullptr || mate->last_heard_s > heir->last_heard_s) heir = mate;
    }
    if (mate_heard) continue;
    if (heir == nullptr) {  // its mates are forgotten: a signal of its own
      s.shadow = false;
      r.events.push_back({s.id, TrackChange::kNew, window_end});
      continue;
    }
    heir->timing = s.timing;
    heir->on_time_s = s.on_time_s;
    heir->on_time_weight = s.on_time_weight;
    heir->last_heard_s = s.last_heard_s;
    heir->lost = false;
    heir->pending = SignalEvent::kReacquired;
    r.events.push_back({heir->id, TrackChange::kReacquired, window_end});
    retired.push_back(s.id);
  }
  tracks_.erase(std::remove_if(tracks_.begin(), tracks_.end(),
                               [&](const Track& t) {
                                 return std::find(retired.begin(), retired.end(), t.id) != retired.end();
                               }),
                tracks_.end());
}

bool SignalSeparator::better_fit_elsewhere(const Track& chosen, const std::vector<Track*>& mates,
                                           const DetectedPulse& p, std::size_t index) const {
  if (!consistency_) return false;
  const SeparatedSample probe = sample_of(p, 0, index);
  if (probe.valid_axes == 0) return false;
  const auto own = consistency_(chosen.id, probe.field, probe.noise, probe.valid_axes);
  if (!own) return false;
  for (const Track* t : mates) {
    if (t == &chosen) continue;
    const auto other = consistency_(t->id, probe.field, probe.noise, probe.valid_axes);
    if (other && other->log_likelihood - own->log_likelihood > config_.log_likelihood_margin) return true;
  }
  return false;
}

bool SignalSeparator::elliptical(const DetectedPulse& p) const {
  const double major = principal_axis(p.amplitude).norm();
  const double bound = config_.channel_ellipticity +
                       single_transmitter_ellipticity(major, config_.wavenumber_rad_per_m, config_.moment_max_A_m2);
  return minor_axis(p.amplitude).norm() > bound * major + 3.0 * p.amplitude_noise.norm();
}

bool SignalSeparator::unseparable(const DetectedPulse& p) const {
  return p.variance_inflation > config_.max_variance_inflation || p.blended || elliptical(p);
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
  s.noise = p.amplitude_noise + Vec3::Constant(config_.calibration_relative * s.field.norm());
  return s;
}

SeparationReport SignalSeparator::process(const BasebandWindow& window) {
  SeparationReport r;
  std::vector<double> carriers;
  for (const auto& t : tracks_) carriers.push_back(t.carrier_hz);
  r.pulses = detect_pulses(window, config_.detector, carriers);
  const double window_end = window.time(window.size());
  // A start found within its own uncertainty of the window's start may be the window's: the
  // pulse may have begun before it (seen: the last 44 ms of a pulse, found 2 ms after the window
  // began, taken for a whole pulse; it started a second track on the transmitter's carrier, and
  // the transmitter's own pulses, claimed by both, were never attributed again, 25 m from it).
  // The end is left as found: a transmitter whose period is close to the window's is cut by
  // every window's end, and only such a pulse's start, which is its own, lets a track begin.
  for (auto& p : r.pulses)
    if (p.start_s - window.t0_s < config_.timing_gate_sigmas * edge_sigma(p)) p.truncated_start = true;
  if (window.lead_s > 0.0) {
    // A window that begins with the end of the previous one: a pulse that ended there was heard
    // then, and one still on at this window's end is heard whole in the next.
    const double heard_before = window.new_from_s() + 0.5 / window.sample_rate_hz;
    r.pulses.erase(std::remove_if(r.pulses.begin(), r.pulses.end(),
                                  [&](const DetectedPulse& p) { return p.end_s <= heard_before || p.truncated_end; }),
                   r.pulses.end());
  }
  r.attributed.assign(r.pulses.size(), std::nullopt);
  // Strongest first: a weak pulse never takes a track from a strong one.
  std::vector<std::size_t> order(r.pulses.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return r.pulses[a].statistic > r.pulses[b].statistic; });
  auto merge = [&](const std::vector<Track*>& tracks, double time) {
    for (Track* t : tracks) {
      if (!t->merged && !t->shadow) r.events.push_back({t->id, TrackChange::kMerged, time});  // shadows are unpublished
      t->merged = true;
    }
  };
  for (std::size_t i : order) {
    const DetectedPulse& p = r.pulses[i];
    std::vector<Track*> carrier_matches, confirmed, tentative;
    for (auto& t : tracks_) {
      if (!on_carrier(t, p)) continue;
      carrier_matches.push_back(&t);
      if (timing_fits(t, p)) (t.timing.has_period() ? confirmed : tentative).push_back(&t);
    }
    if (unseparable(p)) {
      merge(carrier_matches, p.start_s);  // overlapping on the same carrier: not separable
      continue;
    }
    // A confirmed track's timing decides before a tentative one's (which fits anything on its
    // carrier until it knows its period).
    const std::vector<Track*>& candidates = confirmed.empty() ? tentative : confirmed;
    Track* chosen = nullptr;
    if (candidates.size() == 1) {
      chosen = candidates.front();
    } else if (candidates.size() > 1) {
      // Carrier and timing both fit several tracks: only each track's filter can tell.
      chosen = chosen_by_filters(candidates, p);
      if (chosen == nullptr) {
        merge(candidates, p.start_s);
        continue;
      }
    } else if (Track* lost = p.truncated() ? nullptr : lost_owner(carrier_matches, p, r)) {
      chosen = lost;  // unheard a while, its timing drifted: reanchor on this pulse
      if (chosen->timing.has_period() && !chosen->period_before_reanchor)
        chosen->period_before_reanchor = std::make_pair(chosen->timing.period_s(), chosen->timing.period_sigma_s());
      chosen->timing.reanchor();
    } else if (!p.truncated() && tracks_.size() < config_.max_signals) {
      // A lost track whose filter cannot explain the pulse is no mate of it: the filter says it
      // is another transmitter, where the lost track's stale timing can say nothing.
      std::vector<Track*> mates;
      for (Track* t : carrier_matches)
        if (!t->lost || explains(*t, p)) mates.push_back(t);
      if (mates.empty() || another_transmitter(mates, p, r)) chosen = &start_track(p, mates);
    }
    if (chosen == nullptr) continue;  // on a known carrier at the wrong time, or no room
    if (carrier_matches.size() > 1 && better_fit_elsewhere(*chosen, carrier_matches, p, i)) continue;
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
      if (!chosen->shadow) r.events.push_back({chosen->id, TrackChange::kSeparated, p.start_s});
    }
    const bool was_confirmed = chosen->timing.has_period();
    learn(*chosen, p);
    if (!was_confirmed && chosen->timing.has_period() && !chosen->shadow) r.events.push_back({chosen->id, TrackChange::kNew, p.start_s});
  }
  // A clean pulse on a tracked carrier, off its timing, heard at once with that track's own
  // pulse (both resolved, their edges distinct) is another transmitter's: one cannot pulse twice
  // at once. Strongest first above, the mate's pulse may have been attributed after this one.
  // Seen: a weak transmitter 2.2 Hz from a strong one, on its period to 0.01 % and 50 ms ahead,
  // resolved by the detector near the cluster and never tracked, so never searched.
  for (std::size_t i : order) {
    const DetectedPulse& p = r.pulses[i];
    if (r.attributed[i] || p.truncated() || unseparable(p) || tracks_.size() >= config_.max_signals) continue;
    std::vector<Track*> carrier_matches;
    bool timing_of_a_match = false;
    for (auto& t : tracks_) {
      if (!on_carrier(t, p)) continue;
      carrier_matches.push_back(&t);
      timing_of_a_match = timing_of_a_match || timing_fits(t, p);
    }
    if (carrier_matches.empty() || timing_of_a_match || !another_transmitter(carrier_matches, p, r)) continue;
    Track& t = start_track(p, carrier_matches);
    r.attributed[i] = t.id;
    learn(t, p);
  }
  for (std::size_t i = 0; i < r.pulses.size(); ++i)
    if (!r.attributed[i]) ++r.unattributed;

  // One sample per signal: its strongest attributed pulse of the window. A track is confirmed
  // by its second pulse a period later: a one-off burst (a residual, a false alarm) never
  // becomes a signal.
  settle_shadows(r, window_end);
  for (auto& t : tracks_) {
    if (!t.timing.has_period() || t.shadow) continue;
    std::optional<std::size_t> best;
    for (std::size_t i = 0; i < r.pulses.size(); ++i) {
      const DetectedPulse& p = r.pulses[i];
      if (p.truncated() && p.end_s - p.start_s < config_.detector.min_on_time_s) continue;
      if (r.attributed[i] == t.id && (!best || p.statistic > r.pulses[*best].statistic)) best = i;
    }
    if (!best) continue;
    SeparatedSample s = sample_of(r.pulses[*best], t.id, *best);
    if (s.valid_axes == 0) continue;
    s.event = t.pending;
    t.pending = SignalEvent::kNone;
    r.samples.push_back(s);
  }
  // Negative information: a confirmed track's whole pulse was due, and nothing was detected on
  // its carrier nor over that pulse (another transmitter's pulse there could hide a weak one:
  // the detector's dynamic range, PulseDetectorConfig::sidelobe_ratio). Due within this window
  // by its timing, or, when the timing is too vague for one window, somewhere in the carrier's
  // silence since it was last heard for every phase (QuietSpan).
  if (config_.report_misses) {
    const Vec3 floor = pulse_noise_of(window.sample_noise, window.sample_rate_hz);
    std::vector<QuietSpan::Interval> pulse_spans;
    for (const auto& p : r.pulses) pulse_spans.emplace_back(p.start_s, p.end_s);
    for (auto& t : tracks_) {
      const bool heard = std::any_of(r.pulses.begin(), r.pulses.end(), [&](const DetectedPulse& p) { return on_carrier(t, p); });
      if (t.shadow || t.merged || heard || !t.timing.has_period() || !t.on_time_s) {
        t.quiet.reset();
        continue;
      }
      bool missed = false;
      if (const auto due = whole_pulse_due(t, window.new_from_s(), window_end)) {
        missed = std::none_of(r.pulses.begin(), r.pulses.end(),
                              [&](const DetectedPulse& p) { return p.end_s > due->first && p.start_s < due->second; });
      }
      if (!missed) {
        t.quiet.add_window(window.new_from_s(), window_end, *t.on_time_s + config_.on_time_tolerance_s, pulse_spans,
                           config_.timing_gate_sigmas * config_.edge_sigma_s);
        missed = t.quiet.every_phase_covered(t.timing.period_s(), config_.timing_gate_sigmas * t.timing.period_sigma_s());
      }
      if (!missed) continue;
      t.quiet.reset();  // the next miss needs a pulse of its own
      SeparatedSample miss;
      miss.signal_id = t.id;
      miss.noise = floor;
      r.misses.push_back(miss);
    }
  }
  // Silence: lost, then forgotten.
  for (auto& t : tracks_) {
    if (t.timing.has_period() && !t.shadow && !t.lost && window_end - t.last_heard_s > config_.lost_after_s) {
      t.lost = true;
      r.events.push_back({t.id, TrackChange::kLost, window_end});
    }
  }
  for (auto it = tracks_.begin(); it != tracks_.end();) {
    if (!it->timing.has_period() && window_end - it->last_heard_s > 2.0 * 1.35) {
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
