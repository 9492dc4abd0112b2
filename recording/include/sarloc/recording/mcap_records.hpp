#pragma once
// The MCAP records sarloc writes and reads (https://mcap.dev/spec, major version 0).
//
// A recording is: magic, Header, a data section (Schema and Channel records, then Chunks of
// Message records, each Chunk followed by one Message Index per channel, and Metadata), Data End,
// a summary section (Schema, Channel, Statistics, Chunk Index, Metadata Index), Summary Offsets,
// Footer, magic. All integers little-endian; CRC-32 as in zlib.
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace sarloc::recording {

/// A recording could not be written or read: the message names the file and what failed.
class RecordingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class Opcode : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

/// The 8 bytes at both ends of every MCAP file.
inline constexpr std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', 0x30, '\r', '\n'};

using StringMap = std::map<std::string, std::string>;

struct Header {
  std::string profile;
  std::string library;
};

struct Schema {
  std::uint16_t id = 0;
  std::string name;      ///< scoped type name, e.g. "sarloc::FieldMeasurement"
  std::string encoding;  ///< "omgidl"
  std::string data;      ///< the self-contained IDL text
};

struct Channel {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;
  std::string topic;
  std::string message_encoding;  ///< "cdr"
  StringMap metadata;
};

struct Message {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time_ns = 0;      ///< when the recorder received it
  std::uint64_t publish_time_ns = 0;  ///< the writer's source timestamp
  std::vector<std::uint8_t> data;     ///< the payload exactly as received
};

struct Metadata {
  std::string name;
  StringMap values;
};

/// What the Statistics record of a complete file says.
struct Statistics {
  std::uint64_t message_count = 0;
  std::uint32_t chunk_count = 0;
  std::uint32_t metadata_count = 0;
  std::uint64_t message_start_time_ns = 0;
  std::uint64_t message_end_time_ns = 0;
  std::map<std::uint16_t, std::uint64_t> channel_message_counts;
};

/// How chunks are compressed ("" means none, as in the file).
enum class Compression { kNone, kZstd, kLz4 };
std::string compression_name(Compression compression);
/// Throws RecordingError for anything but "none"/""/"zstd"/"lz4".
Compression parse_compression(const std::string& text);

}  // namespace sarloc::recording
