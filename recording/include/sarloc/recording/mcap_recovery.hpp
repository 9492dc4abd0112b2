#pragma once
// `sarloc-record --recover`: rewrites a recording that was cut short (a crash, a kill, a full
// disk) or damaged, keeping every record that can still be read and adding a proper summary.
#include <cstdint>
#include <string>

#include "sarloc/recording/mcap_records.hpp"

namespace sarloc::recording {

struct RecoveryResult {
  bool was_complete = false;     ///< the file was already whole: nothing rewritten
  std::uint64_t messages = 0;    ///< messages in the rewritten file
  std::uint64_t bytes_lost = 0;  ///< bytes after the last record that could be read
  std::string damage;            ///< what could not be read (empty when complete)
};

/// Reads `path` as far as it goes and, unless it was complete, writes the readable part to a
/// temporary file that then replaces `path` atomically; the damaged original is kept as
/// `path + ".damaged"`. Throws RecordingError when the file is not MCAP or cannot be rewritten.
RecoveryResult recover_mcap(const std::string& path, Compression compression = Compression::kZstd);

}  // namespace sarloc::recording
