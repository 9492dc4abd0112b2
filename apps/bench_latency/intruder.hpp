#pragma once
// The latency bench's hostile publisher: a participant of its own that publishes valid-looking
// field samples and odometry for ids nobody serves, cycling through `ids` of them at `rate_hz`
// samples per second (alternating topics), to show what such a flood costs the core daemon
// and the real rescuers (docs/benchmarks.md, "Scale and soak").
//
//   Intruder intruder(participant_config, {100000, 2000.0, true, "/tmp/bench"}, a_real_sample);
//   intruder.wait_for_daemon();
//   intruder.start(from, until);
//   ... measure the real rescuers ...
//   const std::size_t sent = intruder.join();
#include <chrono>
#include <memory>
#include <string>
#include <thread>

#include "sarloc/core/avalanche/field_measurement.hpp"
#include "sarloc/dds/participant.hpp"
#include "sarloc/dds/writer.hpp"

namespace sarloc::bench {

struct IntruderOptions {
  std::size_t ids = 100000;  ///< distinct rescuer ids, "intruder-0".."intruder-<ids-1>"
  double rate_hz = 1000.0;   ///< samples per second, both topics together
  bool odometry = true;      ///< alternate odometry with field samples (false: field samples only)
  std::string scratch_dir;   ///< where its writer profile file is written
};

class Intruder {
 public:
  using Clock = std::chrono::steady_clock;

  /// `field_template`: a real sample to imitate (its rescuer id, sequence and stamp are replaced).
  Intruder(const dds::ParticipantConfig& participant, IntruderOptions options,
           avalanche::FieldMeasurement field_template);
  ~Intruder();
  Intruder(const Intruder&) = delete;
  Intruder& operator=(const Intruder&) = delete;

  bool wait_for_daemon();
  /// Publishes from `from` to `until` on its own thread.
  void start(Clock::time_point from, Clock::time_point until);
  /// Waits for the end; the samples DDS accepted.
  std::size_t join();

 private:
  void run(Clock::time_point from, Clock::time_point until);

  IntruderOptions options_;
  std::shared_ptr<dds::Participant> participant_;
  dds::Writer<::sarloc::FieldMeasurement> measurements_;
  dds::Writer<::sarloc::Odometry> odometry_;
  avalanche::FieldMeasurement template_;
  std::size_t sent_ = 0;
  std::thread thread_;
};

}  // namespace sarloc::bench
