// sarloc's recorder against an independent reader: samples published on real topics are
// recorded, and the MCAP project's reader with Foxglove's IDL decoder (tests/js, installed by
// scripts/install-deps) finds every one, with the values that were published.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "support/dds_test_domains.hpp"
#include "support/dds_test_helpers.hpp"
#include "support/required_program.hpp"
#include "support/sample_messages.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/raw_topic_type.hpp"
#include "sarloc/dds/idl_schemas.hpp"
#include "sarloc/dds/mission_clock.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/recorder.hpp"
#include "sarloc/dds/replayer.hpp"
#include "sarloc/dds/topic_catalog.hpp"
#include "sarloc/dds/writer.hpp"
#include "sarloc/recording/mcap_reader.hpp"
#include "sarloc/recording/mcap_writer.hpp"

namespace sarloc::test {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

struct Command {
  int exit_code = -1;
  std::string output;
};

Command run(const std::string& command) {
  Command result;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return result;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) result.output += buffer;
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

/// The independent reader's report of `path` (tests/js/check_mcap.mjs).
json independent_report(const fs::path& path, int* exit_code = nullptr) {
  EXPECT_TRUE(sarloc::test::has_node());
  const Command command = run("node " SARLOC_SOURCE_DIR "/tests/js/check_mcap.mjs '" + path.string() + "'");
  if (exit_code != nullptr) *exit_code = command.exit_code;
  const auto start = command.output.find('{');
  if (start == std::string::npos) return json{{"errors", {"no report: " + command.output}}};
  return json::parse(command.output.substr(start));
}

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("sarloc-recorder-test-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(Recorder, AnIndependentReaderDecodesEveryRecordedSampleWithThePublishedValues) {
  const fs::path dir = temp_dir("values");
  auto publisher = make_participant(kDomainRecorder, "publisher");
  dds::Writer<::sarloc::FieldMeasurement> field_writer(publisher);
  dds::Writer<::sarloc::Odometry> odometry_writer(publisher);
  dds::Writer<::sarloc::FusedVictim> victim_writer(publisher);
  dds::Writer<::sarloc::IncidentAlarm> alarm_writer(publisher);
  dds::Writer<::sarloc::TeamStatus> team_writer(publisher);

  dds::RecorderConfig config;
  config.output_path = (dir / "values.mcap").string();
  config.metadata = {{"mission", "recorder test"}};
  config.block = {"sarloc/guidance"};  // block list: never recorded, not even as a channel
  auto recorder_participant = make_participant(kDomainRecorder, "recorder");
  dds::Recorder recorder(recorder_participant, config);
  ASSERT_TRUE(eventually(
      [&] {
        auto m = recorder.matched_writers();
        return m["sarloc/field_measurement"] >= 1 && m["sarloc/odometry"] >= 1 && m["sarloc/fused_victim"] >= 1 &&
               m["sarloc/incident_alarm"] >= 1 && m["sarloc/team_status"] >= 1;
      },
      std::chrono::seconds(10)));
  // Matched both ways: a VOLATILE writer that has not yet discovered the reader sends it nothing.
  ASSERT_TRUE(field_writer.wait_for_readers(1, std::chrono::seconds(10)));
  ASSERT_TRUE(odometry_writer.wait_for_readers(1, std::chrono::seconds(10)));
  ASSERT_TRUE(victim_writer.wait_for_readers(1, std::chrono::seconds(10)));
  ASSERT_TRUE(alarm_writer.wait_for_readers(1, std::chrono::seconds(10)));
  ASSERT_TRUE(team_writer.wait_for_readers(1, std::chrono::seconds(10)));

  constexpr int kMeasurements = 40;
  for (int i = 0; i < kMeasurements; ++i) {
    auto m = sample_field_measurement();
    m.sequence = 1000 + i;
    m.signal_id = 1 + i % 3;  // three instances
    ASSERT_TRUE(field_writer.write(dds::to_idl(m)));
    auto o = sample_odometry();
    o.sequence = 1 + i;
    ASSERT_TRUE(odometry_writer.write(dds::to_idl(o)));
  }
  for (std::uint32_t id = 11; id <= 13; ++id) {
    auto v = sample_fused_victim();
    v.victim_id = id;
    ASSERT_TRUE(victim_writer.write(dds::to_idl(v)));
  }
  ASSERT_TRUE(alarm_writer.write(dds::to_idl(sample_incident_alarm())));
  ASSERT_TRUE(team_writer.write(dds::to_idl(sample_team_status())));
  ASSERT_TRUE(eventually(
      [&] {
        auto c = recorder.counters();
        return c["sarloc/field_measurement"].written == kMeasurements && c["sarloc/odometry"].written == kMeasurements &&
               c["sarloc/fused_victim"].written == 3 && c["sarloc/incident_alarm"].written == 1 &&
               c["sarloc/team_status"].written == 1;
      },
      std::chrono::seconds(10)));
  recorder.close();
  const auto counters = recorder.counters();
  EXPECT_EQ(recorder.files().size(), 1u);

  int exit_code = -1;
  const json report = independent_report(config.output_path, &exit_code);
  ASSERT_EQ(exit_code, 0) << report.dump(1);
  EXPECT_TRUE(report["errors"].empty()) << report["errors"].dump();
  EXPECT_EQ(report["header"]["profile"], "x-sarloc");
  EXPECT_FALSE(report["channels"].contains("sarloc/guidance"));
  // Every recorded sarloc topic is a channel with its omgidl schema and its QoS; the counts the
  // independent reader finds are the counts the recorder says it wrote.
  for (const auto& [topic, c] : counters) {
    if (topic == "sarloc/guidance") continue;
    ASSERT_TRUE(report["channels"].contains(topic)) << topic;
    const json& channel = report["channels"][topic];
    EXPECT_EQ(channel["messageEncoding"], "cdr") << topic;
    EXPECT_EQ(channel["schemaEncoding"], "omgidl") << topic;
    EXPECT_EQ(channel["count"].get<std::uint64_t>(), c.written) << topic;
    EXPECT_EQ(channel["decodeFailures"], 0) << topic;
    EXPECT_TRUE(channel["metadata"].contains("reliability")) << topic;
    EXPECT_EQ(c.lost, 0u) << topic;
  }
  // The values, decoded from the recorded schema by a decoder that is not sarloc's.
  const json& field = report["channels"]["sarloc/field_measurement"];
  EXPECT_EQ(field["schemaName"], "sarloc::FieldMeasurement");
  EXPECT_EQ(field["first"]["rescuer_id"], "rescuer-alpha");
  EXPECT_EQ(field["first"]["sequence_number"], 1000);
  EXPECT_EQ(field["last"]["sequence_number"], 1000 + kMeasurements - 1);
  EXPECT_DOUBLE_EQ(field["first"]["field"]["x"].get<double>(), 1.5e-6);
  EXPECT_DOUBLE_EQ(field["first"]["field"]["z"].get<double>(), 3.25e-8);
  const json& odometry = report["channels"]["sarloc/odometry"];
  EXPECT_EQ(odometry["last"]["sequence_number"], kMeasurements);
  EXPECT_DOUBLE_EQ(odometry["first"]["translation"]["x"].get<double>(), 0.98);
  const json& victim = report["channels"]["sarloc/fused_victim"];
  EXPECT_EQ(victim["last"]["victim_id"], 13);
  EXPECT_EQ(victim["last"]["sources"].size(), 2u);
  EXPECT_EQ(victim["last"]["sources"][1]["rescuer_id"], "rescuer-bravo");
  EXPECT_EQ(report["channels"]["sarloc/incident_alarm"]["last"]["acknowledged_by"], "ic-chief");
  EXPECT_EQ(report["channels"]["sarloc/team_status"]["last"]["members"].size(), 3u);
  EXPECT_EQ(report["metadata"]["sarloc.recording"]["mission"], "recorder test");
  EXPECT_TRUE(report["metadata"].contains("sarloc.recorder_counters"));
  fs::remove_all(dir);
}

// SIGKILL mid-stream: the file holds every sample up to the last flush (at most flush_period_s
// before the kill), and --recover makes it whole for any reader.
TEST(Recorder, AKilledRecorderLosesOnlyTheLastSecondAndRecoverMakesTheFileWhole) {
  const fs::path dir = temp_dir("kill");
  const fs::path file = dir / "killed.mcap";
  const std::string log = (dir / "record.log").string();
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const std::string domain = std::to_string(static_cast<int>(kDomainRecorderKill));
    ::execl(SARLOC_BIN_DIR "/sarloc-record", "sarloc-record", "-c", SARLOC_SOURCE_DIR "/config/missions/default.yaml",
            "--domain", domain.c_str(), "-o", file.c_str(), "--log-level", "warn", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  auto publisher = make_participant(kDomainRecorderKill, "publisher");
  dds::Writer<::sarloc::Odometry> writer(publisher);
  ASSERT_TRUE(writer.wait_for_readers(1, std::chrono::seconds(15)));
  // 50 Hz for 4 s, then SIGKILL while still publishing.
  std::vector<std::chrono::steady_clock::time_point> sent_at;
  auto odometry = sample_odometry();
  const auto start = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point kill_time;
  for (std::uint64_t seq = 1; seq <= 300; ++seq) {
    odometry.sequence = seq;
    ASSERT_TRUE(writer.write(dds::to_idl(odometry)));
    sent_at.push_back(std::chrono::steady_clock::now());
    if (seq == 200) {
      ::kill(pid, SIGKILL);
      kill_time = std::chrono::steady_clock::now();
    }
    std::this_thread::sleep_until(start + std::chrono::milliseconds(20 * seq));
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));

  // Everything sent more than the flush period (1 s, the default) plus 0.2 s of slack before the kill.
  std::uint64_t must_have = 0;
  for (std::size_t i = 0; i < sent_at.size(); ++i) {
    if (sent_at[i] < kill_time - std::chrono::milliseconds(1200)) must_have = i + 1;
  }
  ASSERT_GT(must_have, 100u);
  auto sequences_in = [](const fs::path& path, recording::McapReadResult* result) {
    std::vector<std::uint64_t> seen;
    std::map<std::uint16_t, std::string> topics;
    recording::McapVisitor visitor;
    visitor.on_channel = [&](const recording::Channel& c) { topics[c.id] = c.topic; };
    visitor.on_message = [&](const recording::Message& m) {
      if (topics[m.channel_id] != "sarloc/odometry") return;
      ::sarloc::Odometry o;
      if (dds::decode_payload<::sarloc::OdometryPubSubType>(m.data, o)) seen.push_back(o.sequence_number());
    };
    *result = recording::read_mcap(path.string(), visitor);
    return seen;
  };
  recording::McapReadResult before;
  const auto seen_before = sequences_in(file, &before);
  EXPECT_FALSE(before.complete);
  ASSERT_GE(seen_before.size(), must_have) << before.damage;
  for (std::uint64_t k = 0; k < must_have; ++k) ASSERT_EQ(seen_before[k], k + 1) << "gap in what was flushed";

  const Command recover = run(SARLOC_BIN_DIR "/sarloc-record --recover '" + file.string() + "'");
  ASSERT_EQ(recover.exit_code, 0) << recover.output;
  recording::McapReadResult after;
  const auto seen_after = sequences_in(file, &after);
  EXPECT_TRUE(after.complete) << after.damage;
  EXPECT_EQ(seen_after, seen_before);
  const json report = independent_report(file);
  EXPECT_TRUE(report["errors"].empty()) << report["errors"].dump();
  EXPECT_EQ(report["channels"]["sarloc/odometry"]["count"].get<std::size_t>(), seen_before.size());
  (void)log;
  fs::remove_all(dir);
}

// Rotation: by duration here (size works the same way, checked after each flush); every file
// is whole on its own, and together they hold every sample, none twice.
TEST(Recorder, RotatesIntoWholeFilesThatTogetherHoldEverySample) {
  const fs::path dir = temp_dir("rotate");
  auto publisher = make_participant(kDomainRecorderRotate, "publisher");
  dds::Writer<::sarloc::Odometry> writer(publisher);
  dds::RecorderConfig config;
  config.output_path = (dir / "rotated.mcap").string();
  config.allow = {"sarloc/odometry"};
  config.flush_period_s = 0.25;
  config.rotate_duration_s = 1.0;
  auto recorder_participant = make_participant(kDomainRecorderRotate, "recorder");
  dds::Recorder recorder(recorder_participant, config);
  ASSERT_TRUE(writer.wait_for_readers(1, std::chrono::seconds(10)));
  auto odometry = sample_odometry();
  constexpr std::uint64_t kSamples = 175;  // 3.5 s at 50 Hz
  for (std::uint64_t seq = 1; seq <= kSamples; ++seq) {
    odometry.sequence = seq;
    ASSERT_TRUE(writer.write(dds::to_idl(odometry)));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_TRUE(eventually([&] { return recorder.counters()["sarloc/odometry"].written == kSamples; }, std::chrono::seconds(10)));
  recorder.close();
  const auto files = recorder.files();
  ASSERT_GE(files.size(), 3u);
  EXPECT_EQ(fs::path(files[1]).filename(), "rotated-001.mcap");
  std::vector<std::uint64_t> all;
  for (const auto& file : files) {
    std::map<std::uint16_t, std::string> topics;
    recording::McapVisitor visitor;
    visitor.on_channel = [&](const recording::Channel& c) { topics[c.id] = c.topic; };
    visitor.on_message = [&](const recording::Message& m) {
      ::sarloc::Odometry o;
      if (topics[m.channel_id] == "sarloc/odometry" && dds::decode_payload<::sarloc::OdometryPubSubType>(m.data, o)) {
        all.push_back(o.sequence_number());
      }
    };
    const auto result = recording::read_mcap(file, visitor);
    EXPECT_TRUE(result.complete) << file << ": " << result.damage;
  }
  ASSERT_EQ(all.size(), kSamples);
  for (std::uint64_t k = 0; k < kSamples; ++k) EXPECT_EQ(all[k], k + 1);
  fs::remove_all(dir);
}

// The replayer on a recording made here: only the chosen topics, only between start and end,
// each payload untouched, at the recorded pace times the rate.
TEST(Replayer, SendsTheChosenTopicsBetweenStartAndEndAtTheRecordedPaceTimesTheRate) {
  const fs::path dir = temp_dir("replay");
  const std::string path = (dir / "made.mcap").string();
  constexpr std::int64_t kEpoch = 1'800'000'000'000'000'000LL;
  {
    recording::McapWriter writer(path, {});
    writer.write_metadata({"sarloc.recording", {{"epoch_ns", std::to_string(kEpoch)}, {"speedup", "2"}}});
    std::map<std::string, std::uint16_t> channels;
    for (const auto& topic : dds::topic_catalog()) {
      const auto schema = writer.add_schema(topic.type_name, "omgidl", dds::self_contained_idl(topic.idl_file));
      channels[topic.name] = writer.add_channel(topic.name, schema, "cdr", {});
    }
    // 20 odometry and 20 guidance samples, one every 100 ms of wall time = 0.2 mission s.
    for (int k = 0; k < 20; ++k) {
      auto o = sample_odometry();
      o.sequence = static_cast<std::uint64_t>(k + 1);
      const auto bytes = dds::encode_payload<::sarloc::OdometryPubSubType>(dds::to_idl(o));
      const auto at = static_cast<std::uint64_t>(kEpoch + k * 100'000'000LL);
      writer.write(channels["sarloc/odometry"], 0, at, at, bytes.data(), bytes.size());
      const auto g = dds::encode_payload<::sarloc::GuidancePubSubType>(dds::to_idl(sample_guidance()));
      writer.write(channels["sarloc/guidance"], 0, at, at, g.data(), g.size());
    }
    writer.close();
  }
  auto subscriber = make_participant(kDomainReplayer, "subscriber");
  Inbox<std::pair<std::uint64_t, std::chrono::steady_clock::time_point>> inbox;
  std::atomic<int> guidance{0};
  dds::Reader<::sarloc::Odometry> odometry_reader(subscriber, [&](const ::sarloc::Odometry& o, const auto&) {
    inbox.push({o.sequence_number(), std::chrono::steady_clock::now()});
  });
  dds::Reader<::sarloc::Guidance> guidance_reader(subscriber, [&](const ::sarloc::Guidance&, const auto&) { ++guidance; });

  dds::ReplayConfig config;
  config.recording = path;
  config.topics = {"sarloc/odometry"};
  config.start_s = 1.0;  // mission s: sample 6 (k = 5) on
  config.end_s = 3.0;    // up to sample 16 (k = 15)
  config.rate = 2.0;
  auto publisher = make_participant(kDomainReplayer, "replayer");
  dds::Replayer replayer(publisher, config);
  EXPECT_EQ(replayer.timeline().epoch_ns, kEpoch);
  EXPECT_DOUBLE_EQ(replayer.timeline().speedup, 2.0);
  ASSERT_TRUE(odometry_reader.wait_for_writers(1, std::chrono::seconds(10)));
  const auto result = replayer.run(dds::MissionClock::wall_now_ns() + 200'000'000, {});
  EXPECT_EQ(result.published, 11u);
  EXPECT_EQ(result.published_by_topic.at("sarloc/odometry"), 11u);
  const auto got = inbox.wait_for(11, std::chrono::seconds(5));
  ASSERT_EQ(got.size(), 11u);
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i].first, 6 + i);
  // 10 gaps of 100 ms recorded, at rate 2: 0.5 s.
  const double span = std::chrono::duration<double>(got.back().second - got.front().second).count();
  EXPECT_NEAR(span, 0.5, 0.1);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_EQ(guidance.load(), 0) << "guidance was not chosen";
  fs::remove_all(dir);
}

TEST(Recorder, AFullDiskOrANonMcapFileIsAClearErrorWithExitCode4) {
  const fs::path dir = temp_dir("errors");
  const std::string domain = std::to_string(static_cast<int>(kDomainRecorderFullDisk));
  const Command full = run(SARLOC_BIN_DIR "/sarloc-record -c " SARLOC_SOURCE_DIR
                           "/config/missions/default.yaml --domain " + domain + " -o /dev/full --duration 1");
  EXPECT_EQ(full.exit_code, 4) << full.output;
  EXPECT_NE(full.output.find("/dev/full"), std::string::npos) << full.output;
  EXPECT_NE(full.output.find("No space left"), std::string::npos) << full.output;

  const fs::path text = dir / "notes.mcap";
  std::ofstream(text) << "not a recording";
  const Command recover = run(SARLOC_BIN_DIR "/sarloc-record --recover '" + text.string() + "'");
  EXPECT_EQ(recover.exit_code, 4) << recover.output;
  EXPECT_NE(recover.output.find("not an MCAP file"), std::string::npos) << recover.output;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sarloc::test
