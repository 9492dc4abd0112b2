#include "sarloc/core/avalanche/rescuer_search.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "sarloc/core/avalanche/field_measurement_check.hpp"
#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/avalanche/same_transmitter.hpp"
#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "sarloc/core/common/time_units.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::avalanche {
using responder::reject;

void RescuerSearchConfig::validate() const {
  sog.validate();
  search.validate();
  require(summary_components >= 1 && summary_components <= 8, "rescuer_search.summary_components", summary_components,
          "must be in [1, 8]");
  require(max_signals >= 1 && max_signals <= 64, "rescuer_search.max_signals", max_signals, "must be in [1, 64]");
  require(max_step_m > 0.0 && max_step_m <= 1000.0, "rescuer_search.max_step_m", max_step_m, "must be in (0, 1000]");
  require(max_rotation_rad > 0.0 && max_rotation_rad <= 7.0, "rescuer_search.max_rotation_rad", max_rotation_rad,
          "must be in (0, 7]");
  require(unknown_motion_speed_m_per_s > 0.0 && unknown_motion_speed_m_per_s <= 5.0,
          "rescuer_search.unknown_motion_speed_m_per_s", unknown_motion_speed_m_per_s, "must be in (0, 5]");
  require(measurement_lag_tolerance_s >= 0.0 && measurement_lag_tolerance_s <= 10.0,
          "rescuer_search.measurement_lag_tolerance_s", measurement_lag_tolerance_s, "must be in [0, 10]");
  require(unknown_motion_turn_rad_per_s > 0.0 && unknown_motion_turn_rad_per_s <= 3.0,
          "rescuer_search.unknown_motion_turn_rad_per_s", unknown_motion_turn_rad_per_s, "must be in (0, 3]");
  require(target_silence_s >= 1.0 && target_silence_s <= 600.0, "rescuer_search.target_silence_s", target_silence_s,
          "must be in [1, 600]");
  require(same_transmitter_gate_probability > 0.0 && same_transmitter_gate_probability < 1.0,
          "rescuer_search.same_transmitter_gate_probability", same_transmitter_gate_probability, "must be in (0, 1)");
  require(same_transmitter_moment_spread > 0.0 && same_transmitter_moment_spread <= 1.0,
          "rescuer_search.same_transmitter_moment_spread", same_transmitter_moment_spread, "must be in (0, 1]");
  require(found_witness_window_s >= 0.0 && found_witness_window_s <= 600.0, "rescuer_search.found_witness_window_s",
          found_witness_window_s, "must be in [0, 600]");
  require(found_witness_gate_probability > 0.0 && found_witness_gate_probability < 1.0,
          "rescuer_search.found_witness_gate_probability", found_witness_gate_probability, "must be in (0, 1)");
  require(found_witness_radius_factor >= 1.0 && found_witness_radius_factor <= 100.0,
          "rescuer_search.found_witness_radius_factor", found_witness_radius_factor, "must be in [1, 100]");
}

RescuerSearch::RescuerSearch(std::string rescuer_id, RescuerSearchConfig config)
    : rescuer_id_(std::move(rescuer_id)),
      config_((config.validate(), std::move(config))),
      same_transmitter_gate_(chi_square_quantile(config_.same_transmitter_gate_probability, 6.0)),
      witness_gate_(chi_square_quantile(config_.found_witness_gate_probability, 3.0)) {}

void RescuerSearch::log_input(TimestampNs stamp, RecentInput input) {
  if (config_.found_witness_window_s <= 0.0) return;
  recent_.emplace_back(stamp, std::move(input));
  // Kept a little longer than the window: a witness starts at its first sample inside it.
  const auto keep = seconds_to_ns(config_.found_witness_window_s + 5.0);
  while (!recent_.empty() && recent_.back().first - recent_.front().first > keep) recent_.pop_front();
}

std::optional<Rejection> RescuerSearch::add_odometry(const Odometry& o) {
  if (o.rescuer_id != rescuer_id_) {
    return reject(RejectReason::kWrongRescuer, rescuer_id_, "odometry.rescuer_id = '" + o.rescuer_id + "'");
  }
  if (superseded_until_ != 0 && o.interval_end <= superseded_until_) {
    return reject(RejectReason::kSuperseded, rescuer_id_,
                  "odometry.interval_end = " + std::to_string(o.interval_end) +
                      ": unknown motion already stood in for it (arrived too late)");
  }
  if (last_odometry_sequence_) {
    if (o.sequence == *last_odometry_sequence_) {
      return reject(RejectReason::kDuplicateSequence, rescuer_id_,
                    "odometry.sequence = " + std::to_string(o.sequence) + " already received");
    }
    if (o.sequence < *last_odometry_sequence_) {
      return reject(RejectReason::kSequenceBackwards, rescuer_id_,
                    "odometry.sequence = " + std::to_string(o.sequence) + " < last " +
                        std::to_string(*last_odometry_sequence_));
    }
    if (o.interval_start < last_odometry_end_) {
      return reject(RejectReason::kStampBackwards, rescuer_id_,
                    "odometry.interval_start = " + std::to_string(o.interval_start) + " before last interval_end " +
                        std::to_string(last_odometry_end_));
    }
  }
  if (o.interval_end < o.interval_start) {
    return reject(RejectReason::kStampBackwards, rescuer_id_,
                  "odometry.interval_end = " + std::to_string(o.interval_end) + " < interval_start " +
                      std::to_string(o.interval_start));
  }
  if (!o.translation.allFinite() || !o.rotation_rpy.allFinite() || !o.covariance.allFinite()) {
    return reject(RejectReason::kInvalidValue, rescuer_id_, "odometry: non-finite translation, rotation or covariance");
  }
  if (o.translation.norm() > config_.max_step_m) {
    std::ostringstream os;
    os << "odometry.translation |t| = " << o.translation.norm() << " m: more than max_step_m " << config_.max_step_m;
    return reject(RejectReason::kAbsurdMotion, rescuer_id_, os.str());
  }
  if (o.rotation_rpy.cwiseAbs().maxCoeff() > config_.max_rotation_rad) {
    std::ostringstream os;
    os << "odometry.rotation_rpy max |angle| = " << o.rotation_rpy.cwiseAbs().maxCoeff() << " rad: more than "
       << config_.max_rotation_rad;
    return reject(RejectReason::kAbsurdMotion, rescuer_id_, os.str());
  }
  // The filters validate the covariance themselves; check on a copy first so a refusal
  // cannot leave some signals' filters with the sample and others without.
  try {
    OdometryAccumulator probe(config_.sog.idle_translation_sigma_m, config_.sog.idle_rotation_sigma_rad);
    probe.add(o);
  } catch (const InputError& e) {
    return reject(RejectReason::kInvalidValue, rescuer_id_, e.what());
  }
  // A gap before this step: the steps in between were lost for good (a radio fade longer than
  // the sender keeps them). Over 10 s of lost motion the robocentric map is gone: restart the
  // unfound filters. A shorter gap is applied as it is: standing unknown motion in for it was
  // measured to make a near-field filter less consistent (tests/unit, NEES 2293 against 6.4).
  if (last_odometry_sequence_ && o.interval_start > last_odometry_end_) {
    const auto gap = static_cast<std::uint64_t>(o.interval_start) - static_cast<std::uint64_t>(last_odometry_end_);
    if (gap > static_cast<std::uint64_t>(kMaxFrameGapNs)) {
      return reject(RejectReason::kStampBackwards, rescuer_id_,
                    "odometry.interval_start = " + std::to_string(o.interval_start) + ": more than 600 s after the " +
                        "last step's end " + std::to_string(last_odometry_end_) + " (a bogus stamp)");
    }
    if (gap > static_cast<std::uint64_t>(kMaxUnknownMotionNs)) restart_unfound_filters();
  }
  for (auto& [signal, state] : signals_) state.filter.add_odometry(o);
  if (line_bearing_) line_bearing_ = wrap_angle(*line_bearing_ - o.rotation_rpy.z());
  log_input(o.interval_end, o);
  last_odometry_sequence_ = o.sequence;
  last_odometry_end_ = o.interval_end;
  return std::nullopt;
}

void RescuerSearch::restart_unfound_filters() {
  for (auto& [signal, state] : signals_) {
    if (state.found || state.retired) continue;  // stood over before the gap: that moment's estimate stands
    state.filter = SogFilter(config_.sog, rescuer_id_, signal);
    if (state.repeat == responder::RepeatState::kSuspected) state.repeat = responder::RepeatState::kNone;
    state.controller = SearchController(config_.search);
    state.estimate.reset();
  }
  recent_.clear();  // the frame they were given in is lost
  line_bearing_.reset();
  ++restarts_;
  choose_target();
}

bool RescuerSearch::add_unknown_motion(TimestampNs from, TimestampNs until) {
  from = std::max(from, last_odometry_end_);
  if (until <= from) return false;
  // until > from: their difference as unsigned is exact, whatever the stamps' signs.
  const auto span = static_cast<std::uint64_t>(until) - static_cast<std::uint64_t>(from);
  if (span > static_cast<std::uint64_t>(kMaxUnknownMotionNs)) {
    // Too long to stand in for: the robocentric map is lost. Restart the unfound filters
    // (they initialise from the next measurement) rather than update them as if the rescuer
    // had stood still. The clocks stay: a bogus stamp far ahead must not shut real odometry out.
    if (span > static_cast<std::uint64_t>(kMaxFrameGapNs)) return false;
    restart_unfound_filters();
    return true;
  }
  const double dt = static_cast<double>(span) * 1e-9;  // <= 10 s; variances capped at 100 m^2 below
  const double vt = std::pow(config_.unknown_motion_speed_m_per_s * dt, 2);
  const double vz = std::pow(0.2 * config_.unknown_motion_speed_m_per_s * dt, 2) + 1e-4;  // slopes only
  const double vyaw = std::pow(std::min(config_.unknown_motion_turn_rad_per_s * dt, 2.0), 2);
  const double vtilt = std::pow(0.02, 2);  // roll/pitch stay bounded by gravity
  DispCov q = DispCov::Zero();
  q.diagonal() << std::min(vt, 100.0), std::min(vt, 100.0), std::min(vz, 100.0), vtilt, vtilt, vyaw;
  for (auto& [signal, state] : signals_) state.filter.add_unknown_motion(q);
  log_input(until, q);
  last_odometry_end_ = until;
  superseded_until_ = until;
  return true;
}

std::optional<Rejection> RescuerSearch::gate(const FieldMeasurement& m) const {
  if (m.rescuer_id != rescuer_id_) {
    return reject(RejectReason::kWrongRescuer, rescuer_id_, "field_measurement.rescuer_id = '" + m.rescuer_id + "'");
  }
  try {
    validate_field_measurement(m);
  } catch (const InputError& e) {
    return reject(RejectReason::kInvalidValue, rescuer_id_,
                  "signal " + std::to_string(m.signal_id) + ": " + e.what());
  }
  // The odometry received already reaches well past this sample (it was retransmitted under
  // packet loss and overtaken by a later epoch's step): its filter would apply that later
  // motion before the update, i.e. measure from where the rescuer was not (seen: a filter 7 m
  // from its victim diverged to 600 m); a new signal's filter would start in a frame the
  // rescuer has left. The signal's next sample takes the motion.
  const auto tolerance = static_cast<std::uint64_t>(config_.measurement_lag_tolerance_s * 1e9);
  if (last_odometry_end_ > m.stamp &&
      static_cast<std::uint64_t>(last_odometry_end_) - static_cast<std::uint64_t>(m.stamp) > tolerance) {
    return reject(RejectReason::kLateMeasurement, rescuer_id_,
                  "field_measurement(signal " + std::to_string(m.signal_id) + ").stamp = " + std::to_string(m.stamp) +
                      ": the odometry already reaches " + std::to_string(last_odometry_end_) +
                      " (arrived after a later epoch)");
  }
  const auto it = signals_.find(m.signal_id);
  if (it == signals_.end()) {
    if (signals_.size() >= config_.max_signals) {
      return reject(RejectReason::kTooManySignals, rescuer_id_,
                    "field_measurement.signal_id = " + std::to_string(m.signal_id) + ": already " +
                        std::to_string(signals_.size()) + " signals (max_signals)");
    }
    return std::nullopt;
  }
  const SignalState& s = it->second;
  const std::string where = "field_measurement(signal " + std::to_string(m.signal_id) + ").";
  if (m.sequence == s.last_sequence) {
    return reject(RejectReason::kDuplicateSequence, rescuer_id_,
                  where + "sequence = " + std::to_string(m.sequence) + " already received");
  }
  if (m.sequence < s.last_sequence) {
    return reject(RejectReason::kSequenceBackwards, rescuer_id_,
                  where + "sequence = " + std::to_string(m.sequence) + " < last " + std::to_string(s.last_sequence));
  }
  if (m.stamp <= s.last_stamp) {
    return reject(RejectReason::kStampBackwards, rescuer_id_,
                  where + "stamp = " + std::to_string(m.stamp) + " not after last " + std::to_string(s.last_stamp));
  }
  return std::nullopt;
}

std::variant<SearchUpdate, Rejection> RescuerSearch::process(const FieldMeasurement& m) {
  if (auto rejected = gate(m)) return *rejected;
  if (m.valid_axes == 0) return process_miss(m);
  quiet_epochs_ = 0;  // a pulse heard, of any signal (found ones too): the device is within range
  auto it = signals_.find(m.signal_id);
  if (it == signals_.end()) {
    it = signals_
             .emplace(m.signal_id, SignalState{SogFilter(config_.sog, rescuer_id_, m.signal_id),
                                               SearchController(config_.search), 0, 0, 0, 0.0, std::nullopt,
                                               done_.count(m.signal_id) != 0, std::nullopt})
             .first;
  }
  SignalState& s = it->second;
  s.silenced = false;  // heard: on again, or another transmitter where it was
  if (m.transmitter.known()) s.transmitter = m.transmitter;
  if (m.event != SignalEvent::kNone) {
    s.last_event = m.event;
    s.last_event_stamp = m.stamp;
  }
  auto with_event = [&s](VictimEstimate e) { return with_signal_state(s, std::move(e)); };
  if (const std::optional<VictimEstimate>& stood_over = s.found ? s.found : s.retired) {
    // Found here (or retired as a repeat where it was found): the victim stays where the rescuer
    // stood over it. The filter takes no more measurement updates (while the rescuer walks off
    // to the next victim, a late or lost odometry sample could drag it away, and it would still
    // claim kFound: seen under 20 % packet loss, a "found" victim published 6 m off).
    const MixtureMoments mm = s.filter.predicted_moments();
    VictimEstimate moved = *stood_over;
    moved.stamp = m.stamp;
    moved.relative.position = mm.mean.segment<3>(idx::kPos);
    moved.relative.covariance = mm.covariance.block<3, 3>(idx::kPos, idx::kPos);
    moved.top_components.clear();  // they describe the mixture of the moment it was found
    s.last_sequence = m.sequence;
    s.last_stamp = m.stamp;
    s.estimate = with_event(moved);
    SearchUpdate unchanged;
    unchanged.estimate = with_event(*stood_over);
    return unchanged;
  }
  if (auto rejected = update_filter(s, m)) return *rejected;
  if (!line_bearing_) line_bearing_ = 0.0;  // no guidance yet: he is walking the primary line
  s.last_heard_stamp = m.stamp;
  s.last_field_norm = m.field.norm();

  VictimEstimate estimate = s.filter.estimate(config_.summary_components);
  estimate.stamp = m.stamp;
  SearchUpdate update;
  bool found_now = false;
  if (target_ ? *target_ == m.signal_id : may_guide_to(m.signal_id, s)) {
    // Guidance only for the signal being searched (one direction at a time for the rescuer),
    // never towards a victim already found.
    s.controller.primary_line_at(*line_bearing_);
    Guidance g = s.controller.guide(s.filter, m);
    g.rescuer_id = rescuer_id_;
    g.signal_id = m.signal_id;
    g.stamp = m.stamp;
    const bool withdrawn = g.mode == GuidanceMode::kFound && !witnessed(m.signal_id, s, m.stamp);
    if (withdrawn) {
      // The latest samples alone say elsewhere: no FOUND; the search goes on from both. A FOUND
      // this sample still gave is witnessed again with the next.
      estimate = s.filter.estimate(config_.summary_components);
      estimate.stamp = m.stamp;
      g = s.controller.guide(s.filter, m);
      g.rescuer_id = rescuer_id_;
      g.signal_id = m.signal_id;
      g.stamp = m.stamp;
      if (g.mode == GuidanceMode::kFound) g.mode = GuidanceMode::kFineSearch;
    }
    if (g.mode == GuidanceMode::kFound) {
      found_now = true;
      s.done = true;
      done_.insert(m.signal_id);
    }
    update.guidance = g;
  }
  // FOUND only through the guidance's confirmation (found_confirmations samples in a row).
  const ConfirmationEvidence evidence = s.controller.evidence(s.filter, estimate.relative.position);
  estimate.status = found_now ? EstimatorStatus::kFound
                              : std::min(s.controller.assess(estimate, evidence), EstimatorStatus::kLocated);
  test_repeat(m.signal_id, s, estimate.status, found_now);
  if (found_now && s.repeat != responder::RepeatState::kNone) {
    // Stood over a victim this signal is (or cannot be told from) another's: no FOUND, and the
    // next epoch guides to the next target. Done all the same: coming back would tell no more.
    found_now = false;
    update.guidance.reset();
  }
  estimate = with_event(estimate);
  s.estimate = estimate;
  if (found_now) s.found = estimate;
  if (s.repeat == responder::RepeatState::kConfirmed && !s.retired) s.retired = estimate;
  update.estimate = estimate;
  choose_target();
  return update;
}

VictimEstimate RescuerSearch::with_signal_state(const SignalState& s, VictimEstimate e) {
  e.signal_event = s.last_event;
  e.signal_event_stamp = s.last_event_stamp;
  e.repeat = s.repeat;
  e.repeat_of_signal = s.repeat_of;
  e.transmitter = s.transmitter;
  if (s.repeat != responder::RepeatState::kNone) e.status = std::min(e.status, EstimatorStatus::kConverged);
  return e;
}

void RescuerSearch::test_repeat(std::uint32_t id, SignalState& s, EstimatorStatus status, bool found_now) {
  using responder::RepeatState;
  if (s.repeat == RepeatState::kConfirmed) return;  // retired for good
  s.repeat = RepeatState::kNone;
  s.repeat_of = 0;
  if (status < EstimatorStatus::kConverged) return;  // claims nothing a repeat could double
  const MixtureMoments mine = s.filter.moments();
  double closest = same_transmitter_gate_;
  const SignalState* other = nullptr;
  MixtureMoments theirs;  // the closest one's, moved to now
  for (const auto& [other_id, o] : signals_) {
    // Stands as a victim here: found, or published kLocated and not itself a repeat. Once this
    // signal is found, only found ones: the one stood over keeps FOUND and a located other
    // becomes its suspected repeat on its next sample.
    const bool stands = o.found || (!found_now && o.estimate && o.estimate->status >= EstimatorStatus::kLocated &&
                                    o.repeat == RepeatState::kNone);
    if (other_id == id || !stands) continue;
    const MixtureMoments moved = o.filter.predicted_moments();
    const double d2 = same_transmitter_distance2(mine, moved);
    if (d2 <= closest) {
      closest = d2;
      other = &o;
      theirs = moved;
      s.repeat_of = other_id;
    }
  }
  if (other == nullptr) return;
  const double spread = config_.same_transmitter_moment_spread;
  if (found_now && other->found && moment_determined(mine, spread) &&
      moment_determined(theirs, spread)) {
    s.repeat = RepeatState::kConfirmed;
    ++confirmed_repeats_;
    return;
  }
  s.repeat = RepeatState::kSuspected;
}

std::optional<SogFilter> RescuerSearch::found_witness(std::uint32_t id, TimestampNs since) const {
  SogFilter witness(config_.sog, rescuer_id_, id);
  try {
    for (const auto& [stamp, input] : recent_) {
      if (const auto* m = std::get_if<FieldMeasurement>(&input)) {
        if (m->signal_id == id && stamp >= since) witness.process(*m);  // the first heard one initialises it
      } else if (const auto* o = std::get_if<Odometry>(&input)) {
        witness.add_odometry(*o);  // ignored until it is initialised
      } else {
        witness.add_unknown_motion(std::get<DispCov>(input));
      }
    }
  } catch (const InputError&) {
    return std::nullopt;  // the main filter took each of these: a numerical refusal
  }
  return witness;
}

bool RescuerSearch::witnessed(std::uint32_t id, SignalState& s, TimestampNs now) {
  if (config_.found_witness_window_s <= 0.0) return true;
  const auto window = seconds_to_ns(config_.found_witness_window_s);
  std::optional<SogFilter> witness = found_witness(id, now - window);
  if (!witness || !witness->initialised()) return true;
  const VictimEstimate theirs = witness->estimate(config_.summary_components);
  // The latest samples alone must (nearly) locate the victim too. A filter that learnt a moment
  // from a carrier-mate's pulses fits the right transmitter's clean pulses from the wrong place
  // with a small radius; a fresh filter on those pulses is consistent, and wide until they pin
  // the victim down: the FOUND waits for it (the probes go on) rather than trust the narrow one.
  // Nearly: 30 s of samples leave a victim 4 m deep 1.5-2 times the located radius. A FOUND the
  // adaptive end gives unlocated (a stalled search) states its wider radius: that one counts.
  const VictimEstimate mine = s.filter.estimate(config_.summary_components);
  const double claimed = std::max(s.controller.located_radius(mine.relative.position),
                                  radius95_3d(mine.relative.covariance));
  if (radius95_3d(theirs.relative.covariance) > config_.found_witness_radius_factor * claimed) {
    s.controller.withdraw_found();
    ++deferred_founds_;
    return false;
  }
  const Vec3 d = mine.relative.position - theirs.relative.position;
  const Mat3 sum = mine.relative.covariance + theirs.relative.covariance;
  const double d2 = d.dot(sum.ldlt().solve(d));
  if (d2 <= witness_gate_) return true;
  // Neither is taken on trust: the witness may be the one wrong (a deep victim's estimate from 30 s
  // of samples near it, seen 1.5 m off where the filter was right); the samples to come decide.
  s.filter.add_hypotheses(*witness);
  s.controller.withdraw_found();
  ++withdrawn_founds_;
  return false;
}

std::optional<Rejection> RescuerSearch::update_filter(SignalState& s, const FieldMeasurement& m) {
  // The gate already checked everything the filter checks; a throw here is a numerical
  // refusal of this one sample, and the filter stays as it was.
  try {
    const SogStepResult step = s.filter.process(m);
    if (step.leapt) ++leaps_;
    if (step.rebuilt_implausible) ++implausible_rebuilds_;
  } catch (const InputError& e) {
    return reject(RejectReason::kInvalidValue, rescuer_id_, "signal " + std::to_string(m.signal_id) + ": " + e.what());
  }
  log_input(m.stamp, m);
  s.last_sequence = m.sequence;
  s.last_stamp = m.stamp;
  newest_stamp_ = std::max(newest_stamp_, m.stamp);
  return std::nullopt;
}

std::variant<SearchUpdate, Rejection> RescuerSearch::process_miss(const FieldMeasurement& m) {
  const auto it = signals_.find(m.signal_id);
  // Nothing to learn for a signal never heard here (a daemon restarted mid-search) or found.
  if (it == signals_.end() || it->second.found || it->second.retired || !it->second.filter.initialised())
    return SearchUpdate{};
  SignalState& s = it->second;
  if (auto rejected = update_filter(s, m)) return *rejected;
  SearchUpdate update;
  VictimEstimate e = s.filter.estimate(config_.summary_components);
  e.stamp = m.stamp;
  // Where the transmitter is not never confirms where it is: the status never rises on a miss.
  const EstimatorStatus before = s.estimate ? s.estimate->status : EstimatorStatus::kInitialising;
  const ConfirmationEvidence evidence = s.controller.evidence(s.filter, e.relative.position);
  e.status = std::min({s.controller.assess(e, evidence), before, EstimatorStatus::kLocated});
  test_repeat(m.signal_id, s, e.status, false);
  e = with_signal_state(s, std::move(e));
  s.estimate = e;
  update.estimate = e;
  choose_target();
  if (target_ && *target_ == m.signal_id) update.guidance = coast(m.stamp);
  return update;
}

std::optional<Guidance> RescuerSearch::coast(TimestampNs stamp) {
  bool counted = false;
  while (target_) {
    const auto it = signals_.find(*target_);
    if (it == signals_.end() || !it->second.filter.initialised()) return std::nullopt;
    SignalState& s = it->second;
    if (!counted) ++quiet_epochs_;
    counted = true;
    if (line_bearing_) s.controller.primary_line_at(*line_bearing_);
    Guidance g = s.controller.coast(s.filter, quiet_epochs_);
    // On a converged estimate within reach, where its transmitter would be the loudest there
    // is, and the device hearing nothing at all for lost_signal_steps epochs: the transmitter is
    // off (a victim dug out and switched off, a flat battery), not masked or out of range. Leave
    // it, as a searcher moves on; heard again, it is searched again. Seen: a rescuer that
    // converged on a victim as the diggers switched it off stood on the hole for 100 s.
    const bool converged = s.estimate && s.estimate->status >= EstimatorStatus::kConverged;
    if (config_.search.lost_signal_steps > 0 && quiet_epochs_ >= config_.search.lost_signal_steps && converged &&
        g.distance_m <= std::max(kSilencedReachM, g.uncertainty_radius_m)) {
      s.silenced = true;
      ++silenced_targets_;
      choose_target();
      continue;
    }
    g.rescuer_id = rescuer_id_;
    g.signal_id = *target_;
    g.stamp = stamp;
    return g;
  }
  return std::nullopt;
}

void RescuerSearch::mark_done(std::uint32_t signal_id) {
  done_.insert(signal_id);
  if (auto it = signals_.find(signal_id); it != signals_.end()) it->second.done = true;
  choose_target();
}

void RescuerSearch::leave_to_others(std::set<std::uint32_t> signal_ids, TimestampNs until) {
  left_until_ = until;
  if (signal_ids == left_to_others_) return;
  left_to_others_ = std::move(signal_ids);
  choose_target();
}

std::size_t RescuerSearch::line_resumptions() const {
  std::size_t n = 0;
  for (const auto& [id, s] : signals_) n += s.controller.line_resumptions();
  return n;
}

std::optional<VictimEstimate> RescuerSearch::estimate(std::uint32_t signal_id) const {
  const auto it = signals_.find(signal_id);
  if (it == signals_.end()) return std::nullopt;
  return it->second.estimate;
}

std::optional<FieldFit> RescuerSearch::field_fit(std::uint32_t signal_id, const Vec3& field, const Vec3& noise,
                                                 std::uint8_t axes) const {
  const auto it = signals_.find(signal_id);
  // A found filter takes no more updates, but it still moves with the odometry: it knows its
  // transmitter best of all, so it can tell that transmitter's pulses from a carrier-mate's
  // (seen: a signal that lost its own transmitter took a found one's pulses 1 Hz away and
  // converged between the two, a ghost).
  if (it == signals_.end()) return std::nullopt;
  auto fit = it->second.filter.predictive_fit(field, noise, axes);
  if (fit && it->second.repeat != responder::RepeatState::kNone) fit->repeat_of = it->second.repeat_of;
  return fit;
}

bool RescuerSearch::may_guide_to(std::uint32_t signal_id, const SignalState& s) const {
  return !s.done && !s.silenced && (left_to_others_.count(signal_id) == 0 || newest_stamp_ > left_until_);
}

void RescuerSearch::choose_target() {
  // Sticky: keep walking to the current victim until it is found; then the strongest signal
  // among those not done (the classic transceiver rule: strongest is usually nearest). A target
  // silent for target_silence_s gives way to a signal heard since (measured: coasting back and
  // forth to where a signal lost at 40 m was last heard, next to two victims heard every step).
  const auto silence = seconds_to_ns(config_.target_silence_s);
  auto heard_lately = [&](const SignalState& state) { return newest_stamp_ - state.last_heard_stamp < silence; };
  std::optional<std::uint32_t> keep;
  if (target_) {
    const auto it = signals_.find(*target_);
    if (it != signals_.end() && may_guide_to(it->first, it->second)) {
      if (heard_lately(it->second)) return;
      keep = target_;
    }
  }
  target_.reset();
  double strongest = -1.0;
  for (const auto& [signal, state] : signals_) {
    if (!may_guide_to(signal, state) || !state.filter.initialised() || (keep && !heard_lately(state))) continue;
    if (state.last_field_norm > strongest) {
      strongest = state.last_field_norm;
      target_ = signal;
    }
  }
  if (!target_) target_ = keep;  // nothing else heard: the silent target it stays
}

}  // namespace sarloc::avalanche
