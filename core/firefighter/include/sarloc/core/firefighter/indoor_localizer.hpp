#pragma once
// One firefighter's map-aided localization, step by step as the odometry arrives: the loop that
// FirefighterEvaluation runs over a recorded walk, for the live system. Each 2 Hz INS
// displacement moves the particle filter; every `compare_every_m` walked, the last d metres of
// the INS track are compared with the building's search patterns (restricted to the window ends
// the particles can use once the cloud has concentrated) and weigh the particles.
//
//   IndoorLocalizer loc(building, MapFilterConfig{}, seed);
//   loc.start_at(entry_position, floor, heading_of_ins_frame);   // or loc.start_unknown();
//   MapEstimate e = loc.step(ins_delta);                         // navigation frame, m
#include <memory>
#include <random>

#include "sarloc/core/firefighter/building_model.hpp"
#include "sarloc/core/firefighter/map_particle_filter.hpp"
#include "sarloc/core/firefighter/odometry_track.hpp"

namespace sarloc::firefighter {

class IndoorLocalizer {
 public:
  IndoorLocalizer(std::shared_ptr<const BuildingModel> building, MapFilterConfig config, std::uint64_t seed);

  /// Known start: around `position` on `floor`, the INS frame's map heading `frame_heading`
  /// (the filter's known_position_sigma_m and known_heading_sigma_deg apply).
  void start_at(const Vec2& position, std::size_t floor, double frame_heading);
  /// A start near a place someone else told (MapParticleFilter::init_near): its own spreads,
  /// never confirmed. Again after a start, it starts over from there (the INS track is kept).
  void start_near(const Vec2& position, std::size_t floor, double frame_heading, double position_sigma_m,
                  double heading_sigma_deg);
  /// Unknown start: anywhere on the plan, any heading; a walk that came in began near a door
  /// more likely (MapParticleFilter::init_unknown).
  void start_unknown(UnknownStart start = UnknownStart::kWalkedIn);
  bool started() const { return started_; }

  /// One odometry step (INS displacement in its navigation frame, m). Throws InputError for a
  /// non-finite displacement (the filter is left untouched) or before a start.
  MapEstimate step(const Eigen::Vector3d& delta);

  /// Odometry was lost over an interval in which the firefighter may have moved about
  /// `position_sigma_m` (MapParticleFilter::diffuse). The INS track keeps its gap: the
  /// comparisons see the walk without it.
  void lost_motion(double position_sigma_m);

  MapEstimate estimate() const { return filter_.estimate(); }
  double walked_m() const { return track_.walked_m(); }
  std::size_t comparisons() const { return comparisons_; }
  std::size_t particle_count() const { return filter_.particles().size(); }
  const BuildingModel& building() const { return *building_; }

 private:
  std::shared_ptr<const BuildingModel> building_;
  MapParticleFilter filter_;
  OdometryTrack track_;
  std::mt19937_64 rng_;
  Eigen::Vector3d ins_position_ = Eigen::Vector3d::Zero();
  bool started_ = false;
  std::size_t comparisons_ = 0;
};

}  // namespace sarloc::firefighter
