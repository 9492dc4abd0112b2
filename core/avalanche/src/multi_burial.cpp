#include "sarloc/core/avalanche/multi_burial.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "sarloc/core/avalanche/beacon_receiver.hpp"
#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/avalanche/found_victim.hpp"
#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/avalanche/sensor_simulation.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "sarloc/core/common/parallel_trials.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::avalanche {

void MultiBurialSetup::validate() const {
  simulation.validate();
  rescuer.validate();
  evaluation.validate();
  if (simulation.receiver.kind != ReceiverKind::kRealistic)
    throw ConfigError("simulation.receiver.kind = ideal: multiple burials need the realistic receiver");
  require(victims >= 1 && victims <= 8, "multi_burial.victims", victims, "must be in [1, 8]");
  require(spread_m >= 0.5 && spread_m <= 100.0, "multi_burial.spread_m", spread_m, "must be in [0.5, 100]");
  require(period_spread >= 0.0 && period_spread <= 0.3, "multi_burial.period_spread", period_spread,
          "must be in [0, 0.3]");
}

MultiBurialTrial run_multi_burial_trial(const MultiBurialSetup& setup, std::uint32_t index,
                                        const MultiBurialTraceObserver* trace) {
  const SimulationConfig& sim = setup.simulation;
  std::mt19937_64 rng(derive_seed(setup.evaluation.seed, index));
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> n01(0.0, 1.0);
  // The cluster: its centre 40-60 m away, every victim within spread_m / 2 of it.
  const double dist = sim.start_distance_min_m + (sim.start_distance_max_m - sim.start_distance_min_m) * u01(rng);
  const double az = 2.0 * kPi * u01(rng);
  const Vec3 centre(dist * std::cos(az), dist * std::sin(az), 0.0);
  TransmitterTiming common = TransmitterTiming::draw(sim.receiver, rng);
  std::vector<Beacon> beacons;
  for (std::uint32_t v = 0; v < setup.victims; ++v) {
    const double r = 0.5 * setup.spread_m * std::sqrt(u01(rng));
    const double a = 2.0 * kPi * u01(rng);
    const double depth = draw_burial_depth(sim, rng, n01);
    Beacon b;
    b.position = centre + Vec3(r * std::cos(a), r * std::sin(a), -depth);
    b.moment = draw_moment(sim, rng, u01);
    b.timing = TransmitterTiming::draw(sim.receiver, rng);
    if (setup.period_spread > 0.0) {
      b.timing.period_s = std::clamp(common.period_s * (1.0 + setup.period_spread * (2.0 * u01(rng) - 1.0)),
                                     1e-3 * sim.receiver.period_min_ms, 1e-3 * sim.receiver.period_max_ms);
      b.timing.first_start_s = common.first_start_s + 0.3 * b.timing.on_time_s * (2.0 * u01(rng) - 1.0);
    }
    beacons.push_back(b);
  }
  std::vector<Vec3> victim_positions;
  for (const Beacon& b : beacons) victim_positions.push_back(b.position);
  // The rescuer walks a primary-search strip passing within its half width of the cluster.
  ReceiverPose pose;
  pose.position = Vec3(0.0, 0.0, sim.antenna_height_m);
  const double offset = std::asin(std::clamp(sim.primary_strip_half_width_m * (2.0 * u01(rng) - 1.0) / dist, -1.0, 1.0));
  pose.rpy = Vec3(0.0, 0.0, wrap_angle(az + offset));

  BeaconReceiver receiver(sim, derive_seed(setup.evaluation.seed, 0x5EED0000ULL + index));
  double min_gap = 2.0 * sim.receiver.carrier_tolerance_hz;
  double lockstep_s = 0.0;
  for (std::size_t a = 0; a < beacons.size(); ++a)
    for (std::size_t b = a + 1; b < beacons.size(); ++b) {
      const double gap = std::fabs(beacons[a].timing.carrier_offset_hz - beacons[b].timing.carrier_offset_hz);
      min_gap = std::min(min_gap, gap);
      if (gap < kCarrierCellHz)
        lockstep_s = std::max(lockstep_s, pulses_overlap_for_s(beacons[a].timing, beacons[b].timing));
    }
  RescuerSearch search("sim", setup.rescuer);
  // The device's separation asks each signal's filter when carrier and timing cannot decide.
  receiver.separator().set_consistency([&search](std::uint32_t signal, const Vec3& field, const Vec3& noise,
                                                 std::uint8_t axes) { return search.field_fit(signal, field, noise, axes); });
  MultiBurialTrial tr;
  tr.index = index;
  tr.min_carrier_gap_hz = min_gap;
  tr.lockstep_s = lockstep_s;
  std::vector<FoundClaim> founds;
  std::vector<std::pair<std::uint32_t, Vec3>> found_at;  // step and antenna position of each FOUND
  std::set<std::uint32_t> reported, signals, retired, suspected, located, falsely_located;
  std::map<std::uint32_t, std::size_t> victim_found_by;  // signal -> the victim its FOUND was scored as
  std::uint64_t odometry_sequence = 0;
  if (trace && trace->victims) {
    std::vector<MultiBurialTraceVictim> truth;
    for (const Beacon& b : beacons) truth.push_back({b.position, b.moment.norm(), b.timing});
    trace->victims(truth);
  }
  for (std::uint32_t step = 1; step <= setup.evaluation.step_budget; ++step) {
    const TimestampNs stamp = static_cast<TimestampNs>(step) * 1'000'000'000;
    const Listening heard = receiver.listen(pose, beacons, static_cast<double>(step), 1.0);
    tr.wrong_attributions += heard.wrong_attributions;
    tr.unattributed_pulses += heard.report.unattributed;
    for (const HeardSample& h : heard.samples) {
      if (!h.mixed_with || h.mixed_energy_ratio < kMixedEnergyRatio) continue;
      ++tr.mixed_samples;
      const bool tracked = std::any_of(signals.begin(), signals.end(), [&](std::uint32_t other) {
        return other != h.sample.signal_id && receiver.majority_beacon_of_signal(other) == h.mixed_with;
      });
      if (tracked) ++tr.mixed_samples_both_tracked;
    }
    const OrientationObservation attitude = simulate_attitude(sim, pose, rng);
    std::optional<Guidance> guidance;
    MultiBurialTraceStep traced;
    const std::vector<FieldMeasurement> measurements = to_measurements(heard, "sim", step, stamp, attitude);
    for (std::size_t i = 0; i < measurements.size(); ++i) {
      const FieldMeasurement& m = measurements[i];
      signals.insert(m.signal_id);
      std::optional<FieldFit> fit_before;
      if (trace && m.valid_axes != 0) fit_before = search.field_fit(m.signal_id, m.field, m.noise_stddev, m.valid_axes);
      const auto outcome = search.process(m);
      const auto* update = std::get_if<SearchUpdate>(&outcome);
      if (trace) {
        MultiBurialTraceSample& t = traced.samples.emplace_back();
        t.signal_id = m.signal_id;
        t.valid_axes = m.valid_axes;
        t.majority_victim = receiver.majority_beacon_of_signal(m.signal_id);
        if (i < heard.samples.size()) {  // to_measurements: the samples, then the misses
          t.pulse_victim = heard.samples[i].transmitter;
          t.mixed_victim = heard.samples[i].mixed_with;
          t.mixed_energy_ratio = heard.samples[i].mixed_energy_ratio;
          t.truth_nis = heard.samples[i].truth_nis;
        }
        if (fit_before) t.filter_nis = fit_before->nis;
        if (update) {
          t.estimate = update->estimate;
          t.guidance = update->guidance;
          if (t.estimate) {
            t.estimate_at = pose.position + t.estimate->relative.position;
            if (t.majority_victim) {
              const Vec3 err = t.estimate_at - victim_positions[*t.majority_victim];
              t.error_m = err.norm();
              t.nees = err.dot(t.estimate->relative.covariance.ldlt().solve(err));
            }
          }
        }
      }
      if (update == nullptr) continue;
      if (update->guidance) guidance = update->guidance;
      if (update->estimate && update->estimate->status == EstimatorStatus::kLocated) {
        const VictimEstimate& e = *update->estimate;
        if (located.insert(m.signal_id).second) tr.first_located_range_m.push_back(e.relative.position.norm());
        const Vec3 where = pose.position + e.relative.position;
        if (!victim_of_found(where, found_reach(e.relative.covariance), victim_positions,
                             receiver.majority_beacon_of_signal(m.signal_id))) {
          falsely_located.insert(m.signal_id);
          tr.worst_false_located_range_m = std::max(tr.worst_false_located_range_m, e.relative.position.norm());
        }
      }
      if (update->estimate && update->estimate->repeat == responder::RepeatState::kSuspected &&
          suspected.insert(m.signal_id).second)
        ++tr.repeats_suspected;
      if (update->estimate && update->estimate->repeat == responder::RepeatState::kConfirmed &&
          retired.insert(m.signal_id).second) {
        ++tr.repeats_retired;
        const auto majority = receiver.majority_beacon_of_signal(m.signal_id);
        const auto first = victim_found_by.find(update->estimate->repeat_of_signal);
        if (majority && first != victim_found_by.end() && *majority != first->second) ++tr.repeats_wrong;
      }
      if (!update->estimate || update->estimate->status != EstimatorStatus::kFound || reported.count(m.signal_id) != 0)
        continue;
      reported.insert(m.signal_id);
      // A FOUND: which victim it names, the FOUNDs so far matched to distinct victims (found_victim.hpp).
      const Vec3 where = pose.position + update->estimate->relative.position;
      const FoundClaim claim{where, update->estimate->relative.covariance, receiver.majority_beacon_of_signal(m.signal_id)};
      if (const auto victim = victim_of_found(where, found_reach(claim.covariance), victim_positions, claim.own))
        victim_found_by[m.signal_id] = *victim;
      founds.push_back(claim);
      found_at.emplace_back(step, pose.position);
      const FoundMatching matched = match_founds(founds, victim_positions);
      tr.found = static_cast<std::uint32_t>(matched.found);
      tr.ghosts = static_cast<std::uint32_t>(matched.ghosts);
      tr.duplicates = static_cast<std::uint32_t>(matched.duplicates);
    }
    tr.steps = step;
    auto emit_trace = [&](const std::optional<Guidance>& walked) {
      if (!trace || !trace->step) return;
      traced.step = step;
      traced.rescuer = pose.position;
      traced.target = search.target_signal();
      traced.guidance = walked;
      traced.unattributed_pulses = heard.report.unattributed;
      traced.found = tr.found;
      trace->step(traced);
    };
    if (tr.found == setup.victims) {
      emit_trace(std::nullopt);
      tr.all_found = true;
      break;
    }
    if (!guidance) guidance = search.coast(stamp);
    emit_trace(guidance);
    const double bearing = guidance ? guidance->bearing_rad : 0.0;  // no target: the primary line
    const double step_m = guidance ? guidance->step_m : setup.rescuer.search.step_length_m;
    const Vec3 before = pose.position;
    Odometry o = simulate_step(sim, pose, bearing, step_m, rng);
    tr.distance_m += (pose.position - before).norm();
    o.rescuer_id = "sim";
    o.sequence = ++odometry_sequence;
    o.interval_start = stamp;
    o.interval_end = stamp + 1'000'000'000;
    search.add_odometry(o);
  }
  // Each FOUND against the victim it was matched to (else the nearest): inside its stated radius?
  const FoundMatching matched = match_founds(founds, victim_positions);
  for (std::size_t f = 0; f < founds.size(); ++f) {
    std::size_t victim = 0;
    if (matched.victim[f]) {
      victim = *matched.victim[f];
    } else {
      for (std::size_t v = 1; v < victim_positions.size(); ++v)
        if ((victim_positions[v] - founds[f].position).norm() < (victim_positions[victim] - founds[f].position).norm())
          victim = v;
    }
    const Vec3 err = founds[f].position - victim_positions[victim];
    const double error = err.norm();
    const double ratio = error / std::max(radius95_3d(founds[f].covariance), 1e-9);
    FoundRecord& rec = tr.found_records.emplace_back();
    rec.step = found_at[f].first;
    rec.depth_m = -victim_positions[victim].z();
    rec.range_m = (found_at[f].second - victim_positions[victim]).norm();
    rec.error_m = error;
    rec.radius95_m = radius95_3d(founds[f].covariance);
    rec.nees = err.dot(founds[f].covariance.ldlt().solve(err));
    rec.ghost = !matched.victim[f] && error > found_reach(founds[f].covariance);
    ++tr.founds;
    if (ratio > 1.0) ++tr.founds_outside_radius;
    tr.worst_found_error_to_radius = std::max(tr.worst_found_error_to_radius, ratio);
  }
  tr.signals = static_cast<std::uint32_t>(signals.size());
  tr.located_signals = static_cast<std::uint32_t>(located.size());
  tr.false_located = static_cast<std::uint32_t>(falsely_located.size());
  tr.leaps = static_cast<std::uint32_t>(search.leaps());
  tr.implausible_rebuilds = static_cast<std::uint32_t>(search.implausible_rebuilds());
  tr.withdrawn_founds = static_cast<std::uint32_t>(search.withdrawn_founds());
  tr.line_resumptions = static_cast<std::uint32_t>(search.line_resumptions());
  tr.deferred_founds = static_cast<std::uint32_t>(search.deferred_founds());
  return tr;
}

MultiBurialSummary run_multi_burial(const MultiBurialSetup& setup, const std::function<void()>& on_trial_done,
                                    const std::function<bool()>& cancelled) {
  setup.validate();
  const auto start = std::chrono::steady_clock::now();
  TrialRun<MultiBurialTrial> run = run_parallel_trials<MultiBurialTrial>(
      setup.evaluation.trials, setup.evaluation.threads,
      [&](std::uint32_t i) { return run_multi_burial_trial(setup, i); }, on_trial_done, cancelled);
  MultiBurialSummary s;
  s.victims = setup.victims;
  s.spread_m = setup.spread_m;
  s.seed = setup.evaluation.seed;
  std::vector<double> steps, distance, first_located;
  for (const auto& r : run.results) {
    ++s.trials;
    if (r.all_found) {
      ++s.all_found;
      steps.push_back(r.steps);
      distance.push_back(r.distance_m);
    }
    s.ghosts += r.ghosts;
    s.duplicates += r.duplicates;
    s.founds += r.founds;
    s.founds_outside_radius += r.founds_outside_radius;
    s.worst_found_error_to_radius = std::max(s.worst_found_error_to_radius, r.worst_found_error_to_radius);
    s.located_signals += r.located_signals;
    first_located.insert(first_located.end(), r.first_located_range_m.begin(), r.first_located_range_m.end());
    s.false_located += r.false_located;
    if (r.false_located > 0) ++s.trials_with_false_located;
    s.worst_false_located_range_m = std::max(s.worst_false_located_range_m, r.worst_false_located_range_m);
    s.repeats_retired += r.repeats_retired;
    s.repeats_wrong += r.repeats_wrong;
    s.repeats_suspected += r.repeats_suspected;
    if (r.repeats_suspected + r.repeats_retired > 0) ++s.trials_with_repeats;
    s.leaps += r.leaps;
    if (r.leaps > 0) ++s.trials_with_leaps;
    s.implausible_rebuilds += r.implausible_rebuilds;
    if (r.implausible_rebuilds > 0) ++s.trials_with_implausible_rebuilds;
    s.withdrawn_founds += r.withdrawn_founds;
    if (r.withdrawn_founds > 0) ++s.trials_with_withdrawn_founds;
    s.line_resumptions += r.line_resumptions;
    if (r.line_resumptions > 0) ++s.trials_with_line_resumptions;
    s.deferred_founds += r.deferred_founds;
    if (r.deferred_founds > 0) ++s.trials_with_deferred_founds;
    s.wrong_attributions += r.wrong_attributions;
    s.unattributed_pulses += r.unattributed_pulses;
    s.mixed_samples += r.mixed_samples;
    s.mixed_samples_both_tracked += r.mixed_samples_both_tracked;
    if (r.mixed_samples > 0) ++s.trials_with_mixed_samples;
    s.per_trial.push_back(r);
  }
  s.steps = compute_stats(steps);
  s.first_located_range_m = compute_stats(first_located);
  s.distance_m = compute_stats(distance);
  s.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return s;
}

}  // namespace sarloc::avalanche
