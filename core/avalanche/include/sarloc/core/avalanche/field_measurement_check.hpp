#pragma once
// The check every filter makes of a field sample before it uses it (the SOG filter, the
// particle and grid baselines through TransmitterFilter, the rescuer's search): finite values
// within physical bounds, a valid-axes mask, a usable attitude reading.
#include "sarloc/core/avalanche/field_measurement.hpp"

namespace sarloc::avalanche {

/// Throws InputError naming the field and its value ("field_measurement.field = [...]: ...").
void validate_field_measurement(const FieldMeasurement& m);

}  // namespace sarloc::avalanche
