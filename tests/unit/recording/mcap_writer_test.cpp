// The MCAP container on its own: what is written reads back, byte for byte, under every
// compression; the indexes and CRCs a reader checks are right; a write that fails says so.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "sarloc/recording/mcap_reader.hpp"
#include "sarloc/recording/mcap_writer.hpp"

namespace sarloc::recording {
namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("sarloc_mcap_" + std::to_string(::getpid()) + "_" + name)).string();
}

std::vector<std::uint8_t> payload(std::mt19937& rng, std::size_t size) {
  std::vector<std::uint8_t> bytes(size);
  for (auto& b : bytes) b = static_cast<std::uint8_t>(rng() & 0x0F);  // compressible, like CDR
  return bytes;
}

struct Written {
  std::vector<Message> messages;
};

Written write_sample_file(const std::string& path, Compression compression, std::size_t chunk_size, bool close) {
  McapWriterOptions options;
  options.compression = compression;
  options.chunk_size_bytes = chunk_size;
  McapWriter writer(path, options);
  const auto schema = writer.add_schema("sarloc::Odometry", "omgidl", "module sarloc { struct Odometry { long a; }; };");
  const auto a = writer.add_channel("sarloc/odometry", schema, "cdr", {{"reliability", "RELIABLE"}});
  const auto b = writer.add_channel("sarloc/guidance", schema, "cdr", {});
  std::mt19937 rng(7);
  Written written;
  for (std::uint32_t i = 0; i < 500; ++i) {
    Message m;
    m.channel_id = (i % 3 == 0) ? b : a;
    m.sequence = i;
    m.log_time_ns = 1'000'000'000ull + i * 10'000'000ull;
    m.publish_time_ns = m.log_time_ns - 1000;
    m.data = payload(rng, 20 + (i * 37) % 400);
    writer.write(m);
    written.messages.push_back(m);
    if (i == 250) writer.write_metadata({"mission", {{"name", "test"}}});
  }
  if (close) writer.close();
  else writer.flush();
  return written;
}

std::vector<Message> read_all(const std::string& path, McapReadResult* result = nullptr) {
  std::vector<Message> messages;
  McapVisitor visitor;
  visitor.on_message = [&](const Message& m) { messages.push_back(m); };
  const McapReadResult r = read_mcap(path, visitor);
  if (result != nullptr) *result = r;
  return messages;
}

class McapRoundTrip : public ::testing::TestWithParam<Compression> {};

TEST_P(McapRoundTrip, EveryMessageReadsBackExactlyAndTheFileIsComplete) {
  const std::string path = temp_path("roundtrip.mcap");
  const Written written = write_sample_file(path, GetParam(), 4096, true);
  McapReadResult result;
  std::vector<Schema> schemas;
  std::vector<Channel> channels;
  std::vector<Metadata> metadata;
  std::vector<Message> messages;
  McapVisitor visitor;
  visitor.on_schema = [&](const Schema& s) { schemas.push_back(s); };
  visitor.on_channel = [&](const Channel& c) { channels.push_back(c); };
  visitor.on_metadata = [&](const Metadata& m) { metadata.push_back(m); };
  visitor.on_message = [&](const Message& m) { messages.push_back(m); };
  result = read_mcap(path, visitor);
  EXPECT_TRUE(result.complete) << result.damage;
  EXPECT_EQ(result.damage, "");
  EXPECT_EQ(result.header.profile, "x-sarloc");
  EXPECT_GT(result.chunks, 5u);  // 4 KiB chunks: many of them, so the index paths are exercised
  ASSERT_EQ(schemas.size(), 1u);
  EXPECT_EQ(schemas[0].name, "sarloc::Odometry");
  EXPECT_EQ(schemas[0].encoding, "omgidl");
  ASSERT_EQ(channels.size(), 2u);
  EXPECT_EQ(channels[0].metadata.at("reliability"), "RELIABLE");
  ASSERT_EQ(metadata.size(), 1u);
  EXPECT_EQ(metadata[0].values.at("name"), "test");
  ASSERT_EQ(messages.size(), written.messages.size());
  for (std::size_t i = 0; i < messages.size(); ++i) {
    EXPECT_EQ(messages[i].channel_id, written.messages[i].channel_id);
    EXPECT_EQ(messages[i].sequence, written.messages[i].sequence);
    EXPECT_EQ(messages[i].log_time_ns, written.messages[i].log_time_ns);
    EXPECT_EQ(messages[i].publish_time_ns, written.messages[i].publish_time_ns);
    ASSERT_EQ(messages[i].data, written.messages[i].data) << "message " << i;
  }
  std::remove(path.c_str());
}

INSTANTIATE_TEST_SUITE_P(Compressions, McapRoundTrip,
                         ::testing::Values(Compression::kNone, Compression::kZstd, Compression::kLz4));

TEST(McapWriter, StatisticsCountWhatWasWritten) {
  const std::string path = temp_path("stats.mcap");
  McapWriter writer(path, {});
  const auto schema = writer.add_schema("T", "omgidl", "struct T { long a; };");
  const auto channel = writer.add_channel("t", schema, "cdr", {});
  const std::uint8_t bytes[4] = {0, 1, 0, 0};
  for (int i = 0; i < 10; ++i) writer.write(channel, i, 100 + 10 * (10 - i), 0, bytes, 4);  // out of order
  EXPECT_EQ(writer.statistics().message_count, 10u);
  EXPECT_EQ(writer.statistics().message_start_time_ns, 110u);
  EXPECT_EQ(writer.statistics().message_end_time_ns, 200u);
  EXPECT_EQ(writer.statistics().channel_message_counts.at(channel), 10u);
  writer.close();
  EXPECT_FALSE(writer.is_open());
  std::remove(path.c_str());
}

TEST(McapWriter, AFlushedButUnclosedFileReadsUpToTheFlush) {
  const std::string path = temp_path("unclosed.mcap");
  McapReadResult result;
  {
    // Flushed, then "killed": the writer is never closed (its destructor would close it, so
    // copy the file while it is open).
    McapWriterOptions options;
    McapWriter writer(path, options);
    const auto schema = writer.add_schema("T", "omgidl", "struct T { long a; };");
    const auto channel = writer.add_channel("t", schema, "cdr", {});
    const std::uint8_t bytes[4] = {0, 1, 0, 0};
    for (int i = 0; i < 30; ++i) writer.write(channel, i, i, i, bytes, 4);
    writer.flush();
    for (int i = 30; i < 40; ++i) writer.write(channel, i, i, i, bytes, 4);  // never flushed
    std::filesystem::copy_file(path, path + ".killed", std::filesystem::copy_options::overwrite_existing);
  }
  const auto messages = read_all(path + ".killed", &result);
  EXPECT_EQ(messages.size(), 30u);
  EXPECT_FALSE(result.complete);
  EXPECT_NE(result.damage.find("cut short"), std::string::npos) << result.damage;
  std::remove(path.c_str());
  std::remove((path + ".killed").c_str());
}

TEST(McapReader, ACorruptedChunkIsSkippedAndNamedAndTheRestStillReads) {
  const std::string path = temp_path("corrupt.mcap");
  const Written written = write_sample_file(path, Compression::kNone, 4096, true);
  {
    // Flip a byte in the middle of the file: inside some chunk's records.
    std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(static_cast<std::streamoff>(std::filesystem::file_size(path) / 3));
    char c = 0;
    file.read(&c, 1);
    file.seekp(-1, std::ios::cur);
    c = static_cast<char>(c ^ 0x5A);
    file.write(&c, 1);
  }
  McapReadResult result;
  const auto messages = read_all(path, &result);
  EXPECT_FALSE(result.complete);
  EXPECT_FALSE(result.damage.empty());
  EXPECT_LT(messages.size(), written.messages.size());
  EXPECT_GT(messages.size(), written.messages.size() / 2);  // only the damaged chunk is lost
  std::remove(path.c_str());
}

TEST(McapReader, AFileThatIsNotMcapIsAClearError) {
  const std::string path = temp_path("not.mcap");
  std::ofstream(path) << "this is a text file\n";
  try {
    read_mcap(path, {});
    FAIL() << "expected RecordingError";
  } catch (const RecordingError& error) {
    EXPECT_NE(std::string(error.what()).find("not an MCAP file"), std::string::npos) << error.what();
  }
  EXPECT_THROW(read_mcap(temp_path("missing.mcap"), {}), RecordingError);
  std::remove(path.c_str());
}

TEST(McapWriter, AFullDiskIsAnErrorNamingTheFileNeverASilentStop) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  try {
    McapWriter writer("/dev/full", {});
    FAIL() << "writing to /dev/full must fail";
  } catch (const RecordingError& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find("/dev/full"), std::string::npos) << what;
    EXPECT_NE(what.find("No space left"), std::string::npos) << what;
  }
}

TEST(McapWriter, AnUnwritablePathIsAnErrorNamingIt) {
  try {
    McapWriter writer("/nonexistent-folder/x.mcap", {});
    FAIL() << "expected RecordingError";
  } catch (const RecordingError& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent-folder/x.mcap"), std::string::npos);
  }
}

TEST(McapWriter, OptionsAreValidated) {
  McapWriterOptions options;
  options.profile = "sarloc";
  EXPECT_THROW(options.validate(), RecordingError);
  options.profile = "x-sarloc";
  options.chunk_size_bytes = 10;
  EXPECT_THROW(options.validate(), RecordingError);
  EXPECT_THROW(parse_compression("gzip"), RecordingError);
}

}  // namespace
}  // namespace sarloc::recording
