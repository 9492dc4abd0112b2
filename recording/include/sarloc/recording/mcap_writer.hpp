#pragma once
// Writes an MCAP file that any MCAP reader opens (https://mcap.dev/spec): Schema and Channel
// records in the data section as they are added, messages in compressed Chunks with one Message
// Index per channel, Metadata, then on close() the summary (Schema, Channel, Statistics, Chunk
// Index, Metadata Index), Summary Offsets, the Footer and every CRC.
//
// Crash safety: flush() ends the open chunk and hands it to the kernel, so a process killed
// after flush() leaves a file whose every record up to there is complete; a sequential reader
// (or `sarloc-record --recover`) reads it. Any failed write (disk full, unwritable path)
// throws RecordingError naming the file, and the writer refuses further writes.
//
//   McapWriter writer("mission.mcap", {});
//   auto schema = writer.add_schema("sarloc::Odometry", "omgidl", idl_text);
//   auto channel = writer.add_channel("sarloc/odometry", schema, "cdr", {{"reliability", "RELIABLE"}});
//   writer.write(message);  // message.channel_id = channel
//   writer.close();
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "sarloc/recording/mcap_records.hpp"

namespace sarloc::recording {

struct McapWriterOptions {
  /// Header profile: custom profiles start with "x-" (MCAP registry).
  std::string profile = "x-sarloc";
  std::string library = "sarloc";
  Compression compression = Compression::kZstd;
  /// A chunk is closed once its uncompressed records reach this size (flush() closes it earlier).
  std::size_t chunk_size_bytes = 1u << 20;
  /// fdatasync after every flush: survives a power cut as well as a crash, at a cost per flush.
  bool sync_on_flush = false;

  /// Throws RecordingError naming the field, the value and the rule.
  void validate() const;
};

class McapWriter {
 public:
  /// Creates (truncates) `path` and writes the magic and the Header.
  McapWriter(std::string path, McapWriterOptions options);
  /// Closes the file if close() was not called; errors are swallowed here, so call close().
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  std::uint16_t add_schema(const std::string& name, const std::string& encoding, const std::string& data);
  std::uint16_t add_channel(const std::string& topic, std::uint16_t schema_id, const std::string& message_encoding,
                            const StringMap& metadata);
  /// Appends to the open chunk; the chunk is written when it reaches chunk_size_bytes.
  void write(const Message& message);
  void write(std::uint16_t channel_id, std::uint32_t sequence, std::uint64_t log_time_ns,
             std::uint64_t publish_time_ns, const std::uint8_t* data, std::size_t size);
  void write_metadata(const Metadata& metadata);
  /// Writes the open chunk (if any) and its indexes, and hands them to the kernel.
  void flush();
  /// Writes the summary and the footer, and closes the file. Idempotent.
  void close();

  const std::string& path() const { return path_; }
  /// Bytes in the file so far (the open chunk not included).
  std::uint64_t bytes_written() const { return offset_; }
  const Statistics& statistics() const { return statistics_; }
  bool is_open() const { return fd_ >= 0; }

 private:
  struct ChunkIndexEntry {
    std::uint64_t start_time = 0, end_time = 0, offset = 0, length = 0, index_length = 0;
    std::uint64_t compressed_size = 0, uncompressed_size = 0;
    std::vector<std::pair<std::uint16_t, std::uint64_t>> index_offsets;
  };
  struct MetadataIndexEntry {
    std::uint64_t offset = 0, length = 0;
    std::string name;
  };

  void write_chunk();
  void append(const std::vector<std::uint8_t>& bytes, bool data_section = true);
  void check_open(const char* what) const;

  std::string path_;
  McapWriterOptions options_;
  int fd_ = -1;
  std::uint64_t offset_ = 0;
  unsigned long data_crc_ = 0;
  std::vector<Schema> schemas_;
  std::vector<Channel> channels_;
  Statistics statistics_;
  std::vector<ChunkIndexEntry> chunk_indexes_;
  std::vector<MetadataIndexEntry> metadata_indexes_;

  // The open chunk: its records and, per channel, (log time, offset in the chunk).
  std::vector<std::uint8_t> chunk_;
  std::uint64_t chunk_start_time_ = 0, chunk_end_time_ = 0;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index_;
};

}  // namespace sarloc::recording
