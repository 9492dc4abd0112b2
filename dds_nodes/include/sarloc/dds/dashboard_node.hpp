#pragma once
// The DDS side of sarloc-dashboard: reads the incident picture (fused victims, teams, alarms,
// the picture summary) and, for detail, responders' positions and guidance; converts each to
// the core's types and hands it to the dashboard's sink; publishes an operator's alarm
// acknowledgement and a victim dug out. Listener threads only convert and call the sink (which must be quick).
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "sarloc/core/incident/alarm_board.hpp"
#include "sarloc/core/incident/fused_victim.hpp"
#include "sarloc/core/incident/search_plan.hpp"
#include "sarloc/core/incident/team_status.hpp"
#include "sarloc/core/responder/guidance.hpp"
#include "sarloc/core/responder/responder_candidates.hpp"
#include "sarloc/core/responder/responder_position.hpp"
#include "sarloc/dds/participant.hpp"

namespace sarloc::dds {

struct DashboardSink {
  std::function<void(const incident::FusedVictim&)> on_victim;
  std::function<void(std::uint32_t victim_id)> on_victim_gone;  ///< disposed: merged into another
  std::function<void(const incident::TeamStatus&)> on_team;
  std::function<void(const incident::IncidentAlarm&)> on_alarm;
  std::function<void(std::uint32_t alarm_id)> on_alarm_gone;  ///< acknowledged, and cleared or superseded
  std::function<void(const responder::ResponderPosition&)> on_position;
  std::function<void(const responder::ResponderCandidates&)> on_candidates;
  std::function<void(const responder::Guidance&)> on_guidance;
  std::function<void(const incident::SearchPlanPicture&)> on_search_plan;
  /// The incident picture heard from a participant (first 24 hex digits of its writer's GUID).
  std::function<void(const std::string& participant)> on_picture_writer;
  /// A sample that does not convert (named by topic): counted, never shown.
  std::function<void(const std::string& topic)> on_rejected;
};

class DashboardNode {
 public:
  DashboardNode(std::shared_ptr<Participant> participant, DashboardSink sink);
  ~DashboardNode();
  DashboardNode(const DashboardNode&) = delete;
  DashboardNode& operator=(const DashboardNode&) = delete;

  /// Publishes an AlarmAcknowledgement (incident command applies it and records it in the
  /// picture); false when DDS refused the write.
  bool acknowledge(std::uint32_t alarm_id, const std::string& operator_id, TimestampNs stamp);
  /// Publishes a VictimRecovery: the operator reports a FOUND victim dug out (incident command
  /// keeps it as recovered); false when DDS refused the write.
  bool report_dug_out(std::uint32_t victim_id, const std::string& operator_id, TimestampNs stamp);
  /// Publishes the operator's DigOrder for `incident_id` (these victims first, in this order);
  /// false when DDS refused the write.
  bool set_dig_order(const std::string& incident_id, const std::vector<std::uint32_t>& victim_ids,
                     const std::string& operator_id, TimestampNs stamp);
  /// Publishes the operator's DepositDrawing for `incident_id` (incident frame); false when DDS
  /// refused the write or the outline has more points than the topic holds.
  bool draw_deposit(const std::string& incident_id, const std::vector<Eigen::Vector2d>& outline,
                    const std::string& operator_id, TimestampNs stamp);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sarloc::dds
