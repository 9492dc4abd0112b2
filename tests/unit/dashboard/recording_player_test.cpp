// The debrief view: a recording made here played into the dashboard's picture, scrubbed
// forward and back.
#include <gtest/gtest.h>

#include <filesystem>
#include <thread>

#include "recording_player.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/idl_schemas.hpp"
#include "sarloc/dds/raw_topic_type.hpp"
#include "sarloc/dds/topic_catalog.hpp"
#include "sarloc/dds/topics.hpp"
#include "sarloc/recording/mcap_writer.hpp"
#include "support/sample_messages.hpp"

namespace sarloc::dashboard {
namespace {

constexpr std::int64_t kEpoch = 1'800'000'000'000'000'000LL;
constexpr std::int64_t kSec = 1'000'000'000LL;

std::string make_recording() {
  const std::string path = (std::filesystem::temp_directory_path() / "sarloc_dashboard_replay.mcap").string();
  recording::McapWriter writer(path, {});
  writer.write_metadata({"sarloc.recording", {{"epoch_ns", std::to_string(kEpoch)}, {"speedup", "2"}}});
  std::map<std::string, std::uint16_t> channels;
  for (const auto& topic : dds::topic_catalog()) {
    const auto schema = writer.add_schema(topic.type_name, "omgidl", dds::self_contained_idl(topic.idl_file));
    channels[topic.name] = writer.add_channel(topic.name, schema, "cdr", {});
  }
  // Victim 4: LOCATED at mission 10 s, FOUND at 20 s (wall 5 s and 10 s: speedup 2).
  for (int k = 1; k <= 15; ++k) {
    auto v = test::sample_fused_victim();
    v.victim_id = 4;
    v.evidence_conflict = false;
    v.state = k < 5 ? incident::VictimState::kUnconfirmed : (k < 10 ? incident::VictimState::kLocated : incident::VictimState::kFound);
    v.last_update = kEpoch + 2 * k * kSec;
    const auto bytes = dds::encode_payload<::sarloc::FusedVictimPubSubType>(dds::to_idl(v));
    const auto at = static_cast<std::uint64_t>(kEpoch + k * kSec);
    writer.write(channels["sarloc/fused_victim"], 0, at, at, bytes.data(), bytes.size());
  }
  writer.close();
  return path;
}

TEST(RecordingPlayer, ScrubsForwardAndBackAndPlaysAtARate) {
  const std::string path = make_recording();
  RecordingPlayer player(path);
  EXPECT_EQ(player.samples(), 15u);
  PictureState state(PictureStateConfig{}, [&] { return player.mission_now(); }, player.epoch_ns(), [&] { return player.wall_now_s(); });
  player.attach(state);
  auto state_of_victim = [&] {
    const auto s = state.snapshot();
    return s["victims"].empty() ? std::string("none") : s["victims"][0]["state"].get<std::string>();
  };
  player.seek(0.0);  // before the first sample: the cursor stops at the recording's start, with it
  EXPECT_EQ(state_of_victim(), "unconfirmed");
  player.seek(12.0);
  EXPECT_EQ(state_of_victim(), "LOCATED");
  player.seek(25.0);
  EXPECT_EQ(state_of_victim(), "FOUND");
  const auto before = state.version();
  player.seek(9.0);  // back: rebuilt from the start
  EXPECT_EQ(state_of_victim(), "unconfirmed");
  EXPECT_TRUE(state.needs_snapshot(before)) << "open pages get the rebuilt picture whole";
  EXPECT_NEAR(state.snapshot()["replay"]["cursor_s"].get<double>(), 9.0, 1e-6);
  EXPECT_NEAR(state.snapshot()["replay"]["end_s"].get<double>(), 30.0, 1e-6);

  player.play(20.0);  // 20x wall: 0.5 s of wall time is 10 s of recorded wall, 20 mission s
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  player.tick();
  EXPECT_EQ(state_of_victim(), "FOUND");
  EXPECT_THROW(player.control({{"action", "jump"}}), std::invalid_argument);
  EXPECT_THROW(player.control({{"action", "seek"}}), std::invalid_argument);
  EXPECT_FALSE(player.control({{"action", "pause"}})["playing"].get<bool>());
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace sarloc::dashboard
