#include "sarloc/recording/mcap_writer.hpp"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <limits>

#include "record_bytes.hpp"
#include "sarloc/recording/compression.hpp"

namespace sarloc::recording {

using detail::ByteWriter;

namespace {

// The Schema and Channel records: written once in the data section, again in the summary.
void put_schema_record(ByteWriter& out, const Schema& schema) {
  ByteWriter content;
  content.put<std::uint16_t>(schema.id);
  content.put_string(schema.name);
  content.put_string(schema.encoding);
  content.put_string(schema.data);
  out.put_record(Opcode::kSchema, content);
}

void put_channel_record(ByteWriter& out, const Channel& channel) {
  ByteWriter content;
  content.put<std::uint16_t>(channel.id);
  content.put<std::uint16_t>(channel.schema_id);
  content.put_string(channel.topic);
  content.put_string(channel.message_encoding);
  content.put_map(channel.metadata);
  out.put_record(Opcode::kChannel, content);
}

}  // namespace

void McapWriterOptions::validate() const {
  if (profile.rfind("x-", 0) != 0) {
    throw RecordingError("profile = '" + profile + "': a custom MCAP profile must start with 'x-'");
  }
  if (chunk_size_bytes < 1024 || chunk_size_bytes > (64u << 20)) {
    throw RecordingError("chunk_size_bytes = " + std::to_string(chunk_size_bytes) + ": must be 1 KiB to 64 MiB");
  }
}

McapWriter::McapWriter(std::string path, McapWriterOptions options) : path_(std::move(path)), options_(std::move(options)) {
  options_.validate();
  fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw RecordingError("cannot create recording '" + path_ + "': " + std::strerror(errno));
  data_crc_ = crc32(0L, Z_NULL, 0);
  ByteWriter start;
  start.put_bytes(kMagic, sizeof kMagic);
  ByteWriter header;
  header.put_string(options_.profile);
  header.put_string(options_.library);
  start.put_record(Opcode::kHeader, header);
  append(start.bytes());
  flush();
}

McapWriter::~McapWriter() {
  try {
    close();
  } catch (const RecordingError&) {
    // The owner that wanted to know called close() itself.
  }
  if (fd_ >= 0) ::close(fd_);
}

void McapWriter::check_open(const char* what) const {
  if (fd_ < 0) throw RecordingError(std::string("cannot ") + what + ": recording '" + path_ + "' is closed");
}

void McapWriter::append(const std::vector<std::uint8_t>& bytes, bool data_section) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      const std::string reason = std::strerror(errno);
      ::close(fd_);
      fd_ = -1;  // a half-written record: refuse everything after it
      throw RecordingError("cannot write recording '" + path_ + "': " + reason);
    }
    done += static_cast<std::size_t>(n);
  }
  if (data_section) data_crc_ = crc32(data_crc_, bytes.data(), static_cast<uInt>(bytes.size()));
  offset_ += bytes.size();
}

std::uint16_t McapWriter::add_schema(const std::string& name, const std::string& encoding, const std::string& data) {
  check_open("add a schema");
  if (schemas_.size() >= std::numeric_limits<std::uint16_t>::max()) throw RecordingError("too many schemas");
  Schema schema{static_cast<std::uint16_t>(schemas_.size() + 1), name, encoding, data};  // 0 means "no schema"
  ByteWriter record;
  put_schema_record(record, schema);
  append(record.bytes());
  schemas_.push_back(schema);
  return schema.id;
}

std::uint16_t McapWriter::add_channel(const std::string& topic, std::uint16_t schema_id,
                                      const std::string& message_encoding, const StringMap& metadata) {
  check_open("add a channel");
  if (schema_id > schemas_.size()) throw RecordingError("channel '" + topic + "': unknown schema id " + std::to_string(schema_id));
  if (channels_.size() >= std::numeric_limits<std::uint16_t>::max()) throw RecordingError("too many channels");
  Channel channel{static_cast<std::uint16_t>(channels_.size()), schema_id, topic, message_encoding, metadata};
  ByteWriter record;
  put_channel_record(record, channel);
  append(record.bytes());
  channels_.push_back(channel);
  return channel.id;
}

void McapWriter::write(const Message& message) {
  write(message.channel_id, message.sequence, message.log_time_ns, message.publish_time_ns, message.data.data(),
        message.data.size());
}

void McapWriter::write(std::uint16_t channel_id, std::uint32_t sequence, std::uint64_t log_time_ns,
                       std::uint64_t publish_time_ns, const std::uint8_t* data, std::size_t size) {
  check_open("write a message");
  if (channel_id >= channels_.size()) throw RecordingError("message on unknown channel id " + std::to_string(channel_id));
  const std::uint64_t offset_in_chunk = chunk_.size();
  // Message record written straight into the chunk buffer (no intermediate copy of the payload).
  const std::uint64_t content_size = 2 + 4 + 8 + 8 + size;
  ByteWriter head;
  head.put<std::uint8_t>(static_cast<std::uint8_t>(Opcode::kMessage));
  head.put<std::uint64_t>(content_size);
  head.put<std::uint16_t>(channel_id);
  head.put<std::uint32_t>(sequence);
  head.put<std::uint64_t>(log_time_ns);
  head.put<std::uint64_t>(publish_time_ns);
  chunk_.insert(chunk_.end(), head.bytes().begin(), head.bytes().end());
  chunk_.insert(chunk_.end(), data, data + size);
  if (chunk_index_.empty()) {
    chunk_start_time_ = log_time_ns;
    chunk_end_time_ = log_time_ns;
  }
  chunk_start_time_ = std::min(chunk_start_time_, log_time_ns);
  chunk_end_time_ = std::max(chunk_end_time_, log_time_ns);
  chunk_index_[channel_id].emplace_back(log_time_ns, offset_in_chunk);

  if (statistics_.message_count == 0) {
    statistics_.message_start_time_ns = log_time_ns;
    statistics_.message_end_time_ns = log_time_ns;
  }
  statistics_.message_start_time_ns = std::min(statistics_.message_start_time_ns, log_time_ns);
  statistics_.message_end_time_ns = std::max(statistics_.message_end_time_ns, log_time_ns);
  ++statistics_.message_count;
  ++statistics_.channel_message_counts[channel_id];
  if (chunk_.size() >= options_.chunk_size_bytes) write_chunk();
}

void McapWriter::write_chunk() {
  if (chunk_index_.empty()) return;
  const std::vector<std::uint8_t> compressed = compress(options_.compression, chunk_);
  ByteWriter content;
  content.put<std::uint64_t>(chunk_start_time_);
  content.put<std::uint64_t>(chunk_end_time_);
  content.put<std::uint64_t>(chunk_.size());
  content.put<std::uint32_t>(static_cast<std::uint32_t>(crc32(crc32(0L, Z_NULL, 0), chunk_.data(), static_cast<uInt>(chunk_.size()))));
  content.put_string(compression_name(options_.compression));
  content.put<std::uint64_t>(compressed.size());
  content.put_bytes(compressed.data(), compressed.size());
  ByteWriter bytes;
  bytes.put_record(Opcode::kChunk, content);

  ChunkIndexEntry entry;
  entry.start_time = chunk_start_time_;
  entry.end_time = chunk_end_time_;
  entry.offset = offset_;
  entry.length = bytes.bytes().size();
  entry.compressed_size = compressed.size();
  entry.uncompressed_size = chunk_.size();
  for (const auto& [channel_id, entries] : chunk_index_) {
    entry.index_offsets.emplace_back(channel_id, offset_ + bytes.bytes().size());
    ByteWriter index;
    index.put<std::uint16_t>(channel_id);
    index.put<std::uint32_t>(static_cast<std::uint32_t>(entries.size() * 16));
    for (const auto& [time, offset] : entries) {
      index.put<std::uint64_t>(time);
      index.put<std::uint64_t>(offset);
    }
    const std::size_t before = bytes.bytes().size();
    bytes.put_record(Opcode::kMessageIndex, index);
    entry.index_length += bytes.bytes().size() - before;
  }
  // One write per chunk and its indexes: a crash leaves either all of it or a cut-off tail.
  append(bytes.bytes());
  chunk_indexes_.push_back(std::move(entry));
  ++statistics_.chunk_count;
  chunk_.clear();
  chunk_index_.clear();
}

void McapWriter::write_metadata(const Metadata& metadata) {
  check_open("write metadata");
  ByteWriter content;
  content.put_string(metadata.name);
  content.put_map(metadata.values);
  ByteWriter record;
  record.put_record(Opcode::kMetadata, content);
  // Metadata goes between chunks, never inside one: write the open chunk first.
  write_chunk();
  metadata_indexes_.push_back({offset_, record.bytes().size(), metadata.name});
  append(record.bytes());
  ++statistics_.metadata_count;
}

void McapWriter::flush() {
  check_open("flush");
  write_chunk();
  if (options_.sync_on_flush && ::fdatasync(fd_) != 0) {
    throw RecordingError("cannot sync recording '" + path_ + "': " + std::strerror(errno));
  }
}

void McapWriter::close() {
  if (fd_ < 0) return;
  write_chunk();
  ByteWriter data_end_content;
  data_end_content.put<std::uint32_t>(static_cast<std::uint32_t>(data_crc_));
  ByteWriter data_end;
  data_end.put_record(Opcode::kDataEnd, data_end_content);
  append(data_end.bytes(), false);

  // Summary section, grouped by opcode so that Summary Offset records can point at each group.
  const std::uint64_t summary_start = offset_;
  ByteWriter summary;
  struct Group {
    Opcode opcode;
    std::uint64_t start, length;
  };
  std::vector<Group> groups;
  auto group = [&](Opcode opcode, auto&& write_records) {
    const std::uint64_t start = summary.bytes().size();
    write_records();
    const std::uint64_t length = summary.bytes().size() - start;
    if (length > 0) groups.push_back({opcode, summary_start + start, length});
  };
  group(Opcode::kSchema, [&] {
    for (const auto& schema : schemas_) put_schema_record(summary, schema);
  });
  group(Opcode::kChannel, [&] {
    for (const auto& channel : channels_) put_channel_record(summary, channel);
  });
  group(Opcode::kStatistics, [&] {
    ByteWriter content;
    content.put<std::uint64_t>(statistics_.message_count);
    content.put<std::uint16_t>(static_cast<std::uint16_t>(schemas_.size()));
    content.put<std::uint32_t>(static_cast<std::uint32_t>(channels_.size()));
    content.put<std::uint32_t>(0);  // attachments
    content.put<std::uint32_t>(statistics_.metadata_count);
    content.put<std::uint32_t>(statistics_.chunk_count);
    content.put<std::uint64_t>(statistics_.message_start_time_ns);
    content.put<std::uint64_t>(statistics_.message_end_time_ns);
    ByteWriter counts;
    for (const auto& [channel_id, count] : statistics_.channel_message_counts) {
      counts.put<std::uint16_t>(channel_id);
      counts.put<std::uint64_t>(count);
    }
    content.put<std::uint32_t>(static_cast<std::uint32_t>(counts.bytes().size()));
    content.put_bytes(counts.bytes().data(), counts.bytes().size());
    summary.put_record(Opcode::kStatistics, content);
  });
  group(Opcode::kChunkIndex, [&] {
    for (const auto& entry : chunk_indexes_) {
      ByteWriter content;
      content.put<std::uint64_t>(entry.start_time);
      content.put<std::uint64_t>(entry.end_time);
      content.put<std::uint64_t>(entry.offset);
      content.put<std::uint64_t>(entry.length);
      content.put<std::uint32_t>(static_cast<std::uint32_t>(entry.index_offsets.size() * 10));
      for (const auto& [channel_id, offset] : entry.index_offsets) {
        content.put<std::uint16_t>(channel_id);
        content.put<std::uint64_t>(offset);
      }
      content.put<std::uint64_t>(entry.index_length);
      content.put_string(compression_name(options_.compression));
      content.put<std::uint64_t>(entry.compressed_size);
      content.put<std::uint64_t>(entry.uncompressed_size);
      summary.put_record(Opcode::kChunkIndex, content);
    }
  });
  group(Opcode::kMetadataIndex, [&] {
    for (const auto& entry : metadata_indexes_) {
      ByteWriter content;
      content.put<std::uint64_t>(entry.offset);
      content.put<std::uint64_t>(entry.length);
      content.put_string(entry.name);
      summary.put_record(Opcode::kMetadataIndex, content);
    }
  });
  const std::uint64_t summary_offset_start = summary_start + summary.bytes().size();
  for (const auto& g : groups) {
    ByteWriter content;
    content.put<std::uint8_t>(static_cast<std::uint8_t>(g.opcode));
    content.put<std::uint64_t>(g.start);
    content.put<std::uint64_t>(g.length);
    summary.put_record(Opcode::kSummaryOffset, content);
  }
  // Footer: the summary CRC covers the summary, the summary offsets and the footer up to itself.
  ByteWriter footer_head;
  footer_head.put<std::uint8_t>(static_cast<std::uint8_t>(Opcode::kFooter));
  footer_head.put<std::uint64_t>(8 + 8 + 4);
  footer_head.put<std::uint64_t>(summary_start);
  footer_head.put<std::uint64_t>(summary_offset_start);
  unsigned long summary_crc = crc32(0L, Z_NULL, 0);
  summary_crc = crc32(summary_crc, summary.bytes().data(), static_cast<uInt>(summary.bytes().size()));
  summary_crc = crc32(summary_crc, footer_head.bytes().data(), static_cast<uInt>(footer_head.bytes().size()));
  ByteWriter tail = std::move(summary);
  tail.put_bytes(footer_head.bytes().data(), footer_head.bytes().size());
  tail.put<std::uint32_t>(static_cast<std::uint32_t>(summary_crc));
  tail.put_bytes(kMagic, sizeof kMagic);
  append(tail.bytes(), false);
  if (::fsync(fd_) != 0) {
    const std::string reason = std::strerror(errno);
    ::close(fd_);
    fd_ = -1;
    throw RecordingError("cannot sync recording '" + path_ + "': " + reason);
  }
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) throw RecordingError("cannot close recording '" + path_ + "': " + std::strerror(errno));
}

}  // namespace sarloc::recording
