#include "sarloc/dds/responder_filter.hpp"

#include <type_traits>

#include "sarloc/dds/topics.hpp"

namespace sarloc::dds {
namespace {

using eprosima::fastdds::dds::IContentFilter;

// Fast DDS's filter interfaces lack virtual destructors; instances are deleted as their own class.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wnon-virtual-dtor"
template <class T>
class ResponderFilter final : public IContentFilter {
 public:
  explicit ResponderFilter(ResponderPredicate admit) : admit_(std::move(admit)) {}
  virtual ~ResponderFilter() = default;

  bool evaluate(const SerializedPayload& payload, const FilterSampleInfo&, const GUID_t&) const override {
    T sample;
    typename TopicTraits<T>::PubSubType type;
    try {
      // deserialize() only reads the payload; its signature predates const.
      if (!type.deserialize(const_cast<SerializedPayload*>(&payload), &sample)) return false;
    } catch (...) {
      // Fast CDR throws on some malformed payloads (the generated code catches only one
      // exception type); refused here, such a sample never reaches the reader either.
      return false;
    }
    ResponderSample read{sample.rescuer_id().to_string()};
    if constexpr (std::is_same_v<T, ::sarloc::Odometry>) read.first_step = sample.sequence_number() == 1;
    return admit_(read);
  }

 private:
  ResponderPredicate admit_;
};
#pragma GCC diagnostic pop

}  // namespace

std::string ResponderFilterFactory::expression_for(ResponderPredicate predicate) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::string token = "predicate-" + std::to_string(predicates_.size());
  predicates_.emplace(token, std::move(predicate));
  return token;
}

ResponderFilterFactory::ReturnCode_t ResponderFilterFactory::create_content_filter(
    const char*, const char* type_name, const eprosima::fastdds::dds::TopicDataType*, const char* filter_expression,
    const ParameterSeq&, IContentFilter*& filter_instance) {
  ResponderPredicate admit;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = predicates_.find(filter_expression == nullptr ? "" : filter_expression);
    if (it == predicates_.end()) return ReturnCode_t::RETCODE_BAD_PARAMETER;
    admit = it->second;
  }
  const std::string type = type_name == nullptr ? "" : type_name;
  if (type == ::sarloc::FieldMeasurementPubSubType().getName()) {
    filter_instance = new ResponderFilter<::sarloc::FieldMeasurement>(std::move(admit));
  } else if (type == ::sarloc::OdometryPubSubType().getName()) {
    filter_instance = new ResponderFilter<::sarloc::Odometry>(std::move(admit));
  } else {
    return ReturnCode_t::RETCODE_UNSUPPORTED;
  }
  return ReturnCode_t::RETCODE_OK;
}

ResponderFilterFactory::ReturnCode_t ResponderFilterFactory::delete_content_filter(const char*,
                                                                                   IContentFilter* filter_instance) {
  // IContentFilter has no virtual destructor: delete as the class it was made as.
  if (auto* f = dynamic_cast<ResponderFilter<::sarloc::FieldMeasurement>*>(filter_instance)) {
    delete f;
  } else if (auto* o = dynamic_cast<ResponderFilter<::sarloc::Odometry>*>(filter_instance)) {
    delete o;
  } else {
    return ReturnCode_t::RETCODE_BAD_PARAMETER;
  }
  return ReturnCode_t::RETCODE_OK;
}

}  // namespace sarloc::dds
