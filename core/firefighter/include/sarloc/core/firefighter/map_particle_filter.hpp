#pragma once
// Information fusion (seed 004 section IV-E): a particle filter over the firefighter's position,
// floor and the heading of the INS's navigation frame in the map. Time update: the INS
// displacement rotated by each particle's heading, plus the noise of section V-B (0.12 m per
// axis per moving update, 2 deg per metre walked). A particle that crosses a wall of the
// navigation map is removed (R-tree, wall_index.hpp). Pseudo-observations from the pattern
// comparison weight the particles by eq. (2)-(3) mixed with a chance that the comparison says
// nothing of a place (`pattern_outlier_probability`), with the epsilon floor, at a quarter of the
// weight once converged (until a map error is suspected); optionally the q % lowest-weighted
// particles are drawn anew from the pseudo-observations.
//
// Particle count: KLD-sampling (core/common/kld_sampling.hpp). An unknown start begins with
// `particles_max` particles spread over the whole plan; every few moving steps the cloud is
// redrawn from its weights until the draws cover enough bins of (0.5 m, 0.5 m, 10 deg, floor)
// for the KL bound, but never fewer than `particles` (the paper's 500) nor more than
// `particles_max`. A concentrated cloud costs what the paper's does; a spread one keeps a
// particle near the true pose, which 500 over the whole plan and all headings rarely hold
// (docs/estimation/firefighter.md, "Particle count").
//
// Floors: a particle changes floor only on stairs of the plan, where its height follows the
// INS's vertical displacement; off the stairs a particle whose height left its floor's by more
// than `floor_tolerance_m` is removed (it did not climb where the firefighter climbed).
//
// Map errors (section V-E): concentrated while the position variance (trace, horizontal) is
// below `converged_variance_m2`; converged when concentrated and, for a walk that came in from an
// unknown start, with `converged_entry_share` of the weight from an entry (below). Map-error-suspected
// (map_error_flag.hpp) is raised when a concentrated cloud spreads past `map_error_spread_factor`
// times that variance or onto two floors (the paper's flag, with a deadband), and also when one
// odometry step removes more than `map_error_removed_fraction` of the weight at walls (the
// firefighter walked where the map has a wall: a moved door, a new opening), a case the variance
// alone misses because the survivors converge again, confidently and wrongly. It clears after `map_error_clear_updates`
// concentrated updates in a row without such a step.
//
// Not converged, the estimate lists the places the cloud is in (cloud_places.hpp) and says when
// it is ambiguous between 2-4 compact ones.
//
// Confirmed (what incident command may show as a position, not a guess): converged for
// `confirm_after_steps` odometry steps in a row (a cloud at its first convergence may still be
// split between two places), no map error suspected since the start, and at least
// `confirm_entry_share` of the weight descending from particles drawn at the start within
// `entry_radius_m` of an entry of the plan (or from a known start). A search walk begins at an
// entry; a cloud that converged on an image of the walk elsewhere in the building (a room that
// looks the same turned round) traces back to a start where no door is.
//
//   MapParticleFilter pf(plan, grid, MapFilterConfig{});
//   pf.init_unknown(rng);
//   pf.predict(ins_delta, rng);                 // 2 Hz
//   pf.update(observations, walk_heading, rng); // after each pattern comparison
//
// The comparison can be restricted to what the next update uses: `observation_ends` marks the
// window ends that are the nearest end to some particle; it asks for every observation while
// the q % replacement is due (it draws from all of them) or when the restriction would still
// compare most windows.
#include <Eigen/Core>
#include <memory>
#include <optional>
#include <random>
#include <vector>

#include "sarloc/core/common/kld_sampling.hpp"
#include "sarloc/core/firefighter/map_error_flag.hpp"
#include "sarloc/core/firefighter/pattern_matcher.hpp"
#include "sarloc/core/firefighter/search_pattern.hpp"
#include "sarloc/core/firefighter/wall_index.hpp"

namespace sarloc::firefighter {

/// Where an unknown start's walk began: outside, so it came in by a door of the plan (the
/// device's first step; `entry_prior` weighs the start), or somewhere inside (a daemon that meets
/// the firefighter mid-search: uniform over the plan).
enum class UnknownStart { kWalkedIn, kInside };

/// When the q % replacement from pseudo-observations runs: never, after every comparison, or
/// until the estimate first converges (sarloc's default).
enum class PseudoResampling { kNever, kAlways, kUntilConverged };
const char* to_string(PseudoResampling r);
PseudoResampling parse_pseudo_resampling(const std::string& text, const std::string& key);

struct MapFilterConfig {
  std::uint32_t particles = 500;         ///< the least count (seed 004's 500); a known start's count
  std::uint32_t particles_max = 20000;   ///< an unknown start's count; = particles: fixed count
  double kld_epsilon = 0.05;             ///< KL bound of KLD-sampling
  double kld_confidence = 0.99;          ///< 1 - delta
  double kld_bin_m = 0.5;
  double kld_bin_deg = 10.0;
  double position_noise_m = 0.12;
  double heading_noise_deg_per_m = 2.0;
  double moving_threshold_m = 0.02;     ///< below this per update: standing, no position noise
  /// sqrt(m), eq. (2). Seed 004 used 0.1; here that lets a 0.1 m better ICP fit elsewhere
  /// (e^-10) pull a converged cloud onto the wrong grid node (docs/estimation/firefighter.md).
  double likelihood_sigma = 0.5;
  /// sigma of eq. (2) while converged, unless a map error has been suspected since the start:
  /// the comparisons weigh a quarter as much when tracking (the 1040 m2 floor's known start:
  /// 1.09-1.18 m at worst with 0.5, 0.83-0.99 m with 1.0; docs/estimation/firefighter.md).
  /// = likelihood_sigma: one sigma throughout.
  double likelihood_sigma_converged = 1.0;
  /// Chance that a comparison says nothing about a place: the walk of the last 20 m is none of
  /// the plan's search patterns there (a sweep, a turn back, a room crossed diagonally). Each
  /// comparison's factor is outlier + (1 - outlier) exp(-(E - E_best) / sigma^2), so one poor fit
  /// costs a particle at most that factor (docs/estimation/firefighter.md). 0: eq. (2) alone.
  double pattern_outlier_probability = 0.2;
  double weight_floor_factor = 0.01;    ///< epsilon = factor / particles
  double replace_fraction = 0.10;       ///< q
  double replace_position_sigma_m = 0.5;
  double replace_heading_sigma_deg = 25.0;
  bool pseudo_observations = true;
  /// Default: never, pseudo-observations as weights only. The paper's Fig. 7 saw "always" hurt
  /// on the larger building, its Fig. 8 needed it to converge from an unknown state with 500
  /// particles; with the adaptive count an unknown start converges without it, and drawing 10 %
  /// from ambiguous patterns only pulls the cloud apart (docs/estimation/firefighter.md).
  PseudoResampling resampling = PseudoResampling::kNever;
  double converged_variance_m2 = 3.0;  ///< section V-E: concentrated
  /// A walk that came in from an unknown start is converged only while it is concentrated and
  /// at least this share of its weight descends from particles drawn near an entry: a cloud
  /// whose every path from a door has died is a look-alike of the walk, not a place (the 1040 m2
  /// floor; docs/estimation/firefighter.md). 0: concentrated alone.
  double converged_entry_share = 0.5;
  double entry_radius_m = 4.0;          ///< a particle drawn this near an entry began at it
  /// An unknown start of a walk that came in (UnknownStart::kWalkedIn): the prior chance that it
  /// began within entry_radius_m of an entry of the plan, not by a window or a ladder. The
  /// particles are still drawn over the whole plan; their weights carry the prior, so a look-alike
  /// of the walk far from any door keeps particles but little weight (docs/estimation/firefighter.md).
  /// 0: uniform over the plan.
  double entry_prior = 0.9;
  double confirm_entry_share = 0.9;     ///< confirmed: at least this share of the weight from an entry
  std::uint32_t confirm_after_steps = 20;  ///< ... and converged for this many odometry steps in a row (10 s at 2 Hz)
  double known_position_sigma_m = 0.1;
  double known_heading_sigma_deg = 2.0;
  double floor_tolerance_m = 0.5;
  double map_error_removed_fraction = 0.5;
  std::uint32_t map_error_clear_updates = 60;  ///< refreshes: about 25 s at walking pace (MapErrorFlagConfig)
  /// A concentrated cloud that spreads raises the flag only past this many times
  /// converged_variance_m2 (a deadband: MapErrorFlagConfig::spread_factor)
  double map_error_spread_factor = 2.0;
  void validate() const;
};

struct Particle {
  Vec2 position = Vec2::Zero();
  double heading = 0.0;  ///< rotation of the INS navigation frame into the map (rad)
  double z = 0.0;        ///< m, follows the INS on stairs
  std::size_t floor = 0;
  /// Descends from a particle drawn at the start within `entry_radius_m` of an entry, or from
  /// a known start (copies keep it; a particle drawn from a pattern does not have it).
  bool from_entry = false;
};

/// One place a cloud is in: a group of touching 1 m cells holding particles, on one floor.
struct Place {
  std::size_t floor = 0;
  Vec2 position = Vec2::Zero();  ///< weighted mean
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  double weight = 0.0;  ///< share of the cloud's weight
};

struct MapEstimate {
  Vec2 position = Vec2::Zero();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Identity();
  std::size_t floor = 0;
  double floor_probability = 0.0;
  double variance_m2 = 0.0;  ///< trace of the covariance
  /// The paper's convergence (section V-E): the position variance of the whole cloud under
  /// `converged_variance_m2`, on one floor. It drives the map-error flag.
  bool concentrated = false;
  /// Map heading of the INS navigation frame (weighted circular mean on `floor`, rad): a
  /// displacement of the INS, turned by it, is one in the map.
  double frame_heading = 0.0;
  /// Concentrated, and for a walk that came in from an unknown start the weight from an entry
  /// (`converged_entry_share`): what may be shown as a position with its ellipse.
  bool converged = false;
  bool map_error_suspected = false;
  /// The flag has been raised since the start, cleared or not. Over 20 walks per building with
  /// a moved door the filter often converged again in the wrong room and cleared the flag 30 s
  /// later (docs/estimation/firefighter.md): a position after a raise should not count as
  /// confirmed until a person confirms it.
  bool map_error_since_start = false;
  /// Share of the weight whose lineage began at an entry (Particle::from_entry).
  double entry_lineage = 0.0;
  /// Converged for a while, no map error since the start, and the weight from an entry (above).
  bool confirmed = false;
  /// Not converged, the cloud is in 2-4 compact places (each under `converged_variance_m2`,
  /// together 95 % of the weight): "ambiguous between N places", each with its weight.
  bool ambiguous = false;
  /// Not converged: the places the cloud is in, heaviest first (at most 4; none while it is
  /// spread over more than 4).
  std::vector<Place> candidates;
};

class MapParticleFilter {
 public:
  MapParticleFilter(const FloorPlan& plan, const NavigableGrid& grid, MapFilterConfig config);

  /// Known initial state: around (position, floor) with the INS frame's map heading, spread by
  /// `known_position_sigma_m` and `known_heading_sigma_deg`; traced back to an entry.
  void init_known(const Vec2& position, std::size_t floor, double heading, std::mt19937_64& rng);
  /// A start near a place told by someone else (a device's dead reckoning when a daemon meets the
  /// firefighter mid-search): as init_known with its own spreads, and not traced back to an entry
  /// (so never confirmed: only an entry confirms). Such a cloud is a prior, not a lock the map
  /// made: its first brushes with walls raise no map error (MapErrorFlag::restart).
  void init_near(const Vec2& position, std::size_t floor, double heading, double position_sigma_m,
                 double heading_sigma_deg, std::mt19937_64& rng);
  /// Unknown: drawn uniformly over the navigable area of every floor, any heading; a walk that
  /// came in weighs those near an entry by `entry_prior`.
  void init_unknown(std::mt19937_64& rng, UnknownStart start = UnknownStart::kWalkedIn);

  /// One odometry step: the INS displacement in its navigation frame.
  void predict(const Eigen::Vector3d& delta, std::mt19937_64& rng);
  /// Odometry over an interval was lost (a radio gap longer than the device's buffer): the
  /// firefighter moved somewhere within about `position_sigma_m`. Every particle is displaced at
  /// random by that much, through walls too (the unknown path may have used a door), and the
  /// confirmation starts over.
  void diffuse(double position_sigma_m, std::mt19937_64& rng);
  /// One pattern comparison. `walk_heading_ins`: the walking direction in the INS frame at the
  /// end of the compared trajectory.
  void update(const std::vector<PseudoObservation>& observations, double walk_heading_ins, std::mt19937_64& rng);

  /// The window ends whose observations the next update can use (nullopt: all of them).
  std::optional<EndMask> observation_ends(const PatternMatcher& matcher) const;

  MapEstimate estimate() const;
  const std::vector<Particle>& particles() const { return particles_; }
  const std::vector<double>& weights() const { return weights_; }
  const MapFilterConfig& config() const { return config_; }

 private:
  void init_around(const Vec2& position, std::size_t floor, double heading, double position_sigma_m,
                   double heading_sigma_deg, bool from_entry, std::mt19937_64& rng);
  void replace_dead(const std::vector<char>& dead, std::mt19937_64& rng);
  /// Redraws the cloud from its weights with the KLD-sampling count (equal weights after).
  void adapt_count(std::mt19937_64& rng);
  std::uint64_t bin_of(const Particle& p) const;
  void refresh_flags(double removed_weight = 0.0);
  bool on_stairs(Particle& p) const;

  const FloorPlan& plan_;
  const NavigableGrid& grid_;
  MapFilterConfig config_;
  std::vector<std::unique_ptr<WallIndex>> walls_;
  /// Per floor, the flights touching it with their two floors (found once, not per particle).
  struct Flight {
    const Stairs* stairs;
    std::size_t lower, upper;
    double mid_height;
  };
  std::vector<std::vector<Flight>> flights_;
  std::vector<Particle> particles_;
  std::vector<Particle> before_;  ///< the cloud before this predict (used if every particle dies)
  std::vector<double> weights_;
  bool walked_in_ = false;  ///< an unknown start of UnknownStart::kWalkedIn
  MapErrorFlag map_error_;  ///< also whether the cloud is concentrated (MapEstimate::concentrated)
  std::uint32_t converged_steps_ = 0;  ///< odometry steps in a row that ended converged
  std::uint32_t moving_steps_ = 0;
  KldSampleCount kld_needed_;
};

}  // namespace sarloc::firefighter
