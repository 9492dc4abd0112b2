#include "sarloc/dds/raw_topic_type.hpp"

#include <algorithm>
#include <cstring>

namespace sarloc::dds {

using eprosima::fastrtps::rtps::InstanceHandle_t;
using eprosima::fastrtps::rtps::SerializedPayload_t;

RawPubSubType::RawPubSubType(std::unique_ptr<eprosima::fastdds::dds::TopicDataType> typed) : typed_(std::move(typed)) {
  setName(typed_->getName());
  m_typeSize = typed_->m_typeSize;
  m_isGetKeyDefined = typed_->m_isGetKeyDefined;
}

bool RawPubSubType::serialize(void* data, SerializedPayload_t* payload) {
  const auto& bytes = static_cast<RawSample*>(data)->bytes;
  if (bytes.size() < 4 || bytes.size() > payload->max_size) return false;
  std::memcpy(payload->data, bytes.data(), bytes.size());
  payload->length = static_cast<std::uint32_t>(bytes.size());
  // The encapsulation kind is the payload's second byte (CDR_BE 0x00, CDR_LE 0x01, ...).
  payload->encapsulation = static_cast<std::uint16_t>(bytes[1]);
  return true;
}

bool RawPubSubType::deserialize(SerializedPayload_t* payload, void* data) {
  auto& bytes = static_cast<RawSample*>(data)->bytes;
  bytes.assign(payload->data, payload->data + payload->length);
  return true;
}

std::function<std::uint32_t()> RawPubSubType::getSerializedSizeProvider(void* data) {
  return [data] { return static_cast<std::uint32_t>(static_cast<RawSample*>(data)->bytes.size()); };
}

void* RawPubSubType::createData() { return new RawSample(); }

void RawPubSubType::deleteData(void* data) { delete static_cast<RawSample*>(data); }

bool RawPubSubType::getKey(void* data, InstanceHandle_t* handle, bool force_md5) {
  if (!m_isGetKeyDefined) return false;
  auto& bytes = static_cast<RawSample*>(data)->bytes;
  SerializedPayload_t payload(static_cast<std::uint32_t>(bytes.size()));
  std::copy(bytes.begin(), bytes.end(), payload.data);
  payload.length = static_cast<std::uint32_t>(bytes.size());
  void* typed = typed_->createData();
  bool ok = false;
  try {
    ok = typed_->deserialize(&payload, typed) && typed_->getKey(typed, handle, force_md5);
  } catch (...) {
    ok = false;
  }
  typed_->deleteData(typed);
  return ok;
}

}  // namespace sarloc::dds
