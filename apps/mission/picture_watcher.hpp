#pragma once
// sarloc-mission's view of the incident picture, as a late-joining dashboard sees it: the fused
// victims (disposed ones dropped), each responder's link, every alarm the picture held, and who
// publishes it (the participant whose IncidentSummary arrives: exclusive ownership delivers
// only the active instance's; NodeStatus names the participants).
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "sarloc/core/incident/alarm_board.hpp"
#include "sarloc/core/incident/fused_victim.hpp"
#include "sarloc/core/incident/team_status.hpp"
#include "sarloc/dds/participant.hpp"
#include "sarloc/dds/reader.hpp"

namespace sarloc::app {

class PictureWatcher {
 public:
  using TimePoint = std::chrono::steady_clock::time_point;
  struct Publisher {
    std::string participant;  ///< GUID prefix (24 hex digits); empty: none heard yet
    std::string node_id;      ///< its NodeStatus's node id, if heard
    TimePoint since{}, heard{};
  };

  explicit PictureWatcher(std::shared_ptr<dds::Participant> participant);

  std::vector<incident::FusedVictim> victims() const;
  std::map<std::string, incident::LinkState> links() const;
  std::vector<incident::IncidentAlarm> alarms() const;  ///< every alarm the picture held, by id
  Publisher publisher() const;
  /// The participant of incident-command node `node_id` ("" if its status was not heard).
  std::string participant_of(const std::string& node_id) const;
  /// A picture was heard within `lease` (its writers' liveliness lease).
  bool available(TimePoint now, std::chrono::seconds lease = std::chrono::seconds(3)) const;
  /// Every one of `responders` is signed off in the picture.
  bool signed_off(const std::vector<std::string>& responders) const;

 private:
  mutable std::mutex mutex_;
  std::map<std::uint32_t, incident::FusedVictim> victims_;
  std::vector<std::pair<eprosima::fastrtps::rtps::InstanceHandle_t, std::uint32_t>> instances_;
  std::map<std::string, incident::LinkState> links_;
  std::map<std::uint32_t, incident::IncidentAlarm> alarms_;
  Publisher publisher_;
  std::map<std::string, std::string> node_of_participant_, participant_of_node_;

  std::shared_ptr<dds::Participant> participant_;
  std::unique_ptr<dds::Reader<::sarloc::FusedVictim>> victim_reader_;
  std::unique_ptr<dds::Reader<::sarloc::IncidentSummary>> summary_reader_;
  std::unique_ptr<dds::Reader<::sarloc::NodeStatus>> status_reader_;
  std::unique_ptr<dds::Reader<::sarloc::TeamStatus>> team_reader_;
  std::unique_ptr<dds::Reader<::sarloc::IncidentAlarm>> alarm_reader_;
};

}  // namespace sarloc::app
