#include "sarloc/dds/sample_readers.hpp"

#include "sarloc/core/common/errors.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/speaker_claim.hpp"

namespace sarloc::dds {

SampleReaders::SampleReaders(std::shared_ptr<Participant> participant, const WriterAuthority& authority,
                             OnSample on_sample, OnRefused on_refused, const EndpointOptions& options) {
  field_reader_ = std::make_unique<Reader<::sarloc::FieldMeasurement>>(
      std::move(participant),
      [&authority, on_sample, on_refused](const ::sarloc::FieldMeasurement& m, const auto& info) {
        try {
          auto sample = to_core(m);
          const SpeakerClaim claim = speaker_claim(m);  // an identifier: to_core checked it
          if (!admits(authority, info.publication_handle, claim)) {
            on_refused(claim.responder_id, "unauthorized_writer", refusal(authority, info.publication_handle, claim));
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
