#pragma once
// Chunk compression with Debian's libzstd and liblz4 (LZ4 frame format, as MCAP requires).
#include <cstdint>
#include <vector>

#include "sarloc/recording/mcap_records.hpp"

namespace sarloc::recording {

std::vector<std::uint8_t> compress(Compression compression, const std::vector<std::uint8_t>& input);
/// Throws RecordingError when the data does not decompress to exactly `uncompressed_size` bytes.
std::vector<std::uint8_t> decompress(Compression compression, const std::uint8_t* data, std::size_t size,
                                     std::uint64_t uncompressed_size);

}  // namespace sarloc::recording
