#include "firefighter_crew.hpp"

#include <algorithm>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/seeds.hpp"
#include "sarloc/core/estimator/firefighter_device.hpp"
#include "sarloc/core/mission/simulated_firefighter.hpp"

namespace sarloc::bench {
namespace {

// A team goes in at 10 s at the earliest (its boots align standing at the entry before), and
// the teams one after another: the daemon admits 10 new responders a second
// (core.new_rescuers_per_s), and a crew does not enter a building all in one second.
constexpr double kFirstEntryS = 10.0;
constexpr double kEntrySpacingS = 0.4;
// Walks simulated; further members repeat one of them (entry, hand and place in the team alike)
// under their own id, shifted to their own entry time: the daemon's work per step is the same,
// and 200 ten-minute walks would take the load generator minutes to make.
constexpr std::size_t kDistinctWalks = 40;  // even: a repeat keeps its place in the team
static_assert(kDistinctWalks % 2 == 0);

}  // namespace

FirefighterCrew::FirefighterCrew(const app::MissionConfig& mission, std::size_t n, double search_s,
                                 std::uint64_t seed) {
  if (n == 0) return;
  if (!mission.world || mission.world->entries.empty()) {
    throw ConfigError("--firefighters " + std::to_string(n) + ": the mission has no building: section with entries");
  }
  const auto& entries = mission.world->entries;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t team = i / 2;
    app::FirefighterEntry ff;
    ff.id = "ff-" + std::to_string(i);
    ff.team = "crew-" + std::to_string(team);
    ff.spec.entry = entries[team % entries.size()].id;
    ff.spec.hand = (team / entries.size()) % 2 == 0 ? firefighter::Hand::kRight : firefighter::Hand::kLeft;
    ff.spec.member = static_cast<unsigned>(i % 2);
    ff.spec.enter_at_s = kFirstEntryS + kEntrySpacingS * static_cast<double>(team);
    ff.spec.search_s = search_s;
    members_.push_back(ff);
  }
  const std::size_t distinct = std::min(members_.size(), kDistinctWalks);
  // A repeat goes in where its walk does (the daemon's filter starts at the reported entry).
  for (std::size_t m = distinct; m < members_.size(); ++m) {
    members_[m].spec.entry = members_[m % distinct].spec.entry;
    members_[m].spec.hand = members_[m % distinct].spec.hand;
  }
  std::vector<std::vector<Step>> walked(distinct);
  for (std::size_t m = 0; m < distinct; ++m) {
    const auto& ff = members_[m];
    const std::uint64_t team_seed = derive_seed(seed, 1000 + m / 2);
    mission::SimulatedFirefighter sim(*mission.world, ff.spec, team_seed, derive_seed(seed, 5000 + m));
    estimator::FirefighterDevice device(ff.id, ff.team, estimator::FirefighterDeviceConfig{}, 0);
    if (auto entry = estimator::entry_fix(*mission.world, mission.estimators.firefighter, ff.id, ff.team, ff.spec.entry,
                                          ff.spec.hand)) {
      device.start_at(*entry);  // as the device's loop
    }
    while (auto sample = sim.next_sample()) {
      device.push(*sample);
      auto o = device.take_odometry();
      if (!o) continue;
      walked[m].push_back(Step{1e-9 * static_cast<double>(o->interval_end), *o, device.take_own_position()});
    }
  }
  for (std::size_t m = 0; m < members_.size(); ++m) {
    const std::size_t source = m % distinct;
    const auto shift_ns =
        static_cast<TimestampNs>(1e9 * (members_[m].spec.enter_at_s - members_[source].spec.enter_at_s));
    for (auto step : walked[source]) {
      step.odometry.rescuer_id = members_[m].id;
      step.odometry.interval_start += shift_ns;
      step.odometry.interval_end += shift_ns;
      step.at_s = 1e-9 * static_cast<double>(step.odometry.interval_end);
      if (step.reckoning) {
        step.reckoning->responder_id = members_[m].id;
        step.reckoning->team_id = members_[m].team;
        step.reckoning->stamp += shift_ns;
      }
      schedule_.push_back(std::move(step));
    }
  }
  std::stable_sort(schedule_.begin(), schedule_.end(), [](const Step& a, const Step& b) { return a.at_s < b.at_s; });
}

void FirefighterCrew::write_roster(YAML::Node& rescuers) const {
  for (const auto& ff : members_) {
    YAML::Node n;
    n["id"] = ff.id;
    n["team"] = ff.team;
    n["role"] = "firefighter";
    n["entry"] = ff.spec.entry;
    n["hand"] = ff.spec.hand == firefighter::Hand::kRight ? "right" : "left";
    n["member"] = ff.spec.member;
    n["enter_at_s"] = ff.spec.enter_at_s;
    n["search_s"] = ff.spec.search_s;
    rescuers.push_back(n);
  }
}

}  // namespace sarloc::bench
