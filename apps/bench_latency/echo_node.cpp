#include "echo_node.hpp"

#include <fastdds/dds/core/condition/WaitSet.hpp>
#include <spdlog/spdlog.h>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"
#include "sarloc/dds/mission_clock.hpp"
#include "sarloc/dds/process_stats.hpp"

namespace sarloc::bench {

const char* to_string(EchoHandoff handoff) {
  switch (handoff) {
    case EchoHandoff::kListener: return "listener";
    case EchoHandoff::kQueue: return "queue";
    case EchoHandoff::kWaitSet: return "waitset";
  }
  return "?";
}

EchoHandoff parse_echo_handoff(const std::string& text) {
  if (text == "listener") return EchoHandoff::kListener;
  if (text == "queue") return EchoHandoff::kQueue;
  if (text == "waitset") return EchoHandoff::kWaitSet;
  throw ConfigError("echo.handoff = '" + text + "': must be listener, queue or waitset");
}

void EchoNodeConfig::validate() const {
  if (node_id.empty() || node_id.size() > 64) throw ConfigError("echo.node_id = '" + node_id + "': must be 1-64 characters");
  if (!(status_period_s > 0.0 && status_period_s <= 60.0)) {
    throw ConfigError("echo.status_period_s = " + config_value(status_period_s) + ": must be in (0, 60]");
  }
  for (const auto& p : partitions) {
    if (p.empty()) throw ConfigError("echo.partitions contains an empty name");
  }
}

EchoNode::EchoNode(std::shared_ptr<dds::Participant> participant, EchoNodeConfig config)
    : config_((config.validate(), std::move(config))),
      participant_(std::move(participant)),
      estimate_writer_(participant_, dds::EndpointOptions::in(config_.partitions)),
      status_writer_(participant_) {
  status_thread_ = std::thread([this] { run_status(); });
  try {
    auto on_measurement = [this](const ::sarloc::FieldMeasurement& m, const auto&) {
      if (config_.handoff == EchoHandoff::kListener) {
        answer(m);
        return;
      }
      {
        std::lock_guard<std::mutex> lock(mutex_);
        queue_.push_back(m);
      }
      cv_.notify_one();
    };
    measurement_reader_ = std::make_unique<dds::Reader<::sarloc::FieldMeasurement>>(
        participant_, on_measurement, dds::EndpointOptions::in(config_.partitions));
    // Read and dropped: the daemon receives this traffic too, so the echo must.
    odometry_reader_ = std::make_unique<dds::Reader<::sarloc::Odometry>>(
        participant_, [](const ::sarloc::Odometry&, const auto&) {}, dds::EndpointOptions::in(config_.partitions));
    if (config_.handoff == EchoHandoff::kQueue) worker_ = std::thread([this] { run_worker(); });
    if (config_.handoff == EchoHandoff::kWaitSet) {
      // No listener: DATA_AVAILABLE then only raises the status condition the worker waits on.
      // (Nothing is published before the bench has matched, so no sample is lost meanwhile.)
      measurement_reader_->get()->set_listener(nullptr);
      worker_ = std::thread([this] { run_waitset(); });
    }
  } catch (...) {
    stop_threads();
    throw;
  }
  spdlog::info("{}: echoing field measurements ({} hand-off)", config_.node_id, to_string(config_.handoff));
}

EchoNode::~EchoNode() {
  // Threads first: the WaitSet worker uses the reader. A listener callback still running
  // meanwhile only reaches the writer and the queue, which outlive the readers.
  stop_threads();
  measurement_reader_.reset();
  odometry_reader_.reset();
}

void EchoNode::stop_threads() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_.store(true);
  }
  cv_.notify_all();
  status_cv_.notify_all();
  stop_guard_.set_trigger_value(true);
  if (worker_.joinable()) worker_.join();
  if (status_thread_.joinable()) status_thread_.join();
}

void EchoNode::answer(const ::sarloc::FieldMeasurement& m) {
  ::sarloc::VictimEstimate e;
  e.rescuer_id(m.rescuer_id());
  e.signal_id(m.signal_id());
  e.stamp(m.stamp());
  e.measurement_sequence(m.sequence_number());
  if (estimate_writer_.write(e)) {
    echoed_.fetch_add(1);
  } else {
    refused_.fetch_add(1);
    spdlog::error("{}: DDS refused a VictimEstimate for '{}'", config_.node_id, m.rescuer_id().to_string());
  }
}

void EchoNode::run_worker() {
  while (true) {
    ::sarloc::FieldMeasurement m;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      cv_.wait(lock, [this] { return stopping_.load() || !queue_.empty(); });
      if (stopping_.load()) return;
      m = std::move(queue_.front());
      queue_.pop_front();
    }
    answer(m);
  }
}

void EchoNode::run_waitset() {
  namespace fdds = eprosima::fastdds::dds;
  fdds::DataReader* reader = measurement_reader_->get();
  fdds::StatusCondition& data = reader->get_statuscondition();
  data.set_enabled_statuses(fdds::StatusMask::data_available());
  fdds::WaitSet waitset;
  waitset.attach_condition(data);
  waitset.attach_condition(stop_guard_);
  fdds::ConditionSeq active;
  ::sarloc::FieldMeasurement m;
  fdds::SampleInfo info;
  while (!stopping_.load()) {
    if (waitset.wait(active, eprosima::fastrtps::c_TimeInfinite) != eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
      continue;
    }
    while (reader->take_next_sample(&m, &info) == eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
      if (info.valid_data) answer(m);
    }
  }
}

void EchoNode::run_status() {
  dds::ProcessStats stats;
  while (!stopping_.load()) {
    ::sarloc::NodeStatus status;
    status.node_id(config_.node_id);
    status.kind(::sarloc::NODE_CORE);
    status.stamp(dds::MissionClock::wall_now_ns());
    status.samples_accepted(echoed_.load());
    status.samples_rejected(refused_.load());
    status.cpu_percent(stats.cpu_percent());
    status.rss_mb(dds::ProcessStats::rss_mb());
    status_writer_.write(status);
    const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(config_.status_period_s));
    std::unique_lock<std::mutex> lock(mutex_);
    status_cv_.wait_for(lock, period, [this] { return stopping_.load(); });
  }
}

}  // namespace sarloc::bench
