#pragma once
// A fastddsgen type support whose instance handles depend on the key alone.
//
// Fast DDS 2.9's generated getKey() serialises the key into a buffer it keeps between calls,
// and Fast CDR 1.0 skips alignment padding without writing it: the bytes between a key string
// and the next member (three, after "bench-rescuer-50" and its NUL) are left over from the key
// serialised before, and they enter the MD5 that names the instance. One (rescuer, signal) thus
// got a new instance whenever the key written before it differed, the core daemon's
// VictimEstimate writer ran out of max_instances (1024) with 350 keys, and every answer after
// that was refused with RETCODE_TIMEOUT (docs/benchmarks.md, "Scale and soak"). Readers filed
// such samples under another instance too. This one zeroes the buffer first, under a lock
// (the buffer is shared by every writer and reader of the type in the participant).
#include <fastdds/rtps/common/InstanceHandle.h>

#include <cstddef>
#include <cstring>
#include <mutex>

namespace sarloc::dds {

template <class Generated, class T>
class KeyHashedType : public Generated {
 public:
  bool getKey(void* data, eprosima::fastrtps::rtps::InstanceHandle_t* handle, bool force_md5 = false) override {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::size_t size = T::getKeyMaxCdrSerializedSize() > 16 ? T::getKeyMaxCdrSerializedSize() : 16;
    if (this->m_keyBuffer != nullptr) std::memset(this->m_keyBuffer, 0, size);
    return Generated::getKey(data, handle, force_md5);
  }

 private:
  std::mutex mutex_;
};

}  // namespace sarloc::dds
