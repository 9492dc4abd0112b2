#include "sarloc/recording/mcap_reader.hpp"

#include <zlib.h>

#include <cstring>
#include <fstream>

#include "record_bytes.hpp"
#include "sarloc/recording/compression.hpp"

namespace sarloc::recording {

using detail::ByteReader;

namespace {

std::uint32_t crc_of(const std::uint8_t* data, std::size_t size) {
  return static_cast<std::uint32_t>(crc32(crc32(0L, Z_NULL, 0), data, static_cast<uInt>(size)));
}

std::string at_byte(std::uint64_t offset) { return "at byte " + std::to_string(offset); }

Schema parse_schema(ByteReader& in) {
  Schema schema;
  schema.id = in.get<std::uint16_t>();
  schema.name = in.get_string();
  schema.encoding = in.get_string();
  schema.data = in.get_string();
  return schema;
}

Channel parse_channel(ByteReader& in) {
  Channel channel;
  channel.id = in.get<std::uint16_t>();
  channel.schema_id = in.get<std::uint16_t>();
  channel.topic = in.get_string();
  channel.message_encoding = in.get_string();
  channel.metadata = in.get_map();
  return channel;
}

class Reader {
 public:
  Reader(const std::string& path, const McapVisitor& visitor) : path_(path), visitor_(visitor) {
    file_.open(path, std::ios::binary);
    if (!file_) throw RecordingError("cannot open recording '" + path + "': " + std::strerror(errno));
    file_.seekg(0, std::ios::end);
    result_.file_size = static_cast<std::uint64_t>(file_.tellg());
    file_.seekg(0);
  }

  McapReadResult run() {
    std::uint8_t magic[8];
    if (!read_exact(magic, sizeof magic) || std::memcmp(magic, kMagic, sizeof magic) != 0) {
      throw RecordingError("'" + path_ + "' is not an MCAP file (no MCAP magic at its start)");
    }
    data_crc_ = crc32(crc32(0L, Z_NULL, 0), magic, sizeof magic);
    offset_ = sizeof magic;
    bool in_summary = false;
    while (true) {
      const std::uint64_t record_start = offset_;
      std::uint8_t head[9];
      if (!read_exact(head, sizeof head)) {
        if (offset_ + 0 == result_.file_size && record_start == result_.file_size && !in_summary) {
          damage("the file ends " + at_byte(record_start) + " without its Data End, summary and footer (cut short, e.g. by a crash)");
        } else {
          damage("the file ends inside a record header " + at_byte(record_start) + " (cut short)");
        }
        break;
      }
      const auto opcode = static_cast<Opcode>(head[0]);
      std::uint64_t length = 0;
      for (int i = 0; i < 8; ++i) length |= static_cast<std::uint64_t>(head[1 + i]) << (8 * i);
      if (length > result_.file_size - record_start - sizeof head) {
        damage("record " + at_byte(record_start) + " (opcode " + std::to_string(head[0]) + ") claims " +
               std::to_string(length) + " bytes but the file has only " +
               std::to_string(result_.file_size - record_start - sizeof head) + " left (cut short)");
        break;
      }
      std::vector<std::uint8_t> content(length);
      read_exact(content.data(), content.size());
      offset_ = record_start + sizeof head + length;
      if (record_start == sizeof magic && opcode != Opcode::kHeader) {
        throw RecordingError("'" + path_ + "' is not a valid MCAP file (the first record is not a Header)");
      }
      if (opcode == Opcode::kDataEnd) {
        ByteReader in(content.data(), content.size());
        const auto expected = in.get<std::uint32_t>();
        if (expected != 0 && expected != static_cast<std::uint32_t>(data_crc_)) {
          damage("the data section CRC is wrong (expected " + std::to_string(expected) + ", computed " +
                 std::to_string(static_cast<std::uint32_t>(data_crc_)) + ")");
        }
        in_summary = true;
        summary_start_ = offset_;
        summary_crc_ = crc32(0L, Z_NULL, 0);
        result_.good_bytes = offset_;
        continue;
      }
      if (!in_summary) {
        data_crc_ = crc32(data_crc_, head, sizeof head);
        data_crc_ = crc32(data_crc_, content.data(), static_cast<uInt>(content.size()));
      }
      if (opcode == Opcode::kFooter) {
        finish_footer(content, head);
        break;
      }
      if (in_summary) {
        summary_crc_ = crc32(summary_crc_, head, sizeof head);
        summary_crc_ = crc32(summary_crc_, content.data(), static_cast<uInt>(content.size()));
        continue;  // the summary repeats what the data section held
      }
      try {
        handle(opcode, content, record_start);
      } catch (const RecordingError& error) {
        damage("record " + at_byte(record_start) + " is malformed: " + error.what());
        break;
      }
      result_.good_bytes = offset_;
      if (visitor_.on_progress) visitor_.on_progress(offset_, result_.file_size);
    }
    return result_;
  }

 private:
  bool read_exact(std::uint8_t* data, std::size_t size) {
    file_.read(reinterpret_cast<char*>(data), static_cast<std::streamsize>(size));
    return static_cast<std::size_t>(file_.gcount()) == size;
  }

  void damage(const std::string& what) {
    if (!result_.damage.empty()) result_.damage += "; ";
    result_.damage += what;
  }

  void finish_footer(const std::vector<std::uint8_t>& content, const std::uint8_t* head) {
    ByteReader in(content.data(), content.size());
    try {
      in.get<std::uint64_t>();
      in.get<std::uint64_t>();
      const auto expected = in.get<std::uint32_t>();
      if (summary_start_ > 0) {
        summary_crc_ = crc32(summary_crc_, head, 9);
        summary_crc_ = crc32(summary_crc_, content.data(), 16);
        if (expected != 0 && expected != static_cast<std::uint32_t>(summary_crc_)) {
          damage("the summary CRC is wrong");
        }
      }
    } catch (const RecordingError&) {
      damage("the footer is malformed");
      return;
    }
    std::uint8_t magic[8];
    if (!read_exact(magic, sizeof magic) || std::memcmp(magic, kMagic, sizeof magic) != 0) {
      damage("no MCAP magic after the footer");
      return;
    }
    result_.good_bytes = offset_ + sizeof magic;
    result_.complete = summary_start_ > 0 && result_.damage.empty();
    if (visitor_.on_progress) visitor_.on_progress(result_.file_size, result_.file_size);
  }

  void handle(Opcode opcode, const std::vector<std::uint8_t>& content, std::uint64_t record_start) {
    ByteReader in(content.data(), content.size());
    switch (opcode) {
      case Opcode::kHeader:
        result_.header.profile = in.get_string();
        result_.header.library = in.get_string();
        if (visitor_.on_header) visitor_.on_header(result_.header);
        break;
      case Opcode::kSchema: {
        const Schema schema = parse_schema(in);
        if (visitor_.on_schema) visitor_.on_schema(schema);
        break;
      }
      case Opcode::kChannel: {
        const Channel channel = parse_channel(in);
        if (visitor_.on_channel) visitor_.on_channel(channel);
        break;
      }
      case Opcode::kMessage:
        deliver_message(in);
        break;
      case Opcode::kChunk:
        read_chunk(in, record_start);
        break;
      case Opcode::kMetadata: {
        Metadata metadata;
        metadata.name = in.get_string();
        metadata.values = in.get_map();
        if (visitor_.on_metadata) visitor_.on_metadata(metadata);
        break;
      }
      default:
        break;  // indexes and records sarloc does not use
    }
  }

  void deliver_message(ByteReader& in) {
    message_.channel_id = in.get<std::uint16_t>();
    message_.sequence = in.get<std::uint32_t>();
    message_.log_time_ns = in.get<std::uint64_t>();
    message_.publish_time_ns = in.get<std::uint64_t>();
    const std::size_t size = in.remaining();
    const std::uint8_t* data = in.take(size);
    message_.data.assign(data, data + size);
    ++result_.messages;
    if (visitor_.on_message) visitor_.on_message(message_);
  }

  void read_chunk(ByteReader& in, std::uint64_t record_start) {
    in.get<std::uint64_t>();  // start time
    in.get<std::uint64_t>();  // end time
    const auto uncompressed_size = in.get<std::uint64_t>();
    const auto expected_crc = in.get<std::uint32_t>();
    const std::string compression = in.get_string();
    const auto compressed_size = in.get<std::uint64_t>();
    const std::uint8_t* records = in.take(compressed_size);
    std::vector<std::uint8_t> plain;
    try {
      if (uncompressed_size > (1ull << 32)) throw RecordingError("implausible uncompressed size");
      plain = decompress(parse_compression(compression), records, compressed_size, uncompressed_size);
    } catch (const RecordingError& error) {
      ++result_.bad_chunks;
      damage("chunk " + at_byte(record_start) + " skipped: " + error.what());
      return;
    }
    if (expected_crc != 0 && crc_of(plain.data(), plain.size()) != expected_crc) {
      ++result_.bad_chunks;
      damage("chunk " + at_byte(record_start) + " skipped: its CRC is wrong");
      return;
    }
    ++result_.chunks;
    ByteReader chunk(plain.data(), plain.size());
    while (!chunk.done()) {
      const auto opcode = static_cast<Opcode>(chunk.get<std::uint8_t>());
      const auto length = chunk.get<std::uint64_t>();
      if (length > chunk.remaining()) throw RecordingError("a record inside a chunk runs past the chunk");
      ByteReader record(chunk.take(length), length);
      if (opcode == Opcode::kMessage) {
        deliver_message(record);
      } else if (opcode == Opcode::kSchema) {
        const Schema schema = parse_schema(record);
        if (visitor_.on_schema) visitor_.on_schema(schema);
      } else if (opcode == Opcode::kChannel) {
        const Channel channel = parse_channel(record);
        if (visitor_.on_channel) visitor_.on_channel(channel);
      }
    }
  }

  std::string path_;
  const McapVisitor& visitor_;
  std::ifstream file_;
  McapReadResult result_;
  std::uint64_t offset_ = 0;
  unsigned long data_crc_ = 0;
  std::uint64_t summary_start_ = 0;
  unsigned long summary_crc_ = 0;
  Message message_;
};

}  // namespace

McapReadResult read_mcap(const std::string& path, const McapVisitor& visitor) { return Reader(path, visitor).run(); }

}  // namespace sarloc::recording
