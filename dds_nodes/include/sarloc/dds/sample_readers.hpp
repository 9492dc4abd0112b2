#pragma once
// The readers of every sensor-sample topic, one per alternative of estimator::SensorSample:
// each sample is converted (to_core) and handed on as a SensorSample, so that the node that
// consumes them never names a sensor type. A sample that cannot be converted is refused with
// the responder's id and the reason; so is one whose writer may not speak for that responder
// (writer_authority.hpp: with DDS Security, only the responder's own device).
#include <functional>
#include <memory>
#include <string>

#include "sarloc/core/estimator/sensor_sample.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/writer_authority.hpp"

namespace sarloc::dds {

class SampleReaders {
 public:
  using OnSample = std::function<void(estimator::SensorSample)>;
  /// `reason`: "invalid_value" or "unauthorized_writer".
  using OnRefused =
      std::function<void(const std::string& responder_id, const std::string& reason, const std::string& detail)>;

  /// Callbacks run on Fast DDS threads: keep them to converting and enqueueing. `authority`
  /// must outlive this.
  SampleReaders(std::shared_ptr<Participant> participant, const WriterAuthority& authority, OnSample on_sample,
                OnRefused on_refused, const EndpointOptions& options);

 private:
  std::unique_ptr<Reader<::sarloc::FieldMeasurement>> field_reader_;
};

}  // namespace sarloc::dds
