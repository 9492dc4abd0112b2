#include "sarloc/core/firefighter/firefighter_evaluation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <optional>
#include <set>

#include "sarloc/core/common/gaussian.hpp"
#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"
#include "sarloc/core/common/parallel_trials.hpp"
#include "sarloc/core/common/seeds.hpp"
#include "sarloc/core/common/statistics.hpp"
#include "sarloc/core/firefighter/odometry_track.hpp"

namespace sarloc::firefighter {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double median(std::vector<double> v) { return percentile(std::move(v), 0.5); }

// The full comparison's time is measured on every 4th comparison of a walk, made whether a row
// needs it or not: the rows that need one need mostly the early ones (before their cloud
// concentrates), the first of which are shorter, and the figure should not depend on the rows run.
constexpr std::size_t kTimedEvery = 4;

// One member's odometry, truth and full pattern comparisons: shared by every filter
// configuration. A full comparison is made when a configuration first needs it; one whose cloud
// has concentrated compares only the windows its particles can use
// (MapParticleFilter::observation_ends) and pays for that instead.
struct MemberOdometry {
  std::vector<double> t;                  // s since the search started
  std::vector<Eigen::Vector3d> delta;     // INS displacement, navigation frame
  std::vector<Vec2> truth;
  std::vector<std::size_t> truth_floor;
  std::vector<int> comparison;            // index into trajectories, or -1
  std::vector<std::vector<Vec2>> trajectories;             // the compared odometry
  std::vector<double> walk_heading;
  struct FullComparison {
    std::vector<PseudoObservation> observations;  // against every window
    double ms = 0.0;
  };
  std::vector<std::optional<FullComparison>> full;  // per comparison, once made
  std::vector<double> timed_ms;           // every kTimedEvery-th full comparison's time
  Vec2 start = Vec2::Zero();
  std::size_t start_floor = 0;
  double yaw0 = 0.0;                      // the map heading of the INS frame
  double drift_percent = 0.0;
  double distance_m = 0.0;
};

// Comparison c against every window, made on first use.
const MemberOdometry::FullComparison& full_comparison(MemberOdometry& m, const PatternMatcher& matcher, std::size_t c) {
  if (!m.full[c]) {
    const auto t0 = Clock::now();
    std::vector<PseudoObservation> observations = matcher.compare(m.trajectories[c]);
    m.full[c] = MemberOdometry::FullComparison{std::move(observations), ms_since(t0)};
  }
  return *m.full[c];
}

MemberOdometry simulate_member(const FirefighterEvalConfig& config, const std::vector<Footfall>& footfalls,
                               const PatternMatcher& matcher, std::mt19937_64& rng) {
  MemberOdometry m;
  const FootTrajectory foot(footfalls);
  ImuErrors errors(config.imu, rng);
  ZuptInsConfig ins_config = config.ins;
  ins_config.rate_hz = config.imu.rate_hz;
  ins_config.initial_yaw_rad = 0.0;  // the INS's own frame; the filter estimates its heading
  ZuptIns ins(ins_config);
  OdometryTrack track(config.pattern);
  m.start = footfalls.front().position.head<2>();
  m.start_floor = footfalls.front().floor;
  m.yaw0 = footfalls.front().yaw;
  m.distance_m = path_length(footfalls);
  const double search_start = config.walk.standing_s;
  const double period = 1.0 / config.odometry_rate_hz;
  double next = search_start;
  Eigen::Vector3d ins_at_start = Eigen::Vector3d::Zero();
  bool started = false;
  for (const ImuSample& ideal : foot.imu_samples(config.imu.rate_hz)) {
    ins.push(errors.apply(ideal, rng));
    if (!ins.aligned() || ideal.t + 1e-9 < next) continue;
    if (!started) {
      (void)ins.take_displacement();  // standing at the entry is not part of the search
      ins_at_start = ins.nominal().p;
      track.add(Eigen::Vector3d::Zero());
      started = true;
      next += period;
      continue;
    }
    next += period;
    const StepDisplacement d = ins.take_displacement();
    m.t.push_back(ideal.t - search_start);
    m.delta.push_back(d.delta);
    const FootState truth = foot.at(ideal.t);
    m.truth.push_back(truth.position.head<2>());
    m.truth_floor.push_back(truth.floor);
    track.add(ins.nominal().p - ins_at_start);
    int index = -1;
    if (track.comparison_due()) {
      m.trajectories.push_back(track.recent());
      m.walk_heading.push_back(track.walk_heading());
      m.full.emplace_back();
      track.compared();
      index = static_cast<int>(m.trajectories.size()) - 1;
      if (static_cast<std::size_t>(index) % kTimedEvery == 0) {
        m.timed_ms.push_back(full_comparison(m, matcher, static_cast<std::size_t>(index)).ms);
      }
    }
    m.comparison.push_back(index);
  }
  if (!m.truth.empty()) {
    const Vec2 ins_end = m.start + rotate((ins.nominal().p - ins_at_start).head<2>(), m.yaw0);
    m.drift_percent = 100.0 * (ins_end - m.truth.back()).norm() / std::max(m.distance_m, 1.0);
  }
  return m;
}

// The observations the filter's next update gets, as the live system would compute them: the
// comparison restricted to the ends its particles can use, or the shared full one. Returns the
// comparison's cost (ms), choosing the ends included; 0 when the update uses none.
double compare_for(const MapParticleFilter& pf, const PatternMatcher& matcher, MemberOdometry& m, std::size_t c,
                   std::vector<PseudoObservation>& restricted, const std::vector<PseudoObservation>*& observations) {
  const auto t0 = Clock::now();
  const std::optional<EndMask> ends = pf.observation_ends(matcher);
  if (!ends) {
    const double choosing_ms = ms_since(t0);
    const MemberOdometry::FullComparison& full = full_comparison(m, matcher, c);
    observations = &full.observations;
    return choosing_ms + full.ms;
  }
  restricted = matcher.windows_touching(*ends) ? matcher.compare(m.trajectories[c], &*ends) : std::vector<PseudoObservation>{};
  observations = &restricted;
  return restricted.empty() ? 0.0 : ms_since(t0);
}

// chi2_2(0.99): outside a converged estimate's own 99 % ellipse.

struct VariantTrace {
  std::vector<double> error;         // per update
  std::vector<char> wrong_floor;
  std::vector<double> step_ms;
  std::vector<double> comparison_ms;   // per comparison made (none when the update uses none)
  std::vector<std::size_t> particles;  // per update
  std::size_t converged = 0, converged_wrong = 0;
  std::size_t confirmed = 0, confirmed_wrong = 0;
  std::size_t ambiguous = 0, ambiguous_wrong = 0;
  std::vector<double> nees_late;     // converged estimates after 150 s
  std::size_t map_error_raises = 0;  // rising edges of the map-error flag (the map is right here)
  std::size_t map_error_flagged = 0;  // updates with the flag up
  bool converged_at_end = false;
  double nees_end = -1.0;            // -1: not converged at the end
};

VariantTrace run_filter(const FloorPlan& plan, const NavigableGrid& grid, const PatternMatcher& matcher,
                        const MapFilterConfig& base, const FilterVariant& v, MemberOdometry& m, std::uint64_t seed) {
  MapFilterConfig config = base;
  config.pseudo_observations = v.pseudo_observations;
  config.resampling = v.resampling;
  MapParticleFilter pf(plan, grid, config);
  std::mt19937_64 rng(seed);
  if (v.known_initial_state) {
    pf.init_known(m.start, m.start_floor, m.yaw0, rng);
  } else {
    pf.init_unknown(rng);
  }
  VariantTrace trace;
  std::vector<PseudoObservation> restricted;
  bool flag_was_up = false;
  for (std::size_t k = 0; k < m.delta.size(); ++k) {
    auto t0 = Clock::now();
    pf.predict(m.delta[k], rng);
    double step_ms = ms_since(t0);
    if (m.comparison[k] >= 0) {
      const auto c = static_cast<std::size_t>(m.comparison[k]);
      const std::vector<PseudoObservation>* observations = nullptr;
      const double ms = compare_for(pf, matcher, m, c, restricted, observations);
      if (ms > 0.0) trace.comparison_ms.push_back(ms);
      t0 = Clock::now();
      pf.update(*observations, m.walk_heading[c], rng);
      step_ms += ms_since(t0);
    }
    trace.step_ms.push_back(step_ms);
    const MapEstimate e = pf.estimate();
    const Vec2 err = e.position - m.truth[k];
    trace.error.push_back(err.norm());
    trace.wrong_floor.push_back(e.floor != m.truth_floor[k] ? 1 : 0);
    trace.particles.push_back(pf.particles().size());
    if (e.map_error_suspected && !flag_was_up) ++trace.map_error_raises;
    trace.map_error_flagged += e.map_error_suspected ? 1 : 0;
    flag_was_up = e.map_error_suspected;
    const bool last = k + 1 == m.delta.size();
    if (e.converged) {
      const Eigen::Matrix2d P = e.covariance + 1e-9 * Eigen::Matrix2d::Identity();
      const double nees = err.dot(P.ldlt().solve(err));
      const bool outside = nees > kChi2_2_99;
      ++trace.converged;
      trace.converged_wrong += outside ? 1 : 0;
      trace.confirmed += e.confirmed ? 1 : 0;
      trace.confirmed_wrong += e.confirmed && outside ? 1 : 0;
      if (m.t[k] >= 150.0) trace.nees_late.push_back(nees);
      if (last) trace.nees_end = nees;
    }
    if (e.ambiguous) {
      ++trace.ambiguous;
      const bool in_one = std::any_of(e.candidates.begin(), e.candidates.end(), [&](const Place& p) {
        const Vec2 d = p.position - m.truth[k];
        const Eigen::Matrix2d P = p.covariance + 1e-9 * Eigen::Matrix2d::Identity();
        return p.floor == m.truth_floor[k] && d.dot(P.ldlt().solve(d)) <= kChi2_2_99;
      });
      trace.ambiguous_wrong += in_one ? 0 : 1;
    }
    if (last) trace.converged_at_end = e.converged && err.norm() <= 2.0;
  }
  return trace;
}

struct RunResult {
  std::vector<MemberOdometry> members;
  std::vector<std::vector<VariantTrace>> traces;  // [member][variant]
};

}  // namespace

void FirefighterEvalConfig::validate() const {
  if (runs < 1 || runs > 10000) throw ConfigError("evaluation.runs = " + config_value(runs) + ": must be within [1, 10000]");
  if (!std::isfinite(odometry_rate_hz) || odometry_rate_hz < 0.5 || odometry_rate_hz > 20.0) {
    throw ConfigError("evaluation.odometry_rate_hz = " + config_value(odometry_rate_hz) + ": must be within [0.5, 20]");
  }
  if (!std::isfinite(rmse_every_s) || rmse_every_s < 1.0 || rmse_every_s > 3600.0) {
    throw ConfigError("evaluation.rmse_every_s = " + config_value(rmse_every_s) + ": must be within [1, 3600]");
  }
  walk.validate();
  imu.validate();
  ins.validate();
  grid.validate();
  pattern.validate();
  filter.validate();
}

std::string variant_name(bool known_initial_state, bool pseudo_observations, PseudoResampling resampling) {
  const std::string init = known_initial_state ? "known/" : "unknown/";
  if (!pseudo_observations) return init + "no-pseudo";
  switch (resampling) {
    case PseudoResampling::kNever: return init + "weights";
    case PseudoResampling::kAlways: return init + "weights+resampling";
    case PseudoResampling::kUntilConverged: return init + "until-converged";
  }
  return init + "?";
}

std::vector<FilterVariant> standard_variants() {
  std::vector<FilterVariant> out;
  for (bool known : {true, false}) {
    out.push_back({variant_name(known, false, PseudoResampling::kNever), known, false, PseudoResampling::kNever});
    for (auto r : {PseudoResampling::kNever, PseudoResampling::kAlways, PseudoResampling::kUntilConverged}) {
      out.push_back({variant_name(known, true, r), known, true, r});
    }
  }
  return out;
}

FirefighterEvaluation::FirefighterEvaluation(const FloorPlan& plan, FirefighterEvalConfig config,
                                             std::vector<FilterVariant> variants)
    : plan_(plan), config_((config.validate(), config)), variants_(std::move(variants)) {
  plan_.validate();
}

FirefighterSummary FirefighterEvaluation::run(const std::function<void()>& on_run_done,
                                              const std::function<bool()>& cancelled) const {
  const auto wall0 = Clock::now();
  const NavigableGrid grid = navigable_grid(plan_, config_.grid);
  const PatternMatcher matcher(extract_node_sequences(plan_, config_.grid), config_.grid, config_.pattern);
  auto one_run = [&](std::uint32_t r) {
    std::mt19937_64 rng(derive_seed(config_.seed, r));
    const Hand hand = r % 2 == 0 ? Hand::kRight : Hand::kLeft;
    const SearchWalk walk = generate_search_walk(plan_, config_.walk, hand, rng);
    RunResult result;
    for (const auto* feet : {&walk.leader, &walk.follower}) {
      std::mt19937_64 member_rng(derive_seed(config_.seed, 1000 + 2 * r + (feet == &walk.leader ? 0 : 1)));
      result.members.push_back(simulate_member(config_, *feet, matcher, member_rng));
      std::vector<VariantTrace> traces;
      for (std::size_t v = 0; v < variants_.size(); ++v) {
        traces.push_back(run_filter(plan_, grid, matcher, config_.filter, variants_[v], result.members.back(),
                                    derive_seed(config_.seed, 100000 + 64 * r + 16 * (result.members.size() - 1) + v)));
      }
      result.traces.push_back(std::move(traces));
    }
    return result;
  };
  const auto run = run_parallel_trials<RunResult>(config_.runs, config_.threads, one_run, on_run_done, cancelled);

  FirefighterSummary s;
  s.building = plan_.name;
  s.seed = config_.seed;
  s.runs = static_cast<std::uint32_t>(run.results.size());
  s.cancelled = run.cancelled;
  s.duration_s = config_.walk.duration_s;
  for (std::size_t f = 0; f < grid.nodes_per_floor.size(); ++f) s.area_m2 += grid.area_m2(f);
  s.pattern_windows = matcher.window_count();
  std::vector<double> distances, comparison_ms;
  s.members_on_floor.assign(plan_.floors.size(), 0);
  for (const RunResult& r : run.results) {
    for (const MemberOdometry& m : r.members) {
      for (std::size_t f = 0; f < plan_.floors.size(); ++f) {
        s.members_on_floor[f] +=
            std::find(m.truth_floor.begin(), m.truth_floor.end(), f) != m.truth_floor.end() ? 1 : 0;
      }
      s.ins_drift_percent.push_back(m.drift_percent);
      distances.push_back(m.distance_m);
      comparison_ms.insert(comparison_ms.end(), m.timed_ms.begin(), m.timed_ms.end());
      ++s.members;
    }
  }
  s.ins_drift_median = median(s.ins_drift_percent);
  s.ins_drift_p95 = percentile(s.ins_drift_percent, 0.95);
  s.distance_median_m = median(distances);
  s.ms_per_comparison_median = median(comparison_ms);
  const double period = 1.0 / config_.odometry_rate_hz;
  const auto marks = static_cast<std::size_t>(std::floor(config_.walk.duration_s / config_.rmse_every_s));
  for (std::size_t v = 0; v < variants_.size(); ++v) {
    VariantSummary vs;
    vs.variant = variants_[v];
    std::vector<double> sum_sq(marks, 0.0);
    std::vector<std::size_t> count(marks, 0);
    double all_sq = 0.0, final_sq = 0.0;
    std::size_t all_n = 0, final_n = 0, converged = 0, wrong_floor = 0, late_inside = 0, late_n = 0;
    std::vector<double> step_ms, nees_end, variant_comparison_ms;
    double particle_sum = 0.0;
    std::size_t converged_estimates = 0, converged_wrong = 0, confirmed_estimates = 0, confirmed_wrong = 0;
    std::size_t ambiguous_estimates = 0, ambiguous_wrong = 0, map_error_raises = 0, map_error_flagged = 0;
    for (const RunResult& r : run.results) {
      for (std::size_t mi = 0; mi < r.members.size(); ++mi) {
        const MemberOdometry& m = r.members[mi];
        const VariantTrace& tr = r.traces[mi][v];
        for (std::size_t k = 0; k < tr.error.size(); ++k) {
          all_sq += tr.error[k] * tr.error[k];
          ++all_n;
          wrong_floor += static_cast<std::size_t>(tr.wrong_floor[k]);
          const double mark = m.t[k] / config_.rmse_every_s;
          const auto j = static_cast<std::size_t>(std::lround(mark));
          if (j >= 1 && j <= marks && std::abs(mark - static_cast<double>(j)) * config_.rmse_every_s < 0.5 * period) {
            sum_sq[j - 1] += tr.error[k] * tr.error[k];
            ++count[j - 1];
          }
        }
        if (!tr.error.empty()) {
          final_sq += tr.error.back() * tr.error.back();
          ++final_n;
        }
        if (tr.converged_at_end) ++converged;
        if (tr.nees_end >= 0.0) nees_end.push_back(tr.nees_end);
        for (double n : tr.nees_late) {
          ++late_n;
          if (n <= kChi2_2_95) ++late_inside;
        }
        step_ms.insert(step_ms.end(), tr.step_ms.begin(), tr.step_ms.end());
        variant_comparison_ms.insert(variant_comparison_ms.end(), tr.comparison_ms.begin(), tr.comparison_ms.end());
        for (std::size_t n : tr.particles) particle_sum += static_cast<double>(n);
        converged_estimates += tr.converged;
        converged_wrong += tr.converged_wrong;
        confirmed_estimates += tr.confirmed;
        confirmed_wrong += tr.confirmed_wrong;
        ambiguous_estimates += tr.ambiguous;
        ambiguous_wrong += tr.ambiguous_wrong;
        map_error_raises += tr.map_error_raises;
        map_error_flagged += tr.map_error_flagged;
      }
    }
    for (std::size_t j = 0; j < marks; ++j) vs.rmse_at_s.push_back(count[j] ? std::sqrt(sum_sq[j] / count[j]) : 0.0);
    vs.overall_rmse_m = all_n ? std::sqrt(all_sq / all_n) : 0.0;
    vs.final_rmse_m = final_n ? std::sqrt(final_sq / final_n) : 0.0;
    vs.converged_fraction = s.members ? static_cast<double>(converged) / s.members : 0.0;
    vs.wrong_floor_fraction = all_n ? static_cast<double>(wrong_floor) / all_n : 0.0;
    vs.ms_per_update_median = median(step_ms);
    vs.ms_per_update_mean =
        step_ms.empty() ? 0.0 : std::accumulate(step_ms.begin(), step_ms.end(), 0.0) / static_cast<double>(step_ms.size());
    vs.particles_mean = all_n ? particle_sum / static_cast<double>(all_n) : 0.0;
    vs.converged_wrong_fraction =
        converged_estimates ? static_cast<double>(converged_wrong) / static_cast<double>(converged_estimates) : 0.0;
    vs.confirmed_share =
        converged_estimates ? static_cast<double>(confirmed_estimates) / static_cast<double>(converged_estimates) : 0.0;
    vs.confirmed_wrong_fraction =
        confirmed_estimates ? static_cast<double>(confirmed_wrong) / static_cast<double>(confirmed_estimates) : 0.0;
    vs.ambiguous_share = all_n ? static_cast<double>(ambiguous_estimates) / static_cast<double>(all_n) : 0.0;
    vs.ambiguous_wrong_fraction =
        ambiguous_estimates ? static_cast<double>(ambiguous_wrong) / static_cast<double>(ambiguous_estimates) : 0.0;
    // Every walk here is on the plan the filter holds: each raise is a false alarm.
    const double walked_h = static_cast<double>(all_n) * period / 3600.0;
    vs.false_map_errors_per_hour = walked_h > 0.0 ? static_cast<double>(map_error_raises) / walked_h : 0.0;
    vs.false_map_error_share = all_n ? static_cast<double>(map_error_flagged) / static_cast<double>(all_n) : 0.0;
    const double comparison_total = std::accumulate(variant_comparison_ms.begin(), variant_comparison_ms.end(), 0.0);
    vs.ms_per_comparison_median = variant_comparison_ms.empty() ? 0.0 : median(variant_comparison_ms);
    vs.ms_per_update_amortised =
        vs.ms_per_update_median + (step_ms.empty() ? 0.0 : comparison_total / static_cast<double>(step_ms.size()));
    vs.nees_members = static_cast<std::uint32_t>(nees_end.size());
    if (!nees_end.empty()) {
      const double n = static_cast<double>(nees_end.size());
      vs.nees_mean = std::accumulate(nees_end.begin(), nees_end.end(), 0.0) / n;
      vs.nees_lower = chi_square_quantile(0.025, 2.0 * n) / n;
      vs.nees_upper = chi_square_quantile(0.975, 2.0 * n) / n;
    }
    vs.nees_fraction_inside_95 = late_n ? static_cast<double>(late_inside) / late_n : 0.0;
    s.variants.push_back(vs);
  }
  s.wall_s = std::chrono::duration<double>(Clock::now() - wall0).count();
  return s;
}

MapErrorExperiment FirefighterEvaluation::map_error_experiment(std::string door, double shift_m) const {
  std::mt19937_64 rng(derive_seed(config_.seed, 0));
  const SearchWalk walk = generate_search_walk(plan_, config_.walk, Hand::kRight, rng);
  FloorPlan wrong = plan_;
  const std::size_t floor = walk.leader.front().floor;
  Floor& f = wrong.floors[floor];
  std::set<std::string> entry_doors;
  for (const Entry& e : plan_.entries) entry_doors.insert(e.door);
  // Default: the interior door nearest the walk's path in its first two minutes.
  if (door.empty()) {
    double best = 1e300;
    for (const Door& d : f.doors) {
      if (entry_doors.count(d.id)) continue;
      for (const Footfall& ff : walk.leader) {
        if (ff.t_land > config_.walk.standing_s + 120.0) break;
        const double dist = (ff.position.head<2>() - d.center).norm();
        if (dist < best) {
          best = dist;
          door = d.id;
        }
      }
    }
  }
  MapErrorExperiment out;
  out.door = door;
  out.shift_m = move_door(wrong, floor, door, shift_m);
  wrong.validate();
  const NavigableGrid grid = navigable_grid(wrong, config_.grid);
  const PatternMatcher matcher(extract_node_sequences(wrong, config_.grid), config_.grid, config_.pattern);
  std::mt19937_64 member_rng(derive_seed(config_.seed, 1000));
  MemberOdometry m = simulate_member(config_, walk.leader, matcher, member_rng);
  MapParticleFilter pf(wrong, grid, config_.filter);
  std::mt19937_64 pf_rng(derive_seed(config_.seed, 100000));
  pf.init_known(m.start, m.start_floor, m.yaw0, pf_rng);
  std::vector<PseudoObservation> restricted;
  for (std::size_t k = 0; k < m.delta.size(); ++k) {
    pf.predict(m.delta[k], pf_rng);
    if (m.comparison[k] >= 0) {
      const auto c = static_cast<std::size_t>(m.comparison[k]);
      const std::vector<PseudoObservation>* observations = nullptr;
      (void)compare_for(pf, matcher, m, c, restricted, observations);
      pf.update(*observations, m.walk_heading[c], pf_rng);
    }
    const MapEstimate e = pf.estimate();
    const double error = (e.position - m.truth[k]).norm();
    out.timeline.push_back({m.t[k], e.variance_m2, error, e.converged, e.map_error_suspected});
    if (e.map_error_suspected) out.raised = true;
    if (out.raised && e.converged && !e.map_error_suspected && error > 2.0) {
      out.cleared_while_off_s += 1.0 / config_.odometry_rate_hz;
    }
  }
  const MapErrorSample& end = out.timeline.back();
  out.recovered = out.raised && end.converged && !end.map_error_suspected && end.error_m <= 2.0;
  return out;
}

}  // namespace sarloc::firefighter
