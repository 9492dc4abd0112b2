#pragma once
// Helpers for DDS integration tests: participants on the localhost profile in a test's own
// domain, a thread-safe inbox that a reader callback fills, and waiting for a condition.
#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "sarloc/dds/participant.hpp"

namespace sarloc::test {

inline std::shared_ptr<dds::Participant> make_participant(std::uint32_t domain, const std::string& name,
                                                          const std::string& profile = "sarloc_localhost") {
  dds::ParticipantConfig config;
  config.domain_id = domain;
  config.name = name;
  config.profile = profile;
  return std::make_shared<dds::Participant>(config);
}

/// Polls `condition` every 20 ms until it holds (true) or `timeout` passes (false).
inline bool eventually(const std::function<bool()>& condition, std::chrono::milliseconds timeout) {
  const auto until = std::chrono::steady_clock::now() + timeout;
  while (!condition()) {
    if (std::chrono::steady_clock::now() > until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

template <class T>
class Inbox {
 public:
  void push(const T& sample) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      samples_.push_back(sample);
    }
    cv_.notify_all();
  }

  /// Waits until at least `count` samples arrived; returns what arrived by then.
  std::vector<T> wait_for(std::size_t count, std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait_for(lock, timeout, [&] { return samples_.size() >= count; });
    return samples_;
  }

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  std::vector<T> samples_;
};

}  // namespace sarloc::test
