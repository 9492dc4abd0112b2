#include "picture_watcher.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/dds/conversions.hpp"

namespace sarloc::app {

PictureWatcher::PictureWatcher(std::shared_ptr<dds::Participant> participant) : participant_(std::move(participant)) {
  dds::ReaderEvents victim_events;
  victim_events.on_instance_gone = [this](const auto& info) {
    // A disposed victim was merged into another: drop it from the picture.
    if (info.instance_state != eprosima::fastdds::dds::NOT_ALIVE_DISPOSED_INSTANCE_STATE) return;
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [handle, id] : instances_) {
      if (handle == info.instance_handle) victims_.erase(id);
    }
  };
  victim_reader_ = std::make_unique<dds::Reader<::sarloc::FusedVictim>>(
      participant_,
      [this](const ::sarloc::FusedVictim& v, const auto& info) {
        try {
          auto victim = dds::to_core(v);
          std::lock_guard<std::mutex> lock(mutex_);
          victims_[v.victim_id()] = std::move(victim);
          if (std::none_of(instances_.begin(), instances_.end(),
                           [&](const auto& k) { return k.first == info.instance_handle; })) {
            instances_.emplace_back(info.instance_handle, v.victim_id());
          }
        } catch (const InputError& e) {
          spdlog::warn("ignoring a fused victim: {}", e.what());
        }
      },
      dds::EndpointOptions{}, victim_events);
  summary_reader_ = std::make_unique<dds::Reader<::sarloc::IncidentSummary>>(
      participant_, [this](const ::sarloc::IncidentSummary&, const auto& info) {
        const std::string from = dds::handle_text(info.publication_handle).substr(0, 24);
        const auto now = std::chrono::steady_clock::now();
        std::lock_guard<std::mutex> lock(mutex_);
        if (from != publisher_.participant) {
          publisher_.participant = from;
          publisher_.since = now;
        }
        publisher_.heard = now;
      });
  status_reader_ = std::make_unique<dds::Reader<::sarloc::NodeStatus>>(
      participant_, [this](const ::sarloc::NodeStatus& n, const auto& info) {
        if (n.kind() != ::sarloc::NODE_COMMAND) return;
        const std::string from = dds::handle_text(info.publication_handle).substr(0, 24);
        std::lock_guard<std::mutex> lock(mutex_);
        node_of_participant_[from] = n.node_id().to_string();
        participant_of_node_[n.node_id().to_string()] = from;
      });
  team_reader_ = std::make_unique<dds::Reader<::sarloc::TeamStatus>>(
      participant_, [this](const ::sarloc::TeamStatus& t, const auto&) {
        try {
          const auto team = dds::to_core(t);
          std::lock_guard<std::mutex> lock(mutex_);
          for (const auto& m : team.members) links_[m.responder_id] = m.link;
        } catch (const InputError& e) {
          spdlog::warn("ignoring a team status: {}", e.what());
        }
      });
  alarm_reader_ = std::make_unique<dds::Reader<::sarloc::IncidentAlarm>>(
      participant_, [this](const ::sarloc::IncidentAlarm& a, const auto&) {
        try {
          auto alarm = dds::to_core(a);
          std::lock_guard<std::mutex> lock(mutex_);
          alarms_[alarm.alarm_id] = std::move(alarm);
        } catch (const InputError& e) {
          spdlog::warn("ignoring an incident alarm: {}", e.what());
        }
      });
}

std::vector<incident::FusedVictim> PictureWatcher::victims() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<incident::FusedVictim> out;
  for (const auto& [id, v] : victims_) out.push_back(v);
  return out;
}

std::map<std::string, incident::LinkState> PictureWatcher::links() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return links_;
}

std::vector<incident::IncidentAlarm> PictureWatcher::alarms() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<incident::IncidentAlarm> out;
  for (const auto& [id, a] : alarms_) out.push_back(a);
  return out;
}

PictureWatcher::Publisher PictureWatcher::publisher() const {
  std::lock_guard<std::mutex> lock(mutex_);
  Publisher p = publisher_;
  const auto it = node_of_participant_.find(p.participant);
  if (it != node_of_participant_.end()) p.node_id = it->second;
  return p;
}

std::string PictureWatcher::participant_of(const std::string& node_id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = participant_of_node_.find(node_id);
  return it == participant_of_node_.end() ? std::string() : it->second;
}

bool PictureWatcher::available(TimePoint now, std::chrono::seconds lease) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return !publisher_.participant.empty() && now - publisher_.heard < lease;
}

bool PictureWatcher::signed_off(const std::vector<std::string>& responders) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return std::all_of(responders.begin(), responders.end(), [&](const std::string& id) {
    const auto it = links_.find(id);
    return it != links_.end() && it->second == incident::LinkState::kSignedOff;
  });
}

}  // namespace sarloc::app
