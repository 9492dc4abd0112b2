#pragma once
// What the core daemon's admission filter (responder_filter.hpp) reads of a sample, and the
// predicate it asks.
#include <functional>
#include <string>

namespace sarloc::dds {

struct ResponderSample {
  std::string responder_id;
  /// An Odometry of sequence number 1: the device's first step, where a firefighter's filter
  /// may start at the reported entry (a FieldMeasurement is never one).
  bool first_step = false;
};

/// True if the responder's sample may enter the reader. Runs on Fast DDS threads.
using ResponderPredicate = std::function<bool(const ResponderSample& sample)>;

}  // namespace sarloc::dds
