#include "sarloc/core/firefighter/map_particle_filter.hpp"

#include <algorithm>
#include <boost/random/normal_distribution.hpp>
#include <cmath>
#include <numeric>
#include <string>
#include <tuple>
#include <unordered_set>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/particle_weights.hpp"
#include "sarloc/core/common/validate.hpp"
#include "sarloc/core/firefighter/cloud_places.hpp"
#include "sarloc/core/firefighter/point_index.hpp"

namespace sarloc::firefighter {
namespace {

constexpr std::size_t kMaxCandidates = 4;  // "ambiguous between N places": N at most this
constexpr double kCandidateLeast = 0.01;   // a place with less weight is no candidate
constexpr double kCandidatesHold = 0.95;   // the candidates together hold this much

constexpr double kHeightLeak = 0.05;
// The count adapts every 4 moving steps (2 s of walking at 2 Hz): often enough to shed
// particles soon after the cloud concentrates, rarely enough not to deplete it by redrawing.
constexpr std::uint32_t kAdaptEveryMovingSteps = 4;

}  // namespace

const char* to_string(PseudoResampling r) {
  switch (r) {
    case PseudoResampling::kNever: return "never";
    case PseudoResampling::kAlways: return "always";
    case PseudoResampling::kUntilConverged: return "until_converged";
  }
  return "?";
}

PseudoResampling parse_pseudo_resampling(const std::string& text, const std::string& key) {
  if (text == "never") return PseudoResampling::kNever;
  if (text == "always") return PseudoResampling::kAlways;
  if (text == "until_converged") return PseudoResampling::kUntilConverged;
  throw ConfigError(key + " = '" + text + "': must be never, always or until_converged");
}

void MapFilterConfig::validate() const {
  auto check = [](const char* key, double v, double lo, double hi) { check_range("filter", key, v, lo, hi); };
  check("particles", particles, 10.0, 1e6);
  check("particles_max", particles_max, particles, 1e6);
  check("kld_epsilon", kld_epsilon, 1e-4, 1.0);
  check("kld_confidence", kld_confidence, 0.51, 0.9999);
  check("kld_bin_m", kld_bin_m, 0.05, 10.0);
  check("kld_bin_deg", kld_bin_deg, 1.0, 180.0);
  check("position_noise_m", position_noise_m, 0.0, 5.0);
  check("heading_noise_deg_per_m", heading_noise_deg_per_m, 0.0, 90.0);
  check("moving_threshold_m", moving_threshold_m, 0.0, 1.0);
  check("likelihood_sigma", likelihood_sigma, 1e-3, 10.0);
  check("likelihood_sigma_converged", likelihood_sigma_converged, 1e-3, 10.0);
  check("pattern_outlier_probability", pattern_outlier_probability, 0.0, 0.99);
  check("weight_floor_factor", weight_floor_factor, 0.0, 1.0);
  check("replace_fraction", replace_fraction, 0.0, 0.9);
  check("replace_position_sigma_m", replace_position_sigma_m, 0.0, 10.0);
  check("replace_heading_sigma_deg", replace_heading_sigma_deg, 0.0, 180.0);
  check("converged_variance_m2", converged_variance_m2, 1e-3, 1e4);
  check("entry_radius_m", entry_radius_m, 0.1, 50.0);
  check("confirm_entry_share", confirm_entry_share, 0.5, 1.0);
  check("entry_prior", entry_prior, 0.0, 1.0);
  check("converged_entry_share", converged_entry_share, 0.0, 1.0);
  check("confirm_after_steps", confirm_after_steps, 0.0, 1e6);
  check("known_position_sigma_m", known_position_sigma_m, 0.0, 100.0);
  check("known_heading_sigma_deg", known_heading_sigma_deg, 0.0, 180.0);
  check("floor_tolerance_m", floor_tolerance_m, 0.1, 10.0);
  check("map_error_removed_fraction", map_error_removed_fraction, 0.05, 1.0);
  check("map_error_clear_updates", map_error_clear_updates, 1.0, 1e6);
  check("map_error_spread_factor", map_error_spread_factor, 1.0, 100.0);
}

namespace {

MapErrorFlagConfig map_error_flag_config(const MapFilterConfig& filter) {
  MapErrorFlagConfig c;
  c.converged_variance_m2 = filter.converged_variance_m2;
  c.spread_factor = filter.map_error_spread_factor;
  c.removed_fraction = filter.map_error_removed_fraction;
  c.clear_updates = filter.map_error_clear_updates;
  return c;
}

}  // namespace

MapParticleFilter::MapParticleFilter(const FloorPlan& plan, const NavigableGrid& grid, MapFilterConfig config)
    : plan_(plan),
      grid_(grid),
      config_((config.validate(), config)),
      map_error_(map_error_flag_config(config_)),
      kld_needed_(config_.kld_epsilon, config_.kld_confidence) {
  for (std::size_t f = 0; f < plan.floors.size(); ++f) {
    walls_.push_back(std::make_unique<WallIndex>(plan.solid_walls(f, WallSet::kNavigation)));
    std::vector<Flight> flights;
    for (const Stairs* s : plan.stairs_of(f)) {
      const std::size_t lower = plan.floor_index(s->lower_floor), upper = plan.floor_index(s->upper_floor);
      flights.push_back({s, lower, upper, 0.5 * (plan.floors[lower].elevation_m + plan.floors[upper].elevation_m)});
    }
    flights_.push_back(std::move(flights));
  }
}

void MapParticleFilter::init_known(const Vec2& position, std::size_t floor, double heading, std::mt19937_64& rng) {
  init_around(position, floor, heading, config_.known_position_sigma_m, config_.known_heading_sigma_deg, true, rng);
}

void MapParticleFilter::init_near(const Vec2& position, std::size_t floor, double heading, double position_sigma_m,
                                  double heading_sigma_deg, std::mt19937_64& rng) {
  init_around(position, floor, heading, position_sigma_m, heading_sigma_deg, false, rng);
}

void MapParticleFilter::init_around(const Vec2& position, std::size_t floor, double heading, double position_sigma_m,
                                    double heading_sigma_deg, bool from_entry, std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  particles_.assign(config_.particles, Particle{});
  for (Particle& p : particles_) {
    p.position = position + position_sigma_m * Vec2(n(rng), n(rng));
    p.heading = wrap_angle(heading + heading_sigma_deg * kDeg * n(rng));
    p.floor = floor;
    p.z = plan_.floors.at(floor).elevation_m;
    p.from_entry = from_entry;
  }
  weights_.assign(config_.particles, 1.0 / config_.particles);
  walked_in_ = false;
  moving_steps_ = converged_steps_ = 0;
  map_error_.restart(from_entry);
  refresh_flags();
}

void MapParticleFilter::init_unknown(std::mt19937_64& rng, UnknownStart start) {
  std::vector<std::pair<std::size_t, Vec2>> nodes;
  for (std::size_t f = 0; f < grid_.nodes_per_floor.size(); ++f) {
    for (const Vec2& v : grid_.nodes_per_floor[f]) nodes.emplace_back(f, v);
  }
  if (nodes.empty()) throw InputError("init_unknown: the plan has no navigable area");
  std::uniform_int_distribution<std::size_t> pick(0, nodes.size() - 1);
  std::uniform_real_distribution<double> cell(-0.5 * grid_.spacing_m, 0.5 * grid_.spacing_m);
  std::uniform_real_distribution<double> any_heading(-kPi, kPi);
  std::vector<std::pair<std::size_t, Vec2>> entries;
  for (const Entry& entry : plan_.entries) entries.emplace_back(plan_.floor_index(entry.floor), entry.position);
  particles_.assign(config_.particles_max, Particle{});
  for (Particle& p : particles_) {
    const auto& [floor, node] = nodes[pick(rng)];
    Vec2 at(node.x() + cell(rng), node.y() + cell(rng));
    if (walls_[floor]->crosses(node, at)) at = node;  // keep it in the node's room
    p.position = at;
    p.floor = floor;
    p.z = plan_.floors[floor].elevation_m;
    p.heading = any_heading(rng);
    for (const auto& [entry_floor, entry_at] : entries) {
      p.from_entry = p.from_entry || (entry_floor == floor && (entry_at - at).norm() <= config_.entry_radius_m);
    }
  }
  const auto at_entry = static_cast<double>(
      std::count_if(particles_.begin(), particles_.end(), [](const Particle& p) { return p.from_entry; }));
  const double n = static_cast<double>(particles_.size());
  walked_in_ = start == UnknownStart::kWalkedIn;
  const double prior = walked_in_ && at_entry > 0.0 && at_entry < n ? config_.entry_prior : 0.0;
  weights_.resize(particles_.size());
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    weights_[i] =
        prior > 0.0 ? (particles_[i].from_entry ? prior / at_entry : (1.0 - prior) / (n - at_entry)) : 1.0 / n;
  }
  moving_steps_ = converged_steps_ = 0;
  map_error_.restart(true);
  refresh_flags();
}

bool MapParticleFilter::on_stairs(Particle& p) const {
  for (const Flight& f : flights_[p.floor]) {
    if (!f.stairs->progress(p.position)) continue;
    p.floor = p.z > f.mid_height ? f.upper : f.lower;
    return true;
  }
  return false;
}

void MapParticleFilter::predict(const Eigen::Vector3d& delta, std::mt19937_64& rng) {
  if (!delta.allFinite()) throw InputError("odometry delta: not finite");
  if (particles_.empty()) throw InputError("predict before init");
  // Ziggurat (Boost.Random): three normals per particle per step, where the standard library's
  // polar method cost a quarter of an unknown start's time.
  boost::random::normal_distribution<double> n(0.0, 1.0);
  const double walked = delta.head<2>().norm();
  const bool moving = walked > config_.moving_threshold_m;
  const double heading_sigma = config_.heading_noise_deg_per_m * kDeg * walked;
  before_ = particles_;  // a kept buffer: no fresh allocation of the cloud every step
  std::vector<char> dead(particles_.size(), 0);
  std::size_t alive = 0;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    Particle& p = particles_[i];
    const Vec2 from = p.position;
    const std::size_t floor = p.floor;
    p.heading = wrap_angle(p.heading + heading_sigma * n(rng));
    p.position += rotate(delta.head<2>(), p.heading);
    if (moving) p.position += config_.position_noise_m * Vec2(n(rng), n(rng));
    p.z += delta.z();
    bool ok = !walls_[floor]->crosses(from, p.position);
    if (ok && !on_stairs(p)) {
      // Off the stairs the height must stay on the floor's: it leaks back to it (10 s time
      // constant at 2 Hz, for the INS's slow vertical drift) but a climb of more than the
      // tolerance removes the particle.
      const double deviation = p.z - plan_.floors[p.floor].elevation_m;
      if (std::abs(deviation) < config_.floor_tolerance_m) {
        p.z -= kHeightLeak * deviation;
      } else {
        ok = false;
      }
    }
    dead[i] = ok ? 0 : 1;
    if (ok) ++alive;
  }
  if (alive == 0) {
    // Every particle hit a wall or left its floor: the map and the odometry disagree. Keep the
    // moves without the map for this step and say so.
    particles_ = before_;
    for (Particle& p : particles_) {
      p.position += rotate(delta.head<2>(), p.heading);
      p.z += delta.z();
      if (!on_stairs(p)) p.z = plan_.floors[p.floor].elevation_m;  // the map is off: start afresh
    }
    refresh_flags(1.0);
    converged_steps_ = 0;
    return;
  }
  double removed = 0.0;
  for (std::size_t i = 0; i < particles_.size(); ++i) removed += dead[i] ? weights_[i] : 0.0;
  replace_dead(dead, rng);
  refresh_flags(removed);
  converged_steps_ = map_error_.concentrated() ? converged_steps_ + 1 : 0;
  if (moving && ++moving_steps_ % kAdaptEveryMovingSteps == 0) adapt_count(rng);
}

void MapParticleFilter::diffuse(double position_sigma_m, std::mt19937_64& rng) {
  if (!std::isfinite(position_sigma_m) || position_sigma_m < 0.0) {
    throw InputError("diffuse: position_sigma_m = " + std::to_string(position_sigma_m) + ": must be finite and >= 0");
  }
  if (particles_.empty()) throw InputError("diffuse before init");
  boost::random::normal_distribution<double> n(0.0, 1.0);
  for (Particle& p : particles_) p.position += position_sigma_m * Vec2(n(rng), n(rng));
  refresh_flags();
  converged_steps_ = 0;
}

std::uint64_t MapParticleFilter::bin_of(const Particle& p) const {
  // 21 bits per coordinate (+-1 Mm at 0.5 m), 12 for the heading, 10 for the floor.
  constexpr std::int64_t kOffset = std::int64_t{1} << 20;
  const auto cell = [&](double v, double size) {
    return static_cast<std::uint64_t>(std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(v / size)) + kOffset, 0,
                                                               2 * kOffset - 1));
  };
  const std::uint64_t x = cell(p.position.x(), config_.kld_bin_m), y = cell(p.position.y(), config_.kld_bin_m);
  const std::uint64_t h = cell(p.heading + kPi, config_.kld_bin_deg * kDeg) & 0xFFF;
  return (x << 43) | (y << 22) | (h << 10) | (p.floor & 0x3FF);
}

void MapParticleFilter::adapt_count(std::mt19937_64& rng) {
  if (config_.particles_max <= config_.particles) return;  // a fixed count, the paper's
  // Until the cloud has converged, KLD-sampling on a multi-modal cloud keeps a count that
  // loses the true mode at random (house-125: a wrong room confirmed); hold every particle.
  if (!map_error_.concentrated()) return;
  std::vector<double> cumulative(weights_.size());
  std::partial_sum(weights_.begin(), weights_.end(), cumulative.begin());
  std::unordered_set<std::uint64_t> bins;
  std::vector<Particle> drawn;
  drawn.reserve(std::min<std::size_t>(config_.particles_max, 2 * particles_.size()));
  double needed = 0.0;
  while (drawn.size() < config_.particles_max &&
         (drawn.size() < config_.particles || static_cast<double>(drawn.size()) < needed)) {
    drawn.push_back(particles_[draw_index(cumulative, rng)]);
    if (bins.insert(bin_of(drawn.back())).second) needed = kld_needed_(bins.size());
  }
  particles_ = std::move(drawn);
  weights_.assign(particles_.size(), 1.0 / static_cast<double>(particles_.size()));
}

void MapParticleFilter::replace_dead(const std::vector<char>& dead, std::mt19937_64& rng) {
  std::vector<double> cumulative(particles_.size());
  double sum = 0.0;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    sum += dead[i] ? 0.0 : weights_[i];
    cumulative[i] = sum;
  }
  if (!(sum > 0.0)) {  // survivors all at zero weight: uniform over them
    sum = 0.0;
    for (std::size_t i = 0; i < particles_.size(); ++i) cumulative[i] = sum += dead[i] ? 0.0 : 1.0;
    for (std::size_t i = 0; i < particles_.size(); ++i) weights_[i] = dead[i] ? 0.0 : 1.0;
  }
  // Copies share their source's weight (the distribution keeps its mass).
  std::vector<std::size_t> source(particles_.size());
  std::vector<std::uint32_t> copies(particles_.size(), 1);
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    if (!dead[i]) continue;
    source[i] = draw_index(cumulative, rng);
    ++copies[source[i]];
  }
  std::vector<double> shared(particles_.size());
  for (std::size_t i = 0; i < particles_.size(); ++i) shared[i] = weights_[i] / copies[i];
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    if (dead[i]) {
      particles_[i] = particles_[source[i]];
      weights_[i] = shared[source[i]];
    } else {
      weights_[i] = shared[i];
    }
  }
  const double total = std::accumulate(weights_.begin(), weights_.end(), 0.0);
  for (double& w : weights_) w /= total;
}

std::optional<EndMask> MapParticleFilter::observation_ends(const PatternMatcher& matcher) const {
  EndMask mask = matcher.empty_end_mask();
  if (!config_.pseudo_observations || particles_.empty()) return mask;  // the update uses none
  const bool replacing = config_.replace_fraction > 0.0 &&
                         (config_.resampling == PseudoResampling::kAlways ||
                          (config_.resampling == PseudoResampling::kUntilConverged && !map_error_.ever_concentrated()));
  if (replacing) return std::nullopt;
  // Particles grouped in cells: the ends that may be nearest to any point of a cell, which
  // holds every particle's nearest end (update() looks up only that one).
  constexpr double kCell = 0.5;
  std::unordered_set<std::uint64_t> cells;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    if (!(weights_[i] > 0.0)) continue;
    const Particle& p = particles_[i];
    const auto ix = static_cast<std::int64_t>(std::floor(p.position.x() / kCell));
    const auto iy = static_cast<std::int64_t>(std::floor(p.position.y() / kCell));
    if (!cells.insert(cell_key(p.floor, ix, iy)).second) continue;
    const Vec2 centre((static_cast<double>(ix) + 0.5) * kCell, (static_cast<double>(iy) + 0.5) * kCell);
    matcher.mark_ends_near(p.floor, centre, 0.5 * std::sqrt(2.0) * kCell, mask);
  }
  // Restricting pays only while it leaves most windows out.
  if (2 * matcher.windows_touching(mask) > matcher.window_count()) return std::nullopt;
  return mask;
}

void MapParticleFilter::update(const std::vector<PseudoObservation>& observations, double walk_heading_ins,
                               std::mt19937_64& rng) {
  if (!config_.pseudo_observations || observations.empty() || particles_.empty()) return;
  if (!std::isfinite(walk_heading_ins)) throw InputError("walk heading: not finite");
  // Tracking, the comparisons mostly tell aliases along a corridor apart from the cloud, and a
  // slightly better fit 1-2 m off pulled it there (the 1040 m2 floor). Finding the place they
  // count in full (seed 004 VI: of most use before convergence), and so for good once a map
  // error was suspected: the cloud may have converged again in the wrong room, and they are
  // its only way back.
  const double sigma = map_error_.concentrated() && !map_error_.since_start() ? config_.likelihood_sigma_converged
                                                                              : config_.likelihood_sigma;
  const double inv_sigma2 = 1.0 / (sigma * sigma);
  // One k-d tree per floor over the observations' distinct positions (a node carries one per
  // column and more where sequences share it), each position with its observations: a particle
  // then needs only its nearest position.
  std::vector<std::vector<Vec2>> points(plan_.floors.size());
  std::vector<std::vector<std::vector<std::size_t>>> observations_at(plan_.floors.size());
  {
    std::vector<std::size_t> order(observations.size());
    std::iota(order.begin(), order.end(), 0);
    const auto key = [&](std::size_t k) {
      const auto& o = observations[k];
      return std::make_tuple(o.floor, o.position.x(), o.position.y());
    };
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
    for (std::size_t r = 0; r < order.size(); ++r) {
      const PseudoObservation& o = observations[order[r]];
      if (r == 0 || key(order[r - 1]) != key(order[r])) {
        points[o.floor].push_back(o.position);
        observations_at[o.floor].emplace_back();
      }
      observations_at[o.floor].back().push_back(order[r]);
    }
  }
  std::vector<std::unique_ptr<PointIndex>> index(plan_.floors.size());
  for (std::size_t f = 0; f < plan_.floors.size(); ++f) {
    if (!points[f].empty()) index[f] = std::make_unique<PointIndex>(points[f]);
  }
  // eq. (2): per particle, the RMSE of the observation at the nearest position whose heading is
  // closest to the particle's walking direction (of two as close, the better fit).
  double best_fit = std::numeric_limits<double>::infinity();
  for (const PseudoObservation& o : observations) best_fit = std::min(best_fit, o.rmse);
  if (!std::isfinite(best_fit)) return;  // no fit anywhere: no information
  const double outlier = config_.pattern_outlier_probability;
  std::vector<double> log_w(particles_.size(), -std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    const Particle& p = particles_[i];
    if (!index[p.floor] || !(weights_[i] > 0.0)) continue;
    double d2 = 0.0;
    const std::uint32_t nearest = index[p.floor]->nearest(p.position, d2);
    const double walking = wrap_angle(p.heading + walk_heading_ins);
    double best_turn = 1e300, e = std::numeric_limits<double>::infinity();
    for (std::size_t k : observations_at[p.floor][nearest]) {
      const PseudoObservation& o = observations[k];
      const double turn = std::abs(wrap_angle(o.heading - walking));
      if (turn < best_turn || (turn == best_turn && o.rmse < e)) {  // ties: the better fit
        best_turn = turn;
        e = o.rmse;
      }
    }
    const double fit = std::isfinite(e) ? std::exp(-(e - best_fit) * inv_sigma2) : 0.0;
    log_w[i] = std::log(weights_[i]) + std::log(outlier + (1.0 - outlier) * fit);
  }
  const double top = *std::max_element(log_w.begin(), log_w.end());
  if (!std::isfinite(top)) return;  // no particle near any usable observation: no information
  // eq. (3), normalised in the log domain (exp(-E / sigma^2) underflows for E > 7 m).
  double total = 0.0;
  for (std::size_t i = 0; i < particles_.size(); ++i) total += weights_[i] = std::exp(log_w[i] - top);
  for (double& w : weights_) w /= total;
  // The epsilon floor: particles below it are replaced by copies of the others.
  const double epsilon = config_.weight_floor_factor / static_cast<double>(particles_.size());
  std::vector<char> dead(particles_.size(), 0);
  for (std::size_t i = 0; i < particles_.size(); ++i) dead[i] = weights_[i] < epsilon ? 1 : 0;
  if (std::find(dead.begin(), dead.end(), 0) != dead.end()) replace_dead(dead, rng);
  refresh_flags();

  const bool resample = config_.resampling == PseudoResampling::kAlways ||
                        (config_.resampling == PseudoResampling::kUntilConverged && !map_error_.ever_concentrated());
  if (!resample || config_.replace_fraction <= 0.0) return;
  // The q % lowest-weighted particles are drawn from the observations, in proportion to eq. (2).
  std::vector<double> cumulative;
  std::vector<std::size_t> usable;
  double best_e = std::numeric_limits<double>::infinity();
  for (const auto& o : observations) best_e = std::min(best_e, o.rmse);
  if (!std::isfinite(best_e)) return;
  double sum = 0.0;
  for (std::size_t k = 0; k < observations.size(); ++k) {
    if (!std::isfinite(observations[k].rmse)) continue;
    sum += std::exp(-(observations[k].rmse - best_e) * inv_sigma2);
    cumulative.push_back(sum);
    usable.push_back(k);
  }
  const auto count = static_cast<std::size_t>(std::lround(config_.replace_fraction * particles_.size()));
  std::vector<std::size_t> order(particles_.size());
  std::iota(order.begin(), order.end(), 0);
  std::partial_sort(order.begin(), order.begin() + static_cast<long>(count), order.end(),
                    [&](std::size_t a, std::size_t b) { return weights_[a] < weights_[b]; });
  std::normal_distribution<double> n(0.0, 1.0);
  for (std::size_t r = 0; r < count; ++r) {
    // From the observation's best ICP fit (pattern_matcher.hpp): its current position, and the
    // frame heading it implies.
    const PseudoObservation& o = observations[usable[draw_index(cumulative, rng)]];
    Particle& p = particles_[order[r]];
    const Vec2 centre = walls_[o.floor]->crosses(o.position, o.fitted_position) ? o.position : o.fitted_position;
    p.position = centre;
    for (int attempt = 0; attempt < 5; ++attempt) {
      const Vec2 at = centre + config_.replace_position_sigma_m * Vec2(n(rng), n(rng));
      if (!walls_[o.floor]->crosses(centre, at)) {
        p.position = at;
        break;
      }
    }
    p.floor = o.floor;
    p.z = plan_.floors[o.floor].elevation_m;
    p.heading = wrap_angle(o.frame_heading + config_.replace_heading_sigma_deg * kDeg * n(rng));
    p.from_entry = false;  // drawn from a pattern: where its walk began is unknown
    weights_[order[r]] = 1.0 / static_cast<double>(particles_.size());
  }
  total = std::accumulate(weights_.begin(), weights_.end(), 0.0);
  for (double& w : weights_) w /= total;
  refresh_flags();
}

MapEstimate MapParticleFilter::estimate() const {
  MapEstimate e;
  if (particles_.empty()) return e;
  std::vector<double> per_floor(plan_.floors.size(), 0.0);
  for (std::size_t i = 0; i < particles_.size(); ++i) per_floor[particles_[i].floor] += weights_[i];
  e.floor = static_cast<std::size_t>(std::max_element(per_floor.begin(), per_floor.end()) - per_floor.begin());
  e.floor_probability = per_floor[e.floor];
  Vec2 mean = Vec2::Zero();
  Vec2 heading = Vec2::Zero();
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    if (particles_[i].floor != e.floor) continue;
    mean += weights_[i] * particles_[i].position;
    heading += weights_[i] * Vec2(std::cos(particles_[i].heading), std::sin(particles_[i].heading));
  }
  mean /= e.floor_probability;
  e.frame_heading = std::atan2(heading.y(), heading.x());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    if (particles_[i].floor != e.floor) continue;
    const Vec2 d = particles_[i].position - mean;
    cov += weights_[i] * d * d.transpose();
  }
  cov /= e.floor_probability;
  e.position = mean;
  e.covariance = cov;
  e.variance_m2 = cov.trace();
  e.concentrated = map_error_.concentrated();
  e.map_error_suspected = map_error_.up();
  e.map_error_since_start = map_error_.since_start();
  for (std::size_t i = 0; i < particles_.size(); ++i) e.entry_lineage += particles_[i].from_entry ? weights_[i] : 0.0;
  e.converged = e.concentrated && (!walked_in_ || e.entry_lineage >= config_.converged_entry_share);
  if (!e.converged) {
    // Where it might be instead: the places holding at least 1 % each, if at most 4 of them hold
    // 95 % of the weight (a cloud still spread over the plan has no candidates).
    std::vector<Place> places = cloud_places(particles_, weights_);
    double held = 0.0;
    std::size_t n = 0;
    while (n < places.size() && n < kMaxCandidates && places[n].weight >= kCandidateLeast) held += places[n++].weight;
    if (held >= kCandidatesHold) {
      places.resize(n);
      e.candidates = std::move(places);
      e.ambiguous = e.candidates.size() >= 2 &&
                    std::all_of(e.candidates.begin(), e.candidates.end(),
                                [&](const Place& p) { return p.covariance.trace() < config_.converged_variance_m2; });
    }
  }
  e.confirmed = e.converged && !e.map_error_since_start && e.entry_lineage >= config_.confirm_entry_share &&
                converged_steps_ >= config_.confirm_after_steps;
  return e;
}

void MapParticleFilter::refresh_flags(double removed_weight) {
  // Position variance over all particles (a split across floors is not converged).
  Vec2 mean = Vec2::Zero();
  for (std::size_t i = 0; i < particles_.size(); ++i) mean += weights_[i] * particles_[i].position;
  double var = 0.0;
  std::size_t floor0 = particles_.empty() ? 0 : particles_[0].floor;
  double off_floor = 0.0;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    var += weights_[i] * (particles_[i].position - mean).squaredNorm();
    if (particles_[i].floor != floor0) off_floor += weights_[i];
  }
  map_error_.refresh({var, off_floor >= 0.05 && off_floor <= 0.95, removed_weight});
}

}  // namespace sarloc::firefighter
