#include "sarloc/core/estimator/sensor_sample.hpp"

namespace sarloc::estimator {

const std::string& responder_of(const SensorSample& sample) {
  return std::visit([](const auto& s) -> const std::string& { return s.rescuer_id; }, sample);
}

TimestampNs stamp_of(const SensorSample& sample) {
  return std::visit([](const auto& s) { return s.stamp; }, sample);
}

std::uint64_t sequence_of(const SensorSample& sample) {
  return std::visit([](const auto& s) { return s.sequence; }, sample);
}

std::uint32_t signal_of(const SensorSample& sample) {
  return std::visit([](const auto& s) { return s.signal_id; }, sample);
}

}  // namespace sarloc::estimator
