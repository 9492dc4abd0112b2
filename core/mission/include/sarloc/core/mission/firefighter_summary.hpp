#pragma once
// What one simulated firefighter's device reports at the end of a building mission (its
// --summary JSON, read by sarloc-mission): the daemon's map-aided positions it received scored
// against the truth of its walk, and its alarms with their delays from the true events.
//
//   FirefighterScore score("ff1", "alpha", enter_at_s);
//   score.on_fix(t, fix, truth_xy, truth_floor);           // every map-aided position received
//   score.on_alarm(alarm_change);                          // every alarm raised or cleared
//   FirefighterDeviceSummary s = score.summary(...);
#include <optional>
#include <string>
#include <vector>

#include "sarloc/core/firefighter/floor_plan.hpp"
#include "sarloc/core/responder/alarm.hpp"
#include "sarloc/core/responder/responder_position.hpp"

namespace sarloc::mission {

struct FirefighterAlarmRecord {
  std::string kind;                     ///< responder::to_string(AlarmKind)
  double raised_s = 0.0;                ///< mission seconds
  std::optional<double> cleared_s;
  /// Motionless: when the firefighter had stood still for the alarm's time (the true event);
  /// delay_s = raised_s - that. Absent for an alarm without a scripted cause.
  std::optional<double> true_event_s, delay_s;
  std::optional<double> clear_delay_s;  ///< cleared_s - the truly moving again
};

struct FirefighterDeviceSummary {
  std::string responder_id;
  std::string team;
  double enter_at_s = 0.0;
  std::size_t fixes = 0;                       ///< map-aided positions received
  std::optional<double> converged_at_s;        ///< the first converged one after entering (mission s)
  std::optional<double> time_to_converge_s;    ///< converged_at_s - enter_at_s
  std::optional<double> rmse_after_convergence_m;  ///< horizontal, every fix from converged_at_s on
  std::size_t wrong_floor = 0;                 ///< fixes after convergence on another floor than the truth
  double map_error_share = 0.0;                ///< of the fixes, flagged map-error-suspected
  double confirmed_share = 0.0;                ///< of the fixes, confirmed
  std::size_t confirmed_outside_99 = 0;        ///< confirmed fixes whose truth was outside their 99 % ellipse
  double distance_walked_m = 0.0;
  double dead_reckoning_s = 0.0;               ///< mission seconds the device was on its own
  /// The device's own positions (dead reckoning from its anchor, once a mission second: what
  /// incident command has of him while the daemon is down or not yet sure): how many, the
  /// largest horizontal error, and how many had the truth outside their 99 % ellipse.
  std::size_t own_positions = 0;
  std::optional<double> own_max_error_m;
  std::size_t own_outside_99 = 0;
  std::vector<std::int32_t> floors_visited;    ///< by the truth, in order of first visit
  std::vector<std::int32_t> floors_reported;   ///< by the daemon's fixes, in order of first report
  std::vector<FirefighterAlarmRecord> alarms;
};

class FirefighterScore {
 public:
  FirefighterScore(std::string responder_id, std::string team, double enter_at_s);
  /// A map-aided position at mission second `t` (incident frame) and the truth then.
  void on_fix(double t, const responder::ResponderPosition& fix, const firefighter::Vec2& truth, std::int32_t truth_floor);
  /// A map-aided position received on a recorded walk, which has no truth: counted, its flags
  /// and floor noted, nothing scored.
  void on_fix_without_truth(double t, const responder::ResponderPosition& fix);
  /// An alarm raised or cleared (mission seconds from its stamps with `epoch`).
  void on_alarm(const responder::ResponderAlarm& alarm, TimestampNs epoch);
  void add_dead_reckoning(double seconds) { summary_.dead_reckoning_s += seconds; }
  /// The device's own position (dead reckoning), published at mission second `t`, and the truth.
  void on_own_position(const responder::ResponderPosition& own, const firefighter::Vec2& truth);
  /// `stop`: the scripted stop's true start and end (mission s), `motionless_after_s` the alarm's time.
  FirefighterDeviceSummary summary(double distance_walked_m, const std::optional<std::pair<double, double>>& stop,
                                   double motionless_after_s) const;

 private:
  FirefighterDeviceSummary summary_;
  double sum_sq_ = 0.0;
  std::size_t after_ = 0, map_error_ = 0, confirmed_ = 0;
};

}  // namespace sarloc::mission
