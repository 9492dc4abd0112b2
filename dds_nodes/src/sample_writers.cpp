#include "sarloc/dds/sample_writers.hpp"

#include "sarloc/dds/conversions.hpp"

namespace sarloc::dds {

SampleWriters::SampleWriters(std::shared_ptr<Participant> participant, const EndpointOptions& options)
    : field_writer_(std::move(participant), options) {}

bool SampleWriters::write(const estimator::SensorSample& sample) {
  return std::visit([this](const auto& s) { return field_writer_.write(to_idl(s)); }, sample);
}

bool SampleWriters::wait_for_readers(int count, std::chrono::milliseconds timeout) const {
  return field_writer_.wait_for_readers(count, timeout);
}

}  // namespace sarloc::dds
