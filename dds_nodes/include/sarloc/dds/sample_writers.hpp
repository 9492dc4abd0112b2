#pragma once
// The writers of every sensor-sample topic, one per alternative of estimator::SensorSample:
// a device publishes whatever its sensors produce without naming the topics.
#include <chrono>
#include <memory>

#include "sarloc/core/estimator/sensor_sample.hpp"
#include "sarloc/dds/writer.hpp"

namespace sarloc::dds {

class SampleWriters {
 public:
  SampleWriters(std::shared_ptr<Participant> participant, const EndpointOptions& options);

  /// Converts (to_idl) and writes; false if DDS refused the sample.
  bool write(const estimator::SensorSample& sample);
  /// Moves every writer to other DDS partitions (Writer::set_partitions).
  void set_partitions(const std::vector<std::string>& partitions) { field_writer_.set_partitions(partitions); }
  /// Every sample topic has at least `count` matched readers within `timeout`.
  bool wait_for_readers(int count, std::chrono::milliseconds timeout) const;

 private:
  Writer<::sarloc::FieldMeasurement> field_writer_;
};

}  // namespace sarloc::dds
