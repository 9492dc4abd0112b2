#pragma once
// sarloc-dashboard --recording: a recording played into the dashboard's picture, with a
// timeline to play, pause and scrub (the debrief view). Seeking forward feeds what lies in
// between; seeking back rebuilds the picture from the start (PictureState::reset).
#include <nlohmann/json.hpp>

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "picture_state.hpp"

namespace sarloc::dashboard {

class RecordingPlayer {
 public:
  /// Loads the picture topics of `path` (throws recording::RecordingError when it is not MCAP;
  /// a damaged file plays what could be read: damage()).
  explicit RecordingPlayer(const std::string& path);

  /// The picture it plays into (set once, before play/seek).
  void attach(PictureState& state);

  /// The recording's mission clock at the cursor, and its wall clock (s), for PictureState.
  TimestampNs mission_now() const;
  double wall_now_s() const;
  TimestampNs epoch_ns() const { return epoch_ns_; }

  void play(double rate);
  void pause();
  /// To `mission_s` seconds after the recording's epoch (clamped to the recording).
  void seek(double mission_s);
  /// Advances the cursor by the wall time since the last tick while playing; call it often.
  void tick();

  /// {start_s, end_s, cursor_s, playing, rate, damage}: what the page's timeline shows.
  nlohmann::json status() const;
  /// POST /api/replay: {"action": "play"|"pause"|"seek", "t_s": ..., "rate": ...}.
  nlohmann::json control(const nlohmann::json& request);
  const std::string& damage() const { return damage_; }
  std::size_t samples() const { return samples_.size(); }

 private:
  struct Sample {
    std::uint64_t log_ns = 0;
    std::uint8_t topic = 0;  // index in kTopics
    std::vector<std::uint8_t> bytes;
  };
  void feed_until(std::uint64_t log_ns);
  void apply(const Sample& sample);
  double mission_s_of(std::uint64_t log_ns) const;
  std::uint64_t log_of(double mission_s) const;
  void publish_status();
  nlohmann::json status_locked() const;

  std::vector<Sample> samples_;
  std::string damage_;
  std::int64_t epoch_ns_ = 0;
  double speedup_ = 1.0;
  std::uint64_t first_log_ns_ = 0, last_log_ns_ = 0;
  PictureState* state_ = nullptr;

  mutable std::mutex mutex_;
  std::size_t next_ = 0;
  std::atomic<std::uint64_t> cursor_log_ns_{0};
  bool playing_ = false;
  double rate_ = 1.0;
  std::int64_t last_tick_ns_ = 0;
};

}  // namespace sarloc::dashboard
