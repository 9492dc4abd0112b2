#include "recording_player.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string_view>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/time_units.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/recorded_sample.hpp"
#include "sarloc/dds/replayer.hpp"
#include "sarloc/dds/topics.hpp"
#include "sarloc/recording/mcap_reader.hpp"

namespace sarloc::dashboard {

namespace {

// The topics the dashboard shows, in the order of Sample::topic.
const char* const kTopics[] = {
    "sarloc/fused_victim", "sarloc/team_status",     "sarloc/incident_alarm", "sarloc/responder_position",
    "sarloc/guidance",     "sarloc/recorder_events", "sarloc/search_plan",    "sarloc/responder_candidates"};

std::int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// What the page shows of each recorded sample; the topics of kTopics only come here.
void show(PictureState& state, const incident::FusedVictim& v) { state.on_victim(v); }
void show(PictureState& state, const incident::TeamStatus& t) { state.on_team(t); }
void show(PictureState& state, const incident::IncidentAlarm& a) { state.on_alarm(a); }
void show(PictureState& state, const responder::ResponderPosition& p) { state.on_position(p); }
void show(PictureState& state, const responder::ResponderCandidates& c) { state.on_candidates(c); }
void show(PictureState& state, const responder::Guidance& g) { state.on_guidance(g); }
void show(PictureState& state, const incident::SearchPlanPicture& p) { state.on_search_plan(p); }
template <class T>
void show(PictureState&, const T&) {}

}  // namespace

RecordingPlayer::RecordingPlayer(const std::string& path) {
  std::map<std::uint16_t, int> topic_of;
  recording::McapVisitor visitor;
  visitor.on_channel = [&](const recording::Channel& c) {
    for (int k = 0; k < static_cast<int>(std::size(kTopics)); ++k) {
      if (c.topic == kTopics[k]) topic_of[c.id] = k;
    }
  };
  visitor.on_metadata = [&](const recording::Metadata& m) {
    if (m.name != "sarloc.recording") return;
    try {
      const auto timeline = dds::timeline_of(m.values);
      epoch_ns_ = timeline.epoch_ns;
      speedup_ = timeline.speedup;
    } catch (const ConfigError& error) {
      damage_ += std::string(error.what()) + "; ";
    }
  };
  visitor.on_message = [&](const recording::Message& m) {
    const auto it = topic_of.find(m.channel_id);
    if (it == topic_of.end()) return;
    samples_.push_back({m.log_time_ns, static_cast<std::uint8_t>(it->second), m.data});
  };
  const auto result = recording::read_mcap(path, visitor);
  damage_ += result.damage;
  // Recorded in arrival order, which the log times follow but for a few microseconds.
  std::stable_sort(samples_.begin(), samples_.end(), [](const Sample& a, const Sample& b) { return a.log_ns < b.log_ns; });
  if (!samples_.empty()) {
    first_log_ns_ = samples_.front().log_ns;
    last_log_ns_ = samples_.back().log_ns;
  }
  if (epoch_ns_ == 0) epoch_ns_ = static_cast<std::int64_t>(first_log_ns_);
  cursor_log_ns_ = first_log_ns_;
}

void RecordingPlayer::attach(PictureState& state) {
  state_ = &state;
  publish_status();
}

double RecordingPlayer::mission_s_of(std::uint64_t log_ns) const {
  return 1e-9 * speedup_ * (static_cast<double>(log_ns) - static_cast<double>(epoch_ns_));
}

std::uint64_t RecordingPlayer::log_of(double mission_s) const {
  const double log = static_cast<double>(epoch_ns_) + mission_s / speedup_ * 1e9;
  return static_cast<std::uint64_t>(std::clamp(log, static_cast<double>(first_log_ns_), static_cast<double>(last_log_ns_)));
}

TimestampNs RecordingPlayer::mission_now() const {
  return epoch_ns_ + seconds_to_ns(mission_s_of(cursor_log_ns_.load()));
}

double RecordingPlayer::wall_now_s() const { return 1e-9 * static_cast<double>(cursor_log_ns_.load()); }

void RecordingPlayer::apply(const Sample& s) {
  auto& state = *state_;
  const char* topic = kTopics[s.topic];
  try {
    if (std::string_view(topic) == "sarloc/recorder_events") {
      const auto event = nlohmann::json::parse(s.bytes.begin(), s.bytes.end());
      if (event.value("topic", "") == "sarloc/incident_summary")
        state.on_picture_writer(event.value("participant", ""));
      return;
    }
    if (const auto sample = dds::decode_recorded(topic, s.bytes)) {
      std::visit([&state](const auto& decoded) { show(state, decoded); }, *sample);
    }
  } catch (const std::exception&) {
    state.on_rejected(topic);  // what does not decode, or the core refuses, is counted, never shown
  }
}

void RecordingPlayer::feed_until(std::uint64_t log_ns) {
  while (next_ < samples_.size() && samples_[next_].log_ns <= log_ns) apply(samples_[next_++]);
}

void RecordingPlayer::play(double rate) {
  std::lock_guard<std::mutex> lock(mutex_);
  playing_ = true;
  rate_ = std::clamp(std::isfinite(rate) ? rate : 1.0, 0.1, 100.0);
  last_tick_ns_ = steady_ns();
  publish_status();
}

void RecordingPlayer::pause() {
  std::lock_guard<std::mutex> lock(mutex_);
  playing_ = false;
  publish_status();
}

void RecordingPlayer::seek(double mission_s) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::uint64_t target = log_of(std::isfinite(mission_s) ? mission_s : 0.0);
  if (target < cursor_log_ns_.load()) {
    state_->reset();  // back in time: the picture as it was is rebuilt from the start
    next_ = 0;
  }
  cursor_log_ns_ = target;
  feed_until(target);
  last_tick_ns_ = steady_ns();
  publish_status();
}

void RecordingPlayer::tick() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!playing_) return;
  const std::int64_t now = steady_ns();
  const auto advance = static_cast<std::uint64_t>(static_cast<double>(now - last_tick_ns_) * rate_);
  last_tick_ns_ = now;
  const std::uint64_t target = std::min(cursor_log_ns_.load() + advance, last_log_ns_);
  cursor_log_ns_ = target;
  feed_until(target);
  if (target >= last_log_ns_) playing_ = false;  // the end
  publish_status();
}

void RecordingPlayer::publish_status() {
  if (state_ != nullptr) state_->set_extra("replay", status_locked());
}

nlohmann::json RecordingPlayer::status() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return status_locked();
}

nlohmann::json RecordingPlayer::status_locked() const {
  return {{"start_s", mission_s_of(first_log_ns_)},
          {"end_s", mission_s_of(last_log_ns_)},
          {"cursor_s", mission_s_of(cursor_log_ns_.load())},
          {"playing", playing_},
          {"rate", rate_},
          {"damage", damage_}};
}

nlohmann::json RecordingPlayer::control(const nlohmann::json& request) {
  const std::string action = request.value("action", "");
  if (action == "play") {
    play(request.value("rate", 1.0));
  } else if (action == "pause") {
    pause();
  } else if (action == "seek") {
    if (!request.contains("t_s") || !request["t_s"].is_number()) throw std::invalid_argument("seek needs a number t_s");
    seek(request["t_s"].get<double>());
  } else {
    throw std::invalid_argument("action must be play, pause or seek");
  }
  return status();
}

}  // namespace sarloc::dashboard
