#pragma once
// A thread-safe progress bar on stderr, drawn only when stderr is a terminal (so CI logs and
// pipes stay clean).
//
//   ProgressBar bar("trials", 100);
//   ... from any thread: bar.tick();
//   bar.finish();
#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace sarloc::app {

class ProgressBar {
 public:
  ProgressBar(std::string label, std::size_t total);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  void tick(std::size_t n = 1);
  void finish();

 private:
  void draw_locked();

  std::string label_;
  std::size_t total_;
  std::size_t done_ = 0;
  bool enabled_;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  std::mutex mutex_;
};

}  // namespace sarloc::app
