// --recover: a file cut short keeps every message before the cut and becomes whole.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "sarloc/recording/mcap_reader.hpp"
#include "sarloc/recording/mcap_recovery.hpp"
#include "sarloc/recording/mcap_writer.hpp"

namespace sarloc::recording {
namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("sarloc_recover_" + std::to_string(::getpid()) + "_" + name)).string();
}

TEST(McapRecovery, ACutFileKeepsEveryWholeChunkAndGetsASummary) {
  const std::string path = temp_path("cut.mcap");
  std::uint64_t first_flush = 0;
  std::uint64_t second_flush = 0;
  {
    McapWriterOptions options;
    options.chunk_size_bytes = 2048;
    McapWriter writer(path, options);
    const auto schema = writer.add_schema("T", "omgidl", "struct T { long a; };");
    const auto channel = writer.add_channel("t", schema, "cdr", {{"durability", "VOLATILE"}});
    std::vector<std::uint8_t> bytes(100, 3);
    for (std::uint32_t i = 0; i < 150; ++i) writer.write(channel, i, i * 1000, i * 1000, bytes.data(), bytes.size());
    writer.flush();
    first_flush = writer.bytes_written();
    for (std::uint32_t i = 150; i < 200; ++i) writer.write(channel, i, i * 1000, i * 1000, bytes.data(), bytes.size());
    writer.flush();
    second_flush = writer.bytes_written();
    writer.close();
  }
  // Cut inside what the second flush wrote: the first 150 messages must all survive.
  std::filesystem::resize_file(path, (first_flush + second_flush) / 2);
  const RecoveryResult result = recover_mcap(path);
  EXPECT_FALSE(result.was_complete);
  EXPECT_FALSE(result.damage.empty());
  EXPECT_GE(result.messages, 150u);
  EXPECT_LT(result.messages, 200u);  // the cut chunk is gone, nothing else
  McapReadResult reread = read_mcap(path, {});
  EXPECT_TRUE(reread.complete) << reread.damage;
  EXPECT_EQ(reread.messages, result.messages);
  EXPECT_TRUE(std::filesystem::exists(path + ".damaged"));

  // Recovering a whole file changes nothing.
  const RecoveryResult again = recover_mcap(path);
  EXPECT_TRUE(again.was_complete);
  EXPECT_EQ(again.messages, result.messages);
  std::remove(path.c_str());
  std::remove((path + ".damaged").c_str());
}

TEST(McapRecovery, AFileThatIsNotMcapIsRefused) {
  const std::string path = temp_path("text.mcap");
  std::ofstream(path) << "no magic here";
  EXPECT_THROW(recover_mcap(path), RecordingError);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace sarloc::recording
