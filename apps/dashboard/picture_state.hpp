#pragma once
// What the dashboard shows, kept up to date from DDS samples (or a recording) and served as
// JSON: a full snapshot for a page that opens, and deltas (what changed since a version) for
// the live stream. Thread-safe: DDS listener threads feed it, HTTP threads read it.
//
// Times shown to people are mission seconds (the clock given to it); link freshness, the PAR
// timers and the "no data" banner go by the wall clock, like the people watching.
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "sarloc/core/firefighter/floor_plan.hpp"
#include "sarloc/core/incident/alarm_board.hpp"
#include "sarloc/core/incident/fused_victim.hpp"
#include "sarloc/core/incident/geodetic_frame.hpp"
#include "sarloc/core/incident/picture_events.hpp"
#include "sarloc/core/incident/search_plan.hpp"
#include "sarloc/core/incident/team_status.hpp"
#include "sarloc/core/responder/guidance.hpp"
#include "sarloc/core/responder/responder_candidates.hpp"
#include "sarloc/core/responder/responder_position.hpp"

namespace sarloc::dashboard {

struct PictureStateConfig {
  /// Recent positions kept per responder for its track on the map.
  std::size_t track_length = 120;
  /// Events kept for the log.
  std::size_t event_log_length = 500;
  /// A personnel accountability report (PAR) is due this long after the last one (wall s).
  double par_interval_s = 600.0;
  /// The "no data" banner after this long without any DDS sample (wall s).
  double stale_after_s = 5.0;

  /// Throws ConfigError naming the key (the dashboard: section's, or picture_state.<key>).
  void validate() const;
};

/// A building plan placed in the incident frame (the mission's building: section).
struct PlacedPlan {
  firefighter::FloorPlan plan;
  double origin_x = 0.0, origin_y = 0.0, rotation_rad = 0.0;
};

class PictureState {
 public:
  using WallClock = std::function<double()>;         ///< wall seconds
  using MissionClock = std::function<TimestampNs()>;  ///< mission time now

  /// `epoch_ns`: mission time 0, from which the page counts (T+ mm:ss).
  PictureState(PictureStateConfig config, MissionClock mission_now, TimestampNs epoch_ns, WallClock wall_now = {});

  void set_building(PlacedPlan building);
  /// The incident frame's WGS-84 origin: victims then carry their latitude and longitude.
  void set_geodetic_origin(const GeodeticOrigin& origin);
  /// The avalanche deposit's outline (incident frame), drawn under everything else.
  void set_deposit(const std::vector<Eigen::Vector2d>& outline);

  void on_victim(const incident::FusedVictim& v);
  void on_victim_gone(std::uint32_t id);
  void on_team(const incident::TeamStatus& t);
  void on_alarm(const incident::IncidentAlarm& a);
  void on_alarm_gone(std::uint32_t id);
  void on_position(const responder::ResponderPosition& p);
  /// The places of an ambiguous map-aided position: drawn instead of its mean while the newest
  /// position is flagged ambiguous and they are of about its time (within 5 s).
  void on_candidates(const responder::ResponderCandidates& c);
  void on_guidance(const responder::Guidance& g);
  /// Incident command's primary-search plan: the strips on the map, shaded by what is searched.
  void on_search_plan(const incident::SearchPlanPicture& plan);
  void on_picture_writer(const std::string& participant);
  void on_rejected(const std::string& topic);
  /// An operator reported the team's PAR: its timer starts again. False for an unknown team.
  bool par_reported(const std::string& team_id, const std::string& operator_id);
  /// Something the operator did (acknowledged an alarm, ...), for the event log.
  void note(const std::string& kind, const std::string& text);

  /// Forgets the picture (not the building) to be filled again (a replay seeking back). Streams
  /// that had a version from before get a new snapshot (needs_snapshot).
  void reset();
  bool needs_snapshot(std::uint64_t since) const;
  /// Extra fields every snapshot and heartbeat carries (a replay's timeline).
  void set_extra(const std::string& key, nlohmann::json value);

  /// Everything, for a page that opens now.
  nlohmann::json snapshot() const;
  /// What changed since `version` (entities whose version is newer, ids removed since, and
  /// newer events); its "version" is the one to ask from next time. Responders come without
  /// their track: the page appends each new position to the track of the snapshot. If the
  /// picture was reset since `version`, a snapshot instead (its "type" says which).
  nlohmann::json delta(std::uint64_t version) const;
  /// Data age and the banner, once a second.
  nlohmann::json heartbeat() const;
  std::uint64_t version() const;
  std::size_t victim_count() const;
  /// The picture as GeoJSON in WGS-84 (app::to_geojson): the deposit, the tracks kept for the map
  /// (track_length positions each), the plan's strips and the victims. Nullopt without a WGS-84
  /// origin (set_geodetic_origin).
  std::optional<nlohmann::json> geojson() const;

 private:
  struct Versioned {
    nlohmann::json json;
    std::uint64_t version = 0;
  };
  struct Responder {
    responder::ResponderPosition last;
    std::deque<std::array<double, 2>> track;
    std::optional<double> guidance_heading_rad;
    std::uint64_t version = 0;
  };
  struct Team {
    incident::TeamStatus status;
    double par_due_wall_s = 0.0;
    std::uint64_t version = 0;
  };

  void touch_data();
  /// `stamp` 0: now.
  void event(const std::string& kind, const std::string& text, TimestampNs stamp = 0);
  void events(const std::vector<incident::PictureEvent>& changes);
  void store_deposit(const std::vector<Eigen::Vector2d>& outline);  ///< the caller holds mutex_
  nlohmann::json victim_json(const incident::FusedVictim& v) const;
  nlohmann::json responder_json(const std::string& id, const Responder& r, bool with_track) const;
  nlohmann::json team_json(const Team& t) const;
  nlohmann::json alarm_json(const incident::IncidentAlarm& a) const;
  nlohmann::json plan_json() const;
  nlohmann::json collect(std::uint64_t since, bool with_tracks) const;

  PictureStateConfig config_;
  MissionClock mission_now_;
  TimestampNs epoch_ns_;
  WallClock wall_now_;
  static constexpr std::size_t kRemovedKept = 4096;
  void note_removed(const char* kind, std::uint32_t id);
  /// A page that has seen `since` cannot be brought up to date by a delta.
  bool stale(std::uint64_t since) const { return since < reset_version_ || since < removed_floor_; }

  mutable std::mutex mutex_;
  std::uint64_t version_ = 0;
  std::uint64_t reset_version_ = 0;
  nlohmann::json extra_ = nlohmann::json::object();
  double last_data_wall_s_ = -1.0;
  std::map<std::uint32_t, std::pair<incident::FusedVictim, std::uint64_t>> victims_;
  std::map<std::string, Responder> responders_;
  /// The newest places of each ambiguous firefighter, apart: they may come before his position.
  std::map<std::string, responder::ResponderCandidates> candidates_;
  std::map<std::string, Team> teams_;
  std::map<std::uint32_t, std::pair<incident::IncidentAlarm, std::uint64_t>> alarms_;
  std::deque<std::pair<std::uint64_t, nlohmann::json>> events_;
  incident::PictureEvents picture_events_;  ///< what the samples changed, in words (as the report)
  /// Removals a page may not have seen yet, (version, (kind, id)): the newest kRemovedKept. A
  /// page older than the oldest dropped (removed_floor_) gets a snapshot instead of a delta.
  std::deque<std::pair<std::uint64_t, std::pair<std::string, std::string>>> removed_;
  std::uint64_t removed_floor_ = 0;
  std::string picture_writer_;
  std::map<std::string, std::uint64_t> rejected_;
  nlohmann::json building_;
  nlohmann::json deposit_ = nlohmann::json::array();  ///< [[x, y], ...] in the incident frame
  std::vector<Eigen::Vector2d> deposit_outline_;      ///< the same, for GeoJSON
  std::optional<incident::SearchPlanPicture> plan_;
  std::uint64_t plan_version_ = 0;
  std::optional<incident::GeodeticFrame> geodetic_;
};

}  // namespace sarloc::dashboard
