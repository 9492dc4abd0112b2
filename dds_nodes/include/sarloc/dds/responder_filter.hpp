#pragma once
// A DDS content filter that decides, per sample, whether a responder's sample enters a
// reader at all: the core daemon applies its roster (estimator::ResponderRoster) through it.
//
// Why in DDS and not in the listener: a sample that passes the reader takes an instance (a key)
// in the reader's history, and the history has max_instances of them. A publisher cycling
// through 100,000 rescuer ids used them all up, after which Fast DDS 2.9 refused the real
// rescuers' samples and their reliable streams stalled behind the refused one
// (docs/benchmarks.md). A sample the filter refuses is acknowledged and dropped before the
// history.
//
// Fast DDS's own DDS-SQL filter needs TypeObjects, which sarloc does not generate; this is a
// custom filter class. It reads `rescuer_id` of a FieldMeasurement or an Odometry (and whether
// the Odometry is the device's first step) and asks the reader's predicate, on the Fast DDS
// receive thread.
#include <fastdds/dds/topic/IContentFilterFactory.hpp>
#include <map>
#include <mutex>
#include <string>

#include "sarloc/dds/responder_predicate.hpp"

namespace sarloc::dds {

constexpr const char* kResponderFilterClass = "SARLOC_RESPONDERS";

// IContentFilterFactory lacks a virtual destructor; the participant owns the factory as its class.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wnon-virtual-dtor"
class ResponderFilterFactory final : public eprosima::fastdds::dds::IContentFilterFactory {
 public:
  /// The filter expression that stands for `predicate` (a token this factory resolves).
  std::string expression_for(ResponderPredicate predicate);

  ReturnCode_t create_content_filter(const char* filter_class_name, const char* type_name,
                                     const eprosima::fastdds::dds::TopicDataType* data_type,
                                     const char* filter_expression, const ParameterSeq& filter_parameters,
                                     eprosima::fastdds::dds::IContentFilter*& filter_instance) override;
  ReturnCode_t delete_content_filter(const char* filter_class_name,
                                     eprosima::fastdds::dds::IContentFilter* filter_instance) override;

 private:
  std::mutex mutex_;
  std::map<std::string, ResponderPredicate> predicates_;
};
#pragma GCC diagnostic pop

}  // namespace sarloc::dds
