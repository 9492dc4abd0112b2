#pragma once
// Reads an MCAP file front to back, record by record, so that a file cut short by a crash, or
// damaged in the middle, still yields everything before the damage. Used by --recover, replay
// and the report. Checks every CRC it meets (chunks, data section, summary).
//
//   McapVisitor visitor;
//   visitor.on_message = [&](const Message& m) { ... };
//   const McapReadResult result = read_mcap("mission.mcap", visitor);
//   if (!result.damage.empty()) warn(result.damage);
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sarloc/recording/mcap_records.hpp"

namespace sarloc::recording {

struct McapVisitor {
  std::function<void(const Header&)> on_header;
  std::function<void(const Schema&)> on_schema;
  std::function<void(const Channel&)> on_channel;
  /// The message is valid during the call only.
  std::function<void(const Message&)> on_message;
  std::function<void(const Metadata&)> on_metadata;
  /// Bytes read so far and the file size (for a progress bar).
  std::function<void(std::uint64_t, std::uint64_t)> on_progress;
};

struct McapReadResult {
  Header header;
  std::uint64_t file_size = 0;
  /// End of the last record read whole: everything before it was delivered.
  std::uint64_t good_bytes = 0;
  std::uint64_t messages = 0;
  std::uint64_t chunks = 0;
  /// Chunks skipped because their CRC or compression was wrong.
  std::uint64_t bad_chunks = 0;
  /// True when the file has its Data End, summary, Footer and closing magic, all CRCs right.
  bool complete = false;
  /// Empty when nothing is wrong; otherwise what could not be read, and where.
  std::string damage;
};

/// Throws RecordingError when the file cannot be opened or is not MCAP at all (bad magic or
/// header). Anything wrong after the header is reported in `damage`.
McapReadResult read_mcap(const std::string& path, const McapVisitor& visitor);

}  // namespace sarloc::recording
