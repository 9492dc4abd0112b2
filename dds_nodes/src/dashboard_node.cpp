#include "sarloc/dds/dashboard_node.hpp"

#include <spdlog/spdlog.h>

#include <map>
#include <mutex>
#include <set>

#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/speaker_claim.hpp"
#include "sarloc/dds/writer.hpp"

namespace sarloc::dds {

namespace fdds = eprosima::fastdds::dds;
using Handle = eprosima::fastrtps::rtps::InstanceHandle_t;

struct DashboardNode::Impl {
  std::shared_ptr<Participant> participant;
  std::unique_ptr<WriterAuthority> authority;  // with DDS Security: who may place a responder on the map
  DashboardSink sink;
  std::mutex mutex;
  // Disposals name only the instance: remember which id each instance carried.
  std::map<Handle, std::uint32_t> victim_of_instance, alarm_of_instance;
  // Declared before the readers, so that it outlives the alarm reader's callbacks.
  std::unique_ptr<Writer<::sarloc::AlarmAcknowledgement>> acknowledgements;
  std::set<std::uint32_t> acknowledged;  ///< alarms whose acknowledgement instance this writer holds
  std::unique_ptr<Reader<::sarloc::FusedVictim>> victims;
  std::unique_ptr<Reader<::sarloc::TeamStatus>> teams;
  std::unique_ptr<Reader<::sarloc::IncidentAlarm>> alarms;
  std::unique_ptr<Reader<::sarloc::IncidentSummary>> summary;
  std::unique_ptr<Reader<::sarloc::ResponderPosition>> positions;
  std::unique_ptr<Reader<::sarloc::ResponderCandidates>> candidates;
  std::unique_ptr<Reader<::sarloc::Guidance>> guidance;
  std::unique_ptr<Reader<::sarloc::SearchPlan>> plan;
  std::unique_ptr<Writer<::sarloc::VictimRecovery>> recoveries;
  std::unique_ptr<Writer<::sarloc::DigOrder>> dig_orders;
  std::unique_ptr<Writer<::sarloc::DepositDrawing>> deposits;

  template <class F>
  void guarded(const char* topic, F&& convert_and_deliver) {
    try {
      convert_and_deliver();
    } catch (const std::exception&) {
      if (sink.on_rejected) sink.on_rejected(topic);  // bad input never reaches the page
    }
  }

  // A reader of a topic whose samples speak for a responder: under DDS Security only the
  // identities allowed to speak for him reach the page (WriterAuthority).
  template <class Idl, class Core>
  std::unique_ptr<Reader<Idl>> spoken_for(const char* topic, const std::function<void(const Core&)>& deliver) {
    return std::make_unique<Reader<Idl>>(participant, [this, topic, &deliver](const Idl& sample, const auto& info) {
      guarded(topic, [&] {
        auto converted = to_core(sample);
        if (!admits(*authority, info.publication_handle, speaker_claim(sample))) {
          if (sink.on_rejected) sink.on_rejected(topic);
          return;
        }
        if (deliver) deliver(std::move(converted));
      });
    });
  }

  void gone(const fdds::SampleInfo& info, std::map<Handle, std::uint32_t>& ids, const std::function<void(std::uint32_t)>& callback) {
    if (info.instance_state != fdds::NOT_ALIVE_DISPOSED_INSTANCE_STATE || !callback) return;
    std::uint32_t id = 0;
    {
      std::lock_guard<std::mutex> lock(mutex);
      const auto it = ids.find(info.instance_handle);
      if (it == ids.end()) return;
      id = it->second;
      ids.erase(it);
    }
    callback(id);
  }

  // An alarm disposed needs no acknowledgement any more: its instance goes too, or every alarm
  // ever acknowledged would hold one until max_instances refused the next.
  void forget_acknowledgement(std::uint32_t alarm_id) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (acknowledged.erase(alarm_id) == 0) return;
    }
    ::sarloc::AlarmAcknowledgement key;
    key.alarm_id(alarm_id);
    if (!acknowledgements->dispose(key)) spdlog::warn("cannot dispose of the acknowledgement of alarm {}", alarm_id);
  }
};

DashboardNode::DashboardNode(std::shared_ptr<Participant> participant, DashboardSink sink) : impl_(std::make_unique<Impl>()) {
  auto& d = *impl_;
  d.participant = std::move(participant);
  d.authority = std::make_unique<WriterAuthority>(d.participant);
  d.sink = std::move(sink);
  ReaderEvents victim_events;
  victim_events.on_instance_gone = [&d](const fdds::SampleInfo& info) { d.gone(info, d.victim_of_instance, d.sink.on_victim_gone); };
  d.victims = std::make_unique<Reader<::sarloc::FusedVictim>>(
      d.participant,
      [&d](const ::sarloc::FusedVictim& v, const fdds::SampleInfo& info) {
        d.guarded("fused_victim", [&] {
          const auto victim = to_core(v);
          {
            std::lock_guard<std::mutex> lock(d.mutex);
            d.victim_of_instance[info.instance_handle] = victim.victim_id;
          }
          if (d.sink.on_victim) d.sink.on_victim(victim);
        });
      },
      EndpointOptions{}, victim_events);
  d.teams = std::make_unique<Reader<::sarloc::TeamStatus>>(d.participant, [&d](const ::sarloc::TeamStatus& t, const auto&) {
    d.guarded("team_status", [&] {
      if (d.sink.on_team) d.sink.on_team(to_core(t));
    });
  });
  ReaderEvents alarm_events;
  d.acknowledgements = std::make_unique<Writer<::sarloc::AlarmAcknowledgement>>(d.participant);
  alarm_events.on_instance_gone = [&d](const fdds::SampleInfo& info) {
    d.gone(info, d.alarm_of_instance, [&d](std::uint32_t id) {
      if (d.sink.on_alarm_gone) d.sink.on_alarm_gone(id);
      d.forget_acknowledgement(id);
    });
  };
  d.alarms = std::make_unique<Reader<::sarloc::IncidentAlarm>>(
      d.participant,
      [&d](const ::sarloc::IncidentAlarm& a, const fdds::SampleInfo& info) {
        d.guarded("incident_alarm", [&] {
          const auto alarm = to_core(a);
          {
            std::lock_guard<std::mutex> lock(d.mutex);
            d.alarm_of_instance[info.instance_handle] = alarm.alarm_id;
          }
          if (d.sink.on_alarm) d.sink.on_alarm(alarm);
        });
      },
      EndpointOptions{}, alarm_events);
  d.summary = std::make_unique<Reader<::sarloc::IncidentSummary>>(
      d.participant, [&d](const ::sarloc::IncidentSummary&, const fdds::SampleInfo& info) {
        if (d.sink.on_picture_writer) d.sink.on_picture_writer(handle_text(info.publication_handle).substr(0, 24));
      });
  d.positions = d.spoken_for<::sarloc::ResponderPosition>("responder_position", d.sink.on_position);
  d.candidates = d.spoken_for<::sarloc::ResponderCandidates>("responder_candidates", d.sink.on_candidates);
  d.guidance = std::make_unique<Reader<::sarloc::Guidance>>(d.participant, [&d](const ::sarloc::Guidance& g, const auto&) {
    d.guarded("guidance", [&] {
      if (d.sink.on_guidance) d.sink.on_guidance(to_core(g));
    });
  });
  d.plan =
      std::make_unique<Reader<::sarloc::SearchPlan>>(d.participant, [&d](const ::sarloc::SearchPlan& p, const auto&) {
        d.guarded("search_plan", [&] {
          if (d.sink.on_search_plan) d.sink.on_search_plan(to_core(p));
        });
      });
  d.recoveries = std::make_unique<Writer<::sarloc::VictimRecovery>>(d.participant);
  d.dig_orders = std::make_unique<Writer<::sarloc::DigOrder>>(d.participant);
  d.deposits = std::make_unique<Writer<::sarloc::DepositDrawing>>(d.participant);
}

DashboardNode::~DashboardNode() = default;

bool DashboardNode::acknowledge(std::uint32_t alarm_id, const std::string& operator_id, TimestampNs stamp) {
  ::sarloc::AlarmAcknowledgement ack;
  ack.alarm_id(alarm_id);
  ack.operator_id(operator_id);
  ack.stamp(stamp);
  {
    // Before the write: the alarm's disposal may come back before write() returns.
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->acknowledged.insert(alarm_id);
  }
  if (impl_->acknowledgements->write(ack)) return true;
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->acknowledged.erase(alarm_id);
  return false;
}

bool DashboardNode::report_dug_out(std::uint32_t victim_id, const std::string& operator_id, TimestampNs stamp) {
  ::sarloc::VictimRecovery recovery;
  recovery.victim_id(victim_id);
  recovery.reported_by(operator_id);
  recovery.stamp(stamp);
  return impl_->recoveries->write(recovery);
}

bool DashboardNode::set_dig_order(const std::string& incident_id, const std::vector<std::uint32_t>& victim_ids,
                                  const std::string& operator_id, TimestampNs stamp) {
  ::sarloc::DigOrder order;
  order.incident_id(incident_id);
  order.victim_ids(victim_ids);
  order.operator_id(operator_id);
  order.stamp(stamp);
  return impl_->dig_orders->write(order);
}

bool DashboardNode::draw_deposit(const std::string& incident_id, const std::vector<Eigen::Vector2d>& outline,
                                 const std::string& operator_id, TimestampNs stamp) {
  if (outline.size() > ::sarloc::OUTLINE_POINTS_MAX) return false;
  ::sarloc::DepositDrawing drawing;
  drawing.incident_id(incident_id);
  drawing.stamp(stamp);
  drawing.operator_id(operator_id);
  for (const auto& v : outline) {
    ::sarloc::PlanePoint p;
    p.x(v.x());
    p.y(v.y());
    drawing.outline().push_back(p);
  }
  return impl_->deposits->write(drawing);
}

}  // namespace sarloc::dds
