#pragma once
// Triage and dig order for FOUND victims (issue 63, item 4): which victim each free digging team
// takes, in which order, so that the most are expected to survive. A victim's survival is read
// off the avalanche survival curve at the moment it is dug out: time buried so far, plus the
// wait for a team, plus its dig time, which grows with depth.
//
// The survival curve (TriageConfig::survival_curve, minutes buried -> probability, linear between
// points, the last value beyond): Falk, Brugger, Adler-Kastner 1994 (Nature 368: 21) and Brugger
// et al. 2001 (Resuscitation 51: 7-15), Swiss data: 92 % dug out within 15 min, 30 % at 35 min,
// a plateau (air pocket) to 90 min at 27 %, 7 % at 130 min.
// Dig time: dig_min_per_m x depth + dig_min_per_m2 x depth^2 (shovelling a cone out of deposit
// grows faster than the depth), defaults 5 and 5: 1 m in 10 min, 2 m in 30 min. An assumption to
// be replaced by a team's own figures; configurable, not measured here.
//
// Order: list scheduling, each victim in turn to the team free first. With up to
// kExhaustiveVictims victims every order is tried and the one with the most expected survivors
// kept (ties: the earlier last dig-out); beyond, shortest dig first.
//
//   const DigPlan plan = plan_digs({{"v1", 1.2, 8.0}, {"v2", 0.4, 8.0}}, 1, TriageConfig{});
#include <string>
#include <utility>
#include <vector>

namespace sarloc::incident {

struct TriageConfig {
  std::vector<std::pair<double, double>> survival_curve{
      {0.0, 0.92}, {15.0, 0.92}, {35.0, 0.30}, {90.0, 0.27}, {130.0, 0.07}};
  double dig_min_per_m = 5.0;
  double dig_min_per_m2 = 5.0;
  /// Minutes the victims were buried before the search began (incident command's first cycle,
  /// a simulated mission's first second).
  double buried_before_start_min = 0.0;
  /// ConfigError naming triage.survival_curve (at least 2 points, minutes increasing from 0,
  /// probabilities in [0, 1] never rising), triage.dig_min_per_m / dig_min_per_m2 ([0, 120])
  /// or triage.buried_before_start_min ([0, 600]).
  void validate() const;
  double survival(double minutes_buried) const;
  double dig_minutes(double depth_m) const;
};

struct DigCandidate {
  std::string victim_id;
  double depth_m = 0.0;     ///< below the snow surface (the estimate's, >= 0)
  double buried_min = 0.0;  ///< minutes buried so far
};

struct Dig {
  std::string victim_id;
  std::size_t team = 0;    ///< 0-based digging team
  double start_min = 0.0;  ///< from now
  double done_min = 0.0;
  double survival = 0.0;  ///< the curve at buried_min + done_min
};

struct DigPlan {
  std::vector<Dig> digs;  ///< in dig order
  double expected_survivors = 0.0;
};

static constexpr std::size_t kExhaustiveVictims = 7;

/// InputError for no team, a negative or non-finite depth or time, or an empty or repeated id.
/// `first`: victims an operator wants dug first, in this order (ids not among `victims` are
/// skipped); the rest follow as planned.
DigPlan plan_digs(const std::vector<DigCandidate>& victims, std::size_t teams, const TriageConfig& config,
                  const std::vector<std::string>& first = {});

}  // namespace sarloc::incident
