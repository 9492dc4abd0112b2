#include "sarloc/dds/sample_readers.hpp"

#include "sarloc/core/common/errors.hpp"
#include "sarloc/dds/conversions.hpp"

namespace sarloc::dds {

SampleReaders::SampleReaders(std::shared_ptr<Participant> participant, const WriterAuthority& authority,
                             OnSample on_sample, OnRefused on_refused, const EndpointOptions& options) {
  field_reader_ = std::make_unique<Reader<::sarloc::FieldMeasurement>>(
      std::move(participant),
      [&authority, on_sample, on_refused](const ::sarloc::FieldMeasurement& m, const auto& info) {
        try {
          auto sample = to_core(m);
          const std::string id = m.rescuer_id().to_string();  // an identifier: to_core checked it
          if (!authority.admits(info.publication_handle, id, WriterAuthority::Speakers::kDevice)) {
            on_refused(id, "unauthorized_writer", authority.refusal("field measurement", info.publication_handle, id));
            return;
          }
          on_sample(std::move(sample));
        } catch (const InputError& e) {
          on_refused(printable_id(m.rescuer_id()), "invalid_value", e.what());
        }
      },
      options);
}

}  // namespace sarloc::dds
