#include "sarloc/core/firefighter/indoor_localizer.hpp"

#include "sarloc/core/common/errors.hpp"

namespace sarloc::firefighter {

IndoorLocalizer::IndoorLocalizer(std::shared_ptr<const BuildingModel> building, MapFilterConfig config,
                                 std::uint64_t seed)
    : building_((building ? void() : throw ConfigError("IndoorLocalizer: no building"), std::move(building))),
      filter_(building_->plan(), building_->grid(), std::move(config)),
      track_(building_->config().pattern),
      rng_(seed) {}

void IndoorLocalizer::start_at(const Vec2& position, std::size_t floor, double frame_heading) {
  if (!position.allFinite() || !std::isfinite(frame_heading)) throw InputError("start: position or heading not finite");
  if (floor >= building_->plan().floors.size()) {
    throw InputError("start: floor " + std::to_string(floor) + " not in the plan");
  }
  filter_.init_known(position, floor, frame_heading, rng_);
  track_.add(ins_position_);
  started_ = true;
}

void IndoorLocalizer::start_near(const Vec2& position, std::size_t floor, double frame_heading, double position_sigma_m,
                                 double heading_sigma_deg) {
  if (!position.allFinite() || !std::isfinite(frame_heading)) throw InputError("start: position or heading not finite");
  if (floor >= building_->plan().floors.size()) {
    throw InputError("start: floor " + std::to_string(floor) + " not in the plan");
  }
  if (!(position_sigma_m > 0.0 && position_sigma_m < 1e3 && heading_sigma_deg > 0.0 && heading_sigma_deg <= 180.0)) {
    throw InputError("start: spreads must be positive");
  }
  filter_.init_near(position, floor, frame_heading, position_sigma_m, heading_sigma_deg, rng_);
  if (!started_) track_.add(ins_position_);
  started_ = true;
}

void IndoorLocalizer::start_unknown(UnknownStart start) {
  filter_.init_unknown(rng_, start);
  track_.add(ins_position_);
  started_ = true;
}

void IndoorLocalizer::lost_motion(double position_sigma_m) {
  if (!started_) throw InputError("lost motion before the localizer was started");
  filter_.diffuse(position_sigma_m, rng_);
}

MapEstimate IndoorLocalizer::step(const Eigen::Vector3d& delta) {
  if (!started_) throw InputError("odometry before the localizer was started");
  if (!delta.allFinite()) throw InputError("odometry delta: not finite");
  filter_.predict(delta, rng_);
  ins_position_ += delta;
  track_.add(ins_position_);
  if (track_.comparison_due() && filter_.config().pseudo_observations) {
    const PatternMatcher& matcher = building_->matcher();
    const std::vector<Vec2> trajectory = track_.recent();
    const std::optional<EndMask> ends = filter_.observation_ends(matcher);
    std::vector<PseudoObservation> observations;
    if (!ends) {
      observations = matcher.compare(trajectory);
    } else if (matcher.windows_touching(*ends) > 0) {
      observations = matcher.compare(trajectory, &*ends);
    }
    filter_.update(observations, track_.walk_heading(), rng_);
    track_.compared();
    ++comparisons_;
  } else if (track_.comparison_due()) {
    track_.compared();
  }
  return filter_.estimate();
}

}  // namespace sarloc::firefighter
