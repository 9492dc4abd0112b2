#pragma once
// One warning per (source, reason) per interval, with the count of what was suppressed, so a
// stream of malformed samples cannot flood the log (and still shows up in it).
//
// Bounded: at most max_sources entries. Entries quiet for an interval are forgotten (their
// suppressed count is logged first); if every entry is still busy, a new source shares the
// entry "(other sources)" of its reason. A publisher cycling through 100,000 ids therefore
// costs one entry per reason, not one per id.
#include <spdlog/spdlog.h>

#include <chrono>
#include <map>
#include <mutex>
#include <string>

namespace sarloc::dds {

class RateLimitedLog {
 public:
  explicit RateLimitedLog(std::chrono::milliseconds interval, std::size_t max_sources = 1024)
      : interval_(interval), max_sources_(max_sources) {}

  void warn(const std::string& source, const std::string& reason, const std::string& message) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto now = std::chrono::steady_clock::now();
    auto it = entries_.find(key(source, reason));
    if (it == entries_.end()) {
      if (entries_.size() >= max_sources_) forget_quiet(now);
      it = entries_.try_emplace(entries_.size() < max_sources_ ? key(source, reason) : key("(other sources)", reason))
               .first;
    }
    Entry& entry = it->second;
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

  std::size_t sources() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return entries_.size();
  }

 private:
  struct Entry {
    std::chrono::steady_clock::time_point last{};
    std::uint64_t suppressed = 0;
  };

  static std::string key(const std::string& source, const std::string& reason) { return source + '\x1f' + reason; }

  // At most once per interval: a full table of busy sources is not rescanned for every sample.
  void forget_quiet(std::chrono::steady_clock::time_point now) {
    if (now - last_sweep_ < interval_) return;
    last_sweep_ = now;
    for (auto it = entries_.begin(); it != entries_.end();) {
      if (now - it->second.last < interval_) {
        ++it;
        continue;
      }
      if (it->second.suppressed > 0) {
        const auto sep = it->first.find('\x1f');
        spdlog::warn("{} more '{}' from '{}' suppressed", it->second.suppressed, it->first.substr(sep + 1),
                     it->first.substr(0, sep));
      }
      it = entries_.erase(it);
    }
  }

  std::chrono::milliseconds interval_;
  std::size_t max_sources_;
  mutable std::mutex mutex_;
  std::map<std::string, Entry> entries_;
  std::chrono::steady_clock::time_point last_sweep_{};
};

}  // namespace sarloc::dds
