#pragma once
// Thread-safe counts of accepted and rejected samples, by reason, for NodeStatus.
#include <cstdint>
#include <map>
#include <mutex>
#include <string>

namespace sarloc::dds {

class RejectCounters {
 public:
  void accepted() {
    std::lock_guard<std::mutex> lock(mutex_);
    ++accepted_;
  }
  void rejected(const std::string& reason) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++rejected_;
    ++by_reason_[reason];
  }
  /// Something went wrong with a sample that was still used (e.g. its odometry came late):
  /// counted under its reason, not as a rejection.
  void anomaly(const std::string& reason) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++by_reason_[reason];
  }
  struct Snapshot {
    std::uint64_t accepted = 0;
    std::uint64_t rejected = 0;
    std::map<std::string, std::uint64_t> by_reason;
    /// The samples rejected for `reason` (0 when none).
    std::uint64_t rejected_for(const std::string& reason) const {
      const auto it = by_reason.find(reason);
      return it == by_reason.end() ? 0 : it->second;
    }
  };
  Snapshot snapshot() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return Snapshot{accepted_, rejected_, by_reason_};
  }

 private:
  mutable std::mutex mutex_;
  std::uint64_t accepted_ = 0;
  std::uint64_t rejected_ = 0;
  std::map<std::string, std::uint64_t> by_reason_;
};

}  // namespace sarloc::dds
