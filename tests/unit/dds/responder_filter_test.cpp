// The core daemon's admission filter: it reads a sample's rescuer_id from the serialized
// payload, asks the predicate, and refuses what it cannot read without throwing.
#include "sarloc/dds/responder_filter.hpp"

#include <fastdds/dds/core/LoanableSequence.hpp>
#include <gtest/gtest.h>

#include <set>

#include "sarloc/dds/topics.hpp"

namespace sarloc::dds {
namespace {

using eprosima::fastdds::dds::IContentFilter;
using ReturnCode = eprosima::fastrtps::types::ReturnCode_t;

template <class T>
eprosima::fastrtps::rtps::SerializedPayload_t serialized(T sample) {
  typename TopicTraits<T>::PubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&sample)());
  EXPECT_TRUE(type.serialize(&sample, &payload));
  return payload;
}

class ResponderFilterTest : public ::testing::Test {
 protected:
  IContentFilter* make(const char* type_name) {
    const std::string expression = factory_.expression_for([this](const ResponderSample& sample) {
      asked_.insert(sample.responder_id);
      if (sample.first_step) first_steps_.insert(sample.responder_id);
      return sample.responder_id == "r1";
    });
    IContentFilter* filter = nullptr;
    const eprosima::fastdds::dds::LoanableSequence<const char*> no_parameters;
    EXPECT_EQ(factory_.create_content_filter(kResponderFilterClass, type_name, nullptr, expression.c_str(),
                                             no_parameters, filter),
              ReturnCode::RETCODE_OK);
    return filter;
  }
  bool evaluate(IContentFilter* f, const eprosima::fastrtps::rtps::SerializedPayload_t& p) {
    return f->evaluate(p, IContentFilter::FilterSampleInfo{}, eprosima::fastrtps::rtps::GUID_t{});
  }

  ResponderFilterFactory factory_;
  std::set<std::string> asked_;
  std::set<std::string> first_steps_;
};

TEST_F(ResponderFilterTest, AsksThePredicateWithTheSamplesRescuerId) {
  auto* filter = make(::sarloc::FieldMeasurementPubSubType().getName());
  ASSERT_NE(filter, nullptr);
  ::sarloc::FieldMeasurement m;
  m.rescuer_id("r1");
  EXPECT_TRUE(evaluate(filter, serialized(m)));
  m.rescuer_id("intruder-7");
  EXPECT_FALSE(evaluate(filter, serialized(m)));
  EXPECT_EQ(asked_, (std::set<std::string>{"r1", "intruder-7"}));
  EXPECT_EQ(factory_.delete_content_filter(kResponderFilterClass, filter), ReturnCode::RETCODE_OK);
}

TEST_F(ResponderFilterTest, ReadsOdometryTooAndWhetherItIsTheDevicesFirstStep) {
  auto* filter = make(::sarloc::OdometryPubSubType().getName());
  ASSERT_NE(filter, nullptr);
  ::sarloc::Odometry o;
  o.rescuer_id("r1");
  o.sequence_number(2);
  EXPECT_TRUE(evaluate(filter, serialized(o)));
  EXPECT_TRUE(first_steps_.empty());
  o.rescuer_id("ff1");
  o.sequence_number(1);
  EXPECT_FALSE(evaluate(filter, serialized(o)));
  EXPECT_EQ(first_steps_, std::set<std::string>{"ff1"});
  auto* measurements = make(::sarloc::FieldMeasurementPubSubType().getName());
  ::sarloc::FieldMeasurement m;
  m.rescuer_id("r7");
  m.sequence_number(1);
  EXPECT_FALSE(evaluate(measurements, serialized(m)));
  EXPECT_EQ(first_steps_, std::set<std::string>{"ff1"}) << "a measurement is never a first step";
  EXPECT_EQ(factory_.delete_content_filter(kResponderFilterClass, filter), ReturnCode::RETCODE_OK);
  EXPECT_EQ(factory_.delete_content_filter(kResponderFilterClass, measurements), ReturnCode::RETCODE_OK);
}

TEST_F(ResponderFilterTest, AMalformedPayloadIsRefusedNotThrown) {
  auto* filter = make(::sarloc::FieldMeasurementPubSubType().getName());
  ASSERT_NE(filter, nullptr);
  for (std::uint32_t size : {0U, 3U, 8U, 64U}) {
    eprosima::fastrtps::rtps::SerializedPayload_t garbage(size);
    for (std::uint32_t i = 0; i < size; ++i) garbage.data[i] = static_cast<unsigned char>(0xFF - i);
    garbage.length = size;
    EXPECT_FALSE(evaluate(filter, garbage)) << size << " bytes";
  }
  EXPECT_TRUE(asked_.empty()) << "nothing readable, nothing asked";
  EXPECT_EQ(factory_.delete_content_filter(kResponderFilterClass, filter), ReturnCode::RETCODE_OK);
}

TEST_F(ResponderFilterTest, OtherTypesAndUnknownExpressionsAreRefused) {
  IContentFilter* filter = nullptr;
  const eprosima::fastdds::dds::LoanableSequence<const char*> none;
  const std::string expression = factory_.expression_for([](const ResponderSample&) { return true; });
  EXPECT_EQ(factory_.create_content_filter(kResponderFilterClass, ::sarloc::GuidancePubSubType().getName(), nullptr,
                                           expression.c_str(), none, filter),
            ReturnCode::RETCODE_UNSUPPORTED);
  EXPECT_EQ(factory_.create_content_filter(kResponderFilterClass, ::sarloc::OdometryPubSubType().getName(), nullptr,
                                           "no such predicate", none, filter),
            ReturnCode::RETCODE_BAD_PARAMETER);
}

}  // namespace
}  // namespace sarloc::dds
