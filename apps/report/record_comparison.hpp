#pragma once
// How one recording's outcome differs from another's (the same inputs, replayed with another
// configuration or another build): victims paired by their final estimates, and the map-aided
// tracks compared at the same stamps. docs/operations/recording.md defines "reproduces" with it.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "mission_record.hpp"

namespace sarloc::report {

struct VictimPair {
  std::uint32_t here = 0;
  std::uint32_t there = 0;  ///< 0: nothing there within reach
  double distance_m = 0.0;  ///< between the final estimates
  incident::VictimState state_here = incident::VictimState::kUnconfirmed;
  incident::VictimState state_there = incident::VictimState::kUnconfirmed;
  std::optional<double> found_here_s, found_there_s;
  double radius_here_m = 0.0, radius_there_m = 0.0;
};

struct TrackDifference {
  std::string responder;
  std::size_t matched = 0;  ///< map-aided fixes with the same stamp in both
  double rms_m = 0.0;
  double max_m = 0.0;
};

struct RecordComparison {
  std::vector<VictimPair> victims;          ///< one per victim here
  std::vector<std::uint32_t> only_there;    ///< victims confirmed there that no victim here paired with
  std::vector<TrackDifference> tracks;      ///< firefighters with map-aided fixes in both
};

RecordComparison compare_records(const MissionRecord& here, const MissionRecord& there);

/// The numeric meaning of "the replay reproduces the recording" (docs/operations/recording.md):
/// the same victims FOUND, each within `victim_tolerance_m` and `found_tolerance_s`, nothing
/// confirmed in one and not the other, and every firefighter's map-aided track within
/// `track_rms_tolerance_m` RMS. Empty when it does; otherwise what differs.
std::vector<std::string> reproduction_failures(const RecordComparison& comparison, double victim_tolerance_m = 0.5,
                                               double found_tolerance_s = 5.0, double track_rms_tolerance_m = 0.5);

}  // namespace sarloc::report
