#pragma once
// The firefighter's estimator: map-aided indoor localization (firefighter::IndoorLocalizer,
// seed 004) behind the ResponderEstimator interface. Its input is the boot INS's odometry
// (source ODOMETRY_FOOT_MOUNTED_INS, 2 Hz); every step answers with a ResponderPosition
// (POSITION_MAP_AIDED) in the incident frame: the filter's mean and covariance, the floor, and
// the converged / map-error-suspected / confirmed flags. It takes no sensor samples.
//
// Odometry of a boot INS, as the device publishes it (FirefighterDevice): the translation in
// the level frame whose x axis is the INS yaw at the interval's start, the yaw change in
// rotation_rpy.z (roll and pitch 0). Chained here into the estimator's own navigation frame,
// whose map heading the particles carry.
//
// Start: from the entry and search hand the team reports (the mission's `rescuers[].entry`
// and `.hand`), around the entry's position with `entry_position_sigma_m`, and around the
// heading the crew stands in while the boot INS aligns (turned from walking in to the wall it
// will follow: right for a right-hand search) with `entry_heading_sigma_deg`. The INS frame's
// x axis is the boot's heading at alignment, and without a compass (magnetometers are useless
// near steel) nothing else ties it to the building. With no entry given, or when the first
// odometry this estimator sees is not the device's first step (a daemon restarted mid-search),
// from an unknown state (anywhere, any heading); but when the device's own position is at hand
// (its dead reckoning, `hint_position`, within `hint_max_age_s` of the step), near it:
// `hint_sigma_scale` times its horizontal spread plus how far the firefighter may have walked
// between the two (at most `hint_max_sigma_m`, else it is no hint), the heading within
// `hint_heading_sigma_deg`, never confirmed. A hint that
// comes after such an unknown start, before it converged, starts it over near the hint.
// While the particles are in 2-4 compact places (MapEstimate::ambiguous), the position is flagged
// ambiguous and each step also answers with those places (ResponderCandidates); the step that
// ends the ambiguity answers once with none.
// A gap in the odometry (interval_start after the last interval_end: steps lost on the radio)
// spreads the particles by how far the firefighter may have walked in it (`max_speed_mps`).
#include <map>
#include <memory>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/estimator/responder_estimator.hpp"
#include "sarloc/core/firefighter/indoor_localizer.hpp"
#include "sarloc/core/firefighter/search_walk.hpp"

namespace sarloc::estimator {

struct FirefighterEstimatorConfig {
  /// The mission's building (null: no building, a firefighter cannot be served).
  std::shared_ptr<const firefighter::BuildingModel> building;
  /// Where the plan sits in the incident frame: p_incident = origin + Rz(rotation) p_plan; z is
  /// the floor's elevation.
  firefighter::Vec2 origin = firefighter::Vec2::Zero();
  double rotation_deg = 0.0;
  /// The plan's rotation into the incident frame (rad), and a plan point there (horizontal).
  double rotation_rad() const { return rotation_deg * kPi / 180.0; }
  firefighter::Vec2 to_incident(const firefighter::Vec2& plan_point) const {
    return origin + firefighter::rotate(plan_point, rotation_rad());
  }
  firefighter::MapFilterConfig filter;
  double entry_position_sigma_m = 0.5;  ///< where inside the door the crew starts
  double entry_heading_sigma_deg = 10.0;
  double max_speed_mps = 1.5;           ///< bounds a step and the spread after lost odometry
  /// Responder id -> the entry and hand its team reports (absent or no entry: unknown start).
  struct ReportedStart {
    std::string entry;
    firefighter::Hand hand = firefighter::Hand::kRight;
  };
  std::map<std::string, ReportedStart> entry_of;
  /// Mid-search starts from the device's dead reckoning (see the header comment).
  double hint_max_age_s = 10.0;
  double hint_sigma_scale = 1.0;
  double hint_heading_sigma_deg = 15.0;
  /// A hint whose start would spread wider than this (a device that has reckoned long, or was
  /// never anchored by a converged fix) is no start: the filter starts anywhere instead.
  double hint_max_sigma_m = 3.0;
  std::uint64_t seed = 1;

  /// Throws ConfigError naming the key ("firefighter.entry_position_sigma_m = 0: ...").
  void validate() const;
};

class FirefighterEstimator final : public ResponderEstimator {
 public:
  FirefighterEstimator(std::string responder_id, const FirefighterEstimatorConfig& config);

  ResponderRole role() const override { return ResponderRole::kFirefighter; }
  const std::string& responder_id() const override { return id_; }
  Outcome add_odometry(const responder::Odometry& odometry) override;
  bool add_unknown_motion(TimestampNs from, TimestampNs until) override;
  /// A firefighter has no sensor samples: every one is refused (kWrongRole).
  Outcome process(const SensorSample& sample) override;
  std::optional<responder::Guidance> coast(TimestampNs) override { return std::nullopt; }
  void mark_done(std::uint32_t) override {}
  void leave_to_others(std::set<std::uint32_t>, TimestampNs) override {}
  std::optional<responder::VictimEstimate> estimate_of(std::uint32_t) const override { return std::nullopt; }
  /// A device's dead reckoning (source kDeadReckoning) of this firefighter; anything else, or
  /// an older one, is ignored.
  void hint_position(const responder::ResponderPosition& own) override;
  std::size_t active_filters() const override { return 1; }

  const firefighter::IndoorLocalizer& localizer() const { return localizer_; }
  /// The entry it starts from, empty for an unknown start.
  const std::string& entry() const { return entry_; }
  /// An entry was reported but the first odometry came mid-search: started unknown or near a hint.
  bool started_mid_search() const { return started_mid_search_; }
  /// Started (or started over) near the device's dead reckoning.
  bool started_near_hint() const { return started_near_hint_; }

 private:
  responder::ResponderPosition position_at(TimestampNs stamp, const firefighter::MapEstimate& e) const;
  /// The candidates to publish with this step's position, if any (see the header comment).
  std::optional<responder::ResponderCandidates> candidates_at(TimestampNs stamp, const firefighter::MapEstimate& e);
  /// On the first odometry: from the entry if it is the device's first step, else near a fresh
  /// hint, else unknown.
  void start(std::uint64_t first_sequence, TimestampNs at);
  /// Starts (over) near the hint if it is fresh at `at`; false if it is not.
  bool start_near_hint(TimestampNs at);

  std::string id_;
  FirefighterEstimatorConfig config_;
  firefighter::IndoorLocalizer localizer_;
  std::string entry_;
  bool started_mid_search_ = false;
  bool started_near_hint_ = false;
  bool started_inside_unknown_ = false;  ///< kInside: a hint may still start it over
  bool ever_converged_ = false;
  std::optional<responder::ResponderPosition> hint_;
  double yaw_ = 0.0;  ///< INS yaw in the estimator's navigation frame
  std::optional<std::uint64_t> last_sequence_;
  TimestampNs last_end_ = 0;
  bool was_ambiguous_ = false;
};

}  // namespace sarloc::estimator
