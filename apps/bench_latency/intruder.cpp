#include "intruder.hpp"

#include <fstream>

#include "sarloc/app/shutdown_signal.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/mission_clock.hpp"

namespace sarloc::bench {
namespace {

// Its writers: reliable, one sample per id and no limit on ids, so that its own history never
// holds it back (sarloc's writer profiles stop at 1024 / 256 ids).
constexpr const char* kIntruderProfiles = R"(<?xml version="1.0" encoding="UTF-8" ?>
<dds xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles"><profiles>
  <data_writer profile_name="bench_intruder.writer">
    <topic>
      <historyQos><kind>KEEP_LAST</kind><depth>1</depth></historyQos>
      <resourceLimitsQos><max_samples>200000</max_samples><max_instances>200000</max_instances>
        <max_samples_per_instance>1</max_samples_per_instance><allocated_samples>64</allocated_samples></resourceLimitsQos>
    </topic>
    <qos><reliability><kind>RELIABLE</kind></reliability><durability><kind>VOLATILE</kind></durability></qos>
    <historyMemoryPolicy>PREALLOCATED_WITH_REALLOC</historyMemoryPolicy>
  </data_writer>
</profiles></dds>
)";

dds::EndpointOptions intruder_writer(const std::string& scratch_dir) {
  const std::string path = scratch_dir + "/intruder-profiles.xml";
  std::ofstream(path) << kIntruderProfiles;
  dds::load_profiles_file(path);
  dds::EndpointOptions options;
  options.profile_override = "bench_intruder.writer";
  return options;
}

}  // namespace

Intruder::Intruder(const dds::ParticipantConfig& participant, IntruderOptions options,
                   avalanche::FieldMeasurement field_template)
    : options_(std::move(options)),
      participant_(std::make_shared<dds::Participant>(participant)),
      measurements_(participant_, intruder_writer(options_.scratch_dir)),
      odometry_(participant_, intruder_writer(options_.scratch_dir)),
      template_(std::move(field_template)) {
  if (options_.ids == 0) throw ConfigError("--intruder-ids = 0: the intruder needs at least one id");
}

Intruder::~Intruder() { join(); }

bool Intruder::wait_for_daemon() {
  return measurements_.wait_for_readers(1, std::chrono::seconds(10)) &&
         odometry_.wait_for_readers(1, std::chrono::seconds(10));
}

void Intruder::start(Clock::time_point from, Clock::time_point until) {
  thread_ = std::thread([this, from, until] { run(from, until); });
}

std::size_t Intruder::join() {
  if (thread_.joinable()) thread_.join();
  return sent_;
}

void Intruder::run(Clock::time_point from, Clock::time_point until) {
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / options_.rate_hz));
  auto due = from;
  for (std::size_t k = 0; Clock::now() < until && !app::shutdown_requested(); ++k) {
    std::this_thread::sleep_until(due);
    due += period;
    const std::string id = "intruder-" + std::to_string(k % options_.ids);
    const TimestampNs stamp = dds::MissionClock::wall_now_ns();
    bool written;
    if (k % 2 == 0 || !options_.odometry) {
      auto m = template_;
      m.rescuer_id = id;
      m.sequence = k / options_.ids + 1;
      m.stamp = stamp;
      written = measurements_.write(dds::to_idl(m));
    } else {
      responder::Odometry o;
      o.rescuer_id = id;
      o.sequence = k / options_.ids + 1;
      o.interval_start = stamp - 1'000'000'000;
      o.interval_end = stamp;
      o.covariance = Mat6::Identity() * 0.01;
      written = odometry_.write(dds::to_idl(o));
    }
    if (written) ++sent_;
  }
}

}  // namespace sarloc::bench
