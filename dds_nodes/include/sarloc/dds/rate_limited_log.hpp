#pragma once
// One warning per (source, reason) per interval, with the count of what was suppressed, so a
// stream of malformed samples cannot flood the log (and still shows up in it).
#include <spdlog/spdlog.h>

#include <chrono>
#include <map>
#include <mutex>
#include <string>

namespace sarloc::dds {

class RateLimitedLog {
 public:
  explicit RateLimitedLog(std::chrono::milliseconds interval) : interval_(interval) {}

  void warn(const std::string& source, const std::string& reason, const std::string& message) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto& entry = entries_[source + '\x1f' + reason];
    const auto now = std::chrono::steady_clock::now();
    if (entry.last == std::chrono::steady_clock::time_point{} || now - entry.last >= interval_) {
      if (entry.suppressed > 0) {
        spdlog::warn("{} ({} more like it suppressed)", message, entry.suppressed);
      } else {
        spdlog::warn("{}", message);
      }
      entry.last = now;
      entry.suppressed = 0;
    } else {
      ++entry.suppressed;
    }
  }

 private:
  struct Entry {
    std::chrono::steady_clock::time_point last{};
    std::uint64_t suppressed = 0;
  };
  std::chrono::milliseconds interval_;
  std::mutex mutex_;
  std::map<std::string, Entry> entries_;
};

}  // namespace sarloc::dds
