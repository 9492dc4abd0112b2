#pragma once
// A topic type that moves serialized payloads untouched: the recorder reads them exactly as
// they arrived (encapsulation header included) and the replayer writes them back. It carries
// the generated type's name, size and key so that it matches the typed endpoints, and it asks
// the generated type only for the key of a sample.
#include <fastdds/dds/topic/TopicDataType.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace sarloc::dds {

struct RawSample {
  std::vector<std::uint8_t> bytes;  ///< the whole serialized payload, encapsulation first
};

class RawPubSubType : public eprosima::fastdds::dds::TopicDataType {
 public:
  explicit RawPubSubType(std::unique_ptr<eprosima::fastdds::dds::TopicDataType> typed);

  bool serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) override;
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override;
  std::function<std::uint32_t()> getSerializedSizeProvider(void* data) override;
  void* createData() override;
  void deleteData(void* data) override;
  bool getKey(void* data, eprosima::fastrtps::rtps::InstanceHandle_t* handle, bool force_md5 = false) override;

 private:
  std::unique_ptr<eprosima::fastdds::dds::TopicDataType> typed_;
};

/// Decodes one recorded payload into its generated type; false when it does not decode.
template <class PubSubType, class T>
bool decode_payload(const std::vector<std::uint8_t>& bytes, T& sample) {
  eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<std::uint32_t>(bytes.size()));
  if (!bytes.empty()) std::copy(bytes.begin(), bytes.end(), payload.data);
  payload.length = static_cast<std::uint32_t>(bytes.size());
  PubSubType type;
  try {
    return type.deserialize(&payload, &sample);
  } catch (...) {
    return false;  // a damaged payload is a bad sample, never a crash
  }
}

/// Serializes one sample of a generated type as a payload (encapsulation first), as a writer
/// would send it: what a recording holds.
template <class PubSubType, class T>
std::vector<std::uint8_t> encode_payload(const T& sample) {
  PubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.m_typeSize);
  if (!type.serialize(const_cast<T*>(&sample), &payload)) return {};
  return std::vector<std::uint8_t>(payload.data, payload.data + payload.length);
}

}  // namespace sarloc::dds
