#include "sarloc/core/mission/simulated_firefighter.hpp"

#include <cmath>
#include <sstream>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::mission {

void FirefighterSpec::validate(const std::string& key) const {
  require(member <= 1, key + ".member", member, "must be 0 (leads) or 1 (follows)");
  require(std::isfinite(enter_at_s) && enter_at_s >= 0.0 && enter_at_s <= 86400.0, key + ".enter_at_s", enter_at_s,
          "must be in [0, 86400]");
  require(std::isfinite(search_s) && search_s >= 30.0 && search_s <= 86400.0, key + ".search_s", search_s,
          "must be in [30, 86400]");
  require(std::isfinite(stop_at_s) && stop_at_s <= 86400.0, key + ".stop_at_s", stop_at_s,
          "must be finite, at most 86400");
  require(std::isfinite(stop_s) && stop_s >= 0.0 && stop_s <= 3600.0, key + ".stop_s", stop_s, "must be in [0, 3600]");
  require(!(stop_at_s >= 0.0 && stop_s <= 0.0), key + ".stop_s", stop_s, "must be > 0 with a stop_at_s");
  require(std::isfinite(mayday_at_s) && mayday_at_s <= 86400.0, key + ".mayday_at_s", mayday_at_s,
          "must be finite, at most 86400");
  require(std::isfinite(reset_at_s) && reset_at_s <= 86400.0, key + ".reset_at_s", reset_at_s,
          "must be finite, at most 86400");
}

SimulatedFirefighter::SimulatedFirefighter(const firefighter::FloorPlan& world, const FirefighterSpec& spec,
                                           std::uint64_t team_seed, std::uint64_t member_seed,
                                           firefighter::SearchWalkConfig walk)
    : rng_(member_seed) {
  spec.validate("firefighter");
  walk.duration_s = spec.search_s;
  // The boot powers up at the entry standing_s before the crew goes in (the INS aligns), at
  // mission second 0 at the earliest: the search starts at max(enter_at_s, standing_s).
  offset_s_ = std::max(0.0, spec.enter_at_s - walk.standing_s);
  walk.standing_s = std::max(spec.enter_at_s, walk.standing_s) - offset_s_;
  std::mt19937_64 team_rng(team_seed);
  // A team that reports no entry (the daemon then starts unknown) still goes in by one: drawn.
  const auto search = spec.entry.empty() ? firefighter::generate_search_walk(world, walk, spec.hand, team_rng)
                                         : firefighter::generate_search_walk(world, walk, spec.hand, spec.entry, team_rng);
  std::vector<firefighter::Footfall> feet = spec.member == 0 ? search.leader : search.follower;
  if (spec.stop_at_s >= 0.0) {
    // The first footfall landing at or after the stop: it stays down stop_s longer, and every
    // later one comes that much later.
    for (std::size_t k = 0; k < feet.size(); ++k) {
      if (feet[k].t_land + offset_s_ < spec.stop_at_s) continue;
      const double lifts = feet[k].t_land + feet[k].stance_s + spec.stop_s;
      feet[k].stance_s += spec.stop_s;
      for (std::size_t j = k + 1; j < feet.size(); ++j) feet[j].t_land += spec.stop_s;
      // Still from that touchdown (the boot's; a PASS counts from there) until the foot lifts.
      stop_ = std::make_pair(feet[k].t_land + offset_s_, lifts + offset_s_);
      break;
    }
  }
  foot_ = std::make_unique<firefighter::FootTrajectory>(std::move(feet));
  samples_ = foot_->imu_samples(100.0);
  errors_ = std::make_unique<firefighter::ImuErrors>(firefighter::ImuErrorConfig{}, rng_);
}

std::optional<firefighter::ImuSample> SimulatedFirefighter::next_sample() {
  if (next_ >= samples_.size()) return std::nullopt;
  firefighter::ImuSample s = errors_->apply(samples_[next_++], rng_);
  s.t += offset_s_;
  return s;
}

SimulatedFirefighter::Truth SimulatedFirefighter::truth(double t) const {
  const auto state = foot_->at(t - offset_s_);
  return Truth{state.position.head<2>(), state.floor};
}

}  // namespace sarloc::mission
