#pragma once
// Monte Carlo evaluation of the firefighter pipeline (seed 004 section V, Figs. 7-8), without
// DDS. Per run: a team of two searches the building (search_walk.hpp); each member's boot IMU
// is simulated at 100 Hz with MTi-3-class errors and run through the ZUPT INS; its 2 Hz
// displacements drive every filter configuration on the very same odometry and the very same
// pattern comparisons, so that configurations differ only in the filter. (A configuration whose
// cloud has concentrated compares only the windows its particles can use, as the live system
// does: the same observations there, except that an ICP pruned against a far better fit
// elsewhere runs to its end.)
//
// Figures per configuration: RMSE of the horizontal position against time (root mean square
// over the members of all runs at each time), final and overall RMSE, converged fraction
// (members whose last estimate is converged and within 2 m), ms per filter update, NEES of the
// converged estimates. Per member: the INS's horizontal drift in % of the distance walked.
//
//   FirefighterEvaluation eval(plan, FirefighterEvalConfig{});
//   FirefighterSummary s = eval.run([&] { bar.tick(); });
#include <functional>
#include <string>
#include <vector>

#include "sarloc/core/firefighter/imu_error_model.hpp"
#include "sarloc/core/firefighter/map_particle_filter.hpp"
#include "sarloc/core/firefighter/search_walk.hpp"
#include "sarloc/core/firefighter/zupt_ins.hpp"

namespace sarloc::firefighter {

struct FirefighterEvalConfig {
  std::uint32_t runs = 10;
  std::uint64_t seed = 1;
  std::uint32_t threads = 0;
  double odometry_rate_hz = 2.0;  ///< seed 004 section V-B
  double rmse_every_s = 30.0;
  SearchWalkConfig walk;
  ImuErrorConfig imu;
  ZuptInsConfig ins;
  PatternGridConfig grid;
  PatternMatchConfig pattern;
  MapFilterConfig filter;  ///< the defaults every configuration starts from
  void validate() const;
};

struct FilterVariant {
  std::string name;
  bool known_initial_state = false;
  bool pseudo_observations = true;
  PseudoResampling resampling = PseudoResampling::kUntilConverged;
};

/// The configurations of Figs. 7-8 (known / unknown initial state x none / weights only /
/// weights + q % resampling), and resampling only until the estimate first converges.
std::vector<FilterVariant> standard_variants();
/// "known/weights", "unknown/no-pseudo", ...: the row of a configuration, e.g. of the filter's
/// configured default.
std::string variant_name(bool known_initial_state, bool pseudo_observations, PseudoResampling resampling);

struct VariantSummary {
  FilterVariant variant;
  std::vector<double> rmse_at_s;       ///< at rmse_every_s, 2 rmse_every_s, ...
  double final_rmse_m = 0.0;
  double overall_rmse_m = 0.0;
  double converged_fraction = 0.0;
  double wrong_floor_fraction = 0.0;   ///< of all estimates
  double ms_per_update_median = 0.0;   ///< predict + update, pattern comparison excluded
  double ms_per_update_amortised = 0.0;///< plus this configuration's comparisons spread over the updates
  /// Median of this configuration's comparisons: restricted to the windows its particles can use
  /// once concentrated (MapParticleFilter::observation_ends), the full one otherwise; 0: none.
  double ms_per_comparison_median = 0.0;
  double ms_per_update_mean = 0.0;     ///< predict + update: the unconverged phase's cost shows here
  double particles_mean = 0.0;         ///< over all updates (the count adapts, map_particle_filter.hpp)
  /// Of the estimates flagged converged, the share whose truth lies outside their own 99 %
  /// ellipse: a position claimed that is not there (about 1 % if the covariance is honest).
  double converged_wrong_fraction = 0.0;
  /// Of the estimates flagged converged, the share also confirmed (MapEstimate::confirmed), and
  /// of those confirmed, the share whose truth lies outside their own 99 % ellipse.
  double confirmed_share = 0.0;
  double confirmed_wrong_fraction = 0.0;
  /// Of all estimates, the share reported ambiguous between 2-4 places (MapEstimate::ambiguous),
  /// and of those, the share whose truth lies in none of the places' 99 % ellipses.
  double ambiguous_share = 0.0;
  double ambiguous_wrong_fraction = 0.0;
  /// The map-error flag on walks whose plan is right (every walk of the evaluation but the
  /// map-error experiment): raises per hour of walking, and the share of estimates flagged. Each
  /// is a false alarm on incident command's board (ALARM_MAP_ERROR).
  double false_map_errors_per_hour = 0.0;
  double false_map_error_share = 0.0;
  double nees_mean = 0.0;              ///< at the end, members converged there (2 dof)
  double nees_lower = 0.0, nees_upper = 0.0;
  std::uint32_t nees_members = 0;
  double nees_fraction_inside_95 = 0.0;///< of converged estimates after 150 s, NEES <= chi2_2(0.95)
};

struct FirefighterSummary {
  std::string building;
  std::uint32_t runs = 0;
  std::uint64_t seed = 0;
  std::uint32_t members = 0;
  double duration_s = 0.0;
  double area_m2 = 0.0;
  std::size_t pattern_windows = 0;
  std::vector<double> ins_drift_percent;  ///< per member
  double ins_drift_median = 0.0, ins_drift_p95 = 0.0;
  double distance_median_m = 0.0;
  /// Per floor of the plan, how many firefighters set foot on it (who climbed, and how far).
  std::vector<std::uint32_t> members_on_floor;
  double ms_per_comparison_median = 0.0;  ///< against every window
  std::vector<VariantSummary> variants;
  double wall_s = 0.0;
  bool cancelled = false;
};

/// One line of the map-error experiment's timeline (section V-E).
struct MapErrorSample {
  double t = 0.0;
  double variance_m2 = 0.0;
  double error_m = 0.0;
  bool converged = false;
  bool map_error_suspected = false;
};

struct MapErrorExperiment {
  std::string door;
  double shift_m = 0.0;
  std::vector<MapErrorSample> timeline;
  bool raised = false;     ///< the flag was raised at some point
  bool recovered = false;  ///< raised, and at the end converged, cleared and within 2 m
  /// After the first raise: time with the flag clear while converged and more than 2 m off
  /// (a wrong position shown as trustworthy).
  double cleared_while_off_s = 0.0;
};

class FirefighterEvaluation {
 public:
  FirefighterEvaluation(const FloorPlan& plan, FirefighterEvalConfig config,
                        std::vector<FilterVariant> variants = standard_variants());
  FirefighterSummary run(const std::function<void()>& on_run_done = {},
                         const std::function<bool()>& cancelled = {}) const;
  /// Moves interior door `door` (empty: the interior door nearest run 0's path in its first two
  /// minutes) by `shift_m` along its wall (as far as the wall allows) in the filter's map only,
  /// and runs the default filter from a known initial state on run 0's leader.
  MapErrorExperiment map_error_experiment(std::string door, double shift_m) const;

 private:
  const FloorPlan& plan_;
  FirefighterEvalConfig config_;
  std::vector<FilterVariant> variants_;
};

}  // namespace sarloc::firefighter
