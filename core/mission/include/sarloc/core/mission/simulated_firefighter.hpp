#pragma once
// One simulated firefighter of a building mission: the truth of its walk and its boot IMU's
// samples. The team's two members walk one directional search (firefighter::
// generate_search_walk from the team's entry with its hand, drawn from the team's seed, so both
// members' processes draw the same walk): member 0 leads, member 1 follows. The boot powers up
// at the entry 10 s before the search starts at `enter_at_s` (the INS aligns), and a scripted
// stop of `stop_s` at `stop_at_s` makes a motionless firefighter. Samples come from the real
// boot model with MTi-3-class errors (foot_trajectory.hpp, imu_error_model.hpp).
//
//   SimulatedFirefighter sim(world_plan, spec, team_seed, member_seed);
//   while (auto s = sim.next_sample()) device.push(*s);   // t: s since mission start
//   sim.truth(t);                                          // plan frame, floor
#include <memory>
#include <optional>
#include <random>
#include <string>

#include "sarloc/core/firefighter/foot_trajectory.hpp"
#include "sarloc/core/firefighter/imu_error_model.hpp"
#include "sarloc/core/firefighter/search_walk.hpp"

namespace sarloc::mission {

struct FirefighterSpec {
  std::string entry;             ///< the entry the team reports and goes in by ("": one drawn, unreported)
  firefighter::Hand hand = firefighter::Hand::kRight;
  unsigned member = 0;           ///< 0: leads the team's walk; 1: follows
  double enter_at_s = 0.0;       ///< mission second the search starts
  double search_s = 300.0;       ///< how long the search goes on
  double stop_at_s = -1.0;       ///< mission second of a scripted stop (< 0: none)
  double stop_s = 0.0;           ///< its length
  double mayday_at_s = -1.0;     ///< mission second the firefighter raises a mayday (< 0: none)
  double reset_at_s = -1.0;      ///< mission second the firefighter resets its alarms (< 0: never)
  void validate(const std::string& key) const;  ///< throws ConfigError naming `key`.<field>
};

class SimulatedFirefighter {
 public:
  SimulatedFirefighter(const firefighter::FloorPlan& world, const FirefighterSpec& spec, std::uint64_t team_seed,
                       std::uint64_t member_seed, firefighter::SearchWalkConfig walk = {});

  /// The next 100 Hz sample with the IMU's errors (t: mission seconds), nullopt at the end.
  std::optional<firefighter::ImuSample> next_sample();
  struct Truth {
    firefighter::Vec2 position;  ///< plan frame
    std::size_t floor = 0;
  };
  Truth truth(double t) const;
  double end_s() const { return foot_->end_time() + offset_s_; }
  /// Mission second the boot powers up (standing at the entry, `walk.standing_s` before entering).
  double power_up_s() const { return offset_s_; }
  /// When the scripted stop really began (the boot's touchdown at or after stop_at_s) and ended
  /// (the boot lifts again); nullopt without one.
  std::optional<std::pair<double, double>> stop() const { return stop_; }
  double distance_m() const { return firefighter::path_length(foot_->footfalls()); }

 private:
  std::unique_ptr<firefighter::FootTrajectory> foot_;
  std::vector<firefighter::ImuSample> samples_;
  std::size_t next_ = 0;
  std::mt19937_64 rng_;
  std::unique_ptr<firefighter::ImuErrors> errors_;
  std::optional<std::pair<double, double>> stop_;
  double offset_s_ = 0.0;  ///< mission time of the trajectory's t = 0
};

}  // namespace sarloc::mission
