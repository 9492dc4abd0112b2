#pragma once
// What a recording says about a mission, decoded once for the report: tracks, victims over
// time, events, data quality, and the truth when the recording comes from sarloc-mission
// (it embeds the mission file and the floor plan as metadata).
//
//   const MissionRecord record = load_mission_record("mission.mcap", on_progress);
//   if (!record.read.damage.empty()) ... // still usable: everything before the damage
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sarloc/core/common/gaussian.hpp"
#include "sarloc/core/common/types.hpp"
#include "sarloc/core/firefighter/floor_plan.hpp"
#include "sarloc/core/incident/deposit.hpp"
#include "sarloc/core/incident/fused_victim.hpp"
#include "sarloc/core/incident/search_plan.hpp"
#include "sarloc/core/responder/responder_position.hpp"
#include "sarloc/recording/mcap_reader.hpp"

namespace sarloc::report {

struct PositionSample {
  double t_s = 0.0;  ///< mission seconds
  GaussianPosition position;
  std::int32_t floor = 0;
  responder::PositionSource source = responder::PositionSource::kGnss;
  bool converged = false;
  bool confirmed = false;
  bool map_error_suspected = false;
};

struct ResponderTrack {
  std::string id;
  std::string team;
  bool firefighter = false;  ///< from the mission file, else from its position sources
  std::vector<PositionSample> samples;
};

struct VictimSample {
  double t_s = 0.0;
  GaussianPosition position;
  incident::VictimState state = incident::VictimState::kUnconfirmed;
};

struct VictimHistory {
  std::uint32_t id = 0;
  std::vector<VictimSample> samples;
  std::optional<double> located_s, found_s;
  std::vector<std::string> sources;  ///< rescuer/signal, every one ever heard
  bool evidence_conflict = false;
};

struct Event {
  double t_s = 0.0;
  std::string kind;  ///< "victim", "link", "accountability", "alarm", "map error", "daemon", "command"
  std::string text;
};

struct TruthVictim {
  std::string name;
  Vec3 position = Vec3::Zero();
};

/// The building as placed in the incident frame (mission file's building: origin, rotation).
struct PlacedBuilding {
  firefighter::FloorPlan plan;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  double rotation_rad = 0.0;
  Eigen::Vector2d to_incident(const Eigen::Vector2d& p) const;
};

struct TopicQuality {
  std::uint64_t recorded = 0;      ///< messages in the file
  std::uint64_t undecodable = 0;   ///< in the file but not decodable (counted, skipped)
  std::uint64_t received = 0, written = 0, lost = 0;  ///< the recorder's counters
  std::map<std::string, std::uint64_t> rejected;
};

struct MissionRecord {
  std::string path;
  recording::McapReadResult read;
  std::map<std::string, std::string> recording_metadata;  ///< "sarloc.recording"
  std::string mission_name;
  std::int64_t epoch_ns = 0;  ///< mission time 0 (from the metadata; else the first message)
  double speedup = 1.0;
  double duration_s = 0.0;    ///< mission seconds from epoch to the last message

  std::map<std::string, ResponderTrack> responders;
  std::map<std::uint32_t, VictimHistory> victims;
  std::vector<Event> events;  ///< sorted by time
  std::vector<TruthVictim> truth_victims;
  std::optional<PlacedBuilding> building;
  /// The incident frame's WGS-84 origin, as incident command last published it (IncidentFrame),
  /// else as the recorded mission file gives it.
  std::optional<GeodeticOrigin> incident_origin;
  /// The avalanche deposit (incident frame), from the recorded mission file's incident.deposit.
  std::optional<incident::Deposit> deposit;
  /// Incident command's search plan as last recorded (strips, coverage, hand-overs, dig order).
  std::optional<incident::SearchPlanPicture> search_plan;
  std::vector<std::string> notes;  ///< what the report could not do, and why
  std::map<std::string, TopicQuality> quality;
  /// Node id -> reject reason -> count, as each node last reported (NodeStatus).
  std::map<std::string, std::map<std::string, std::uint64_t>> node_rejects;
};

/// Throws recording::RecordingError when the file cannot be opened or is not MCAP. A damaged
/// file gives what could be read (record.read.damage says what could not).
MissionRecord load_mission_record(const std::string& path,
                                  const std::function<void(std::uint64_t, std::uint64_t)>& on_progress = {});

}  // namespace sarloc::report
