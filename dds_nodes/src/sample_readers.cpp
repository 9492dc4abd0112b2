#include "sarloc/dds/sample_readers.hpp"

#include "sarloc/core/common/errors.hpp"
#include "sarloc/dds/conversions.hpp"

namespace sarloc::dds {

SampleReaders::SampleReaders(std::shared_ptr<Participant> participant, OnSample on_sample, OnRefused on_refused,
                             const EndpointOptions& options) {
  field_reader_ = std::make_unique<Reader<::sarloc::FieldMeasurement>>(
      std::move(participant),
      [on_sample, on_refused](const ::sarloc::FieldMeasurement& m, const auto&) {
        try {
          on_sample(to_core(m));
        } catch (const InputError& e) {
          on_refused(printable_id(m.rescuer_id()), e.what());
        }
      },
      options);
}

}  // namespace sarloc::dds
