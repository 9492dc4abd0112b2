#include "sarloc/recording/compression.hpp"

#include <lz4frame.h>
#include <zstd.h>

#include <string>

namespace sarloc::recording {

std::string compression_name(Compression compression) {
  switch (compression) {
    case Compression::kZstd: return "zstd";
    case Compression::kLz4: return "lz4";
    case Compression::kNone: break;
  }
  return "";
}

Compression parse_compression(const std::string& text) {
  if (text.empty() || text == "none") return Compression::kNone;
  if (text == "zstd") return Compression::kZstd;
  if (text == "lz4") return Compression::kLz4;
  throw RecordingError("unknown compression '" + text + "' (expected zstd, lz4 or none)");
}

namespace {
// zstd's default level: about 3x on sarloc's CDR at a small fraction of a core.
constexpr int kZstdLevel = 3;
}  // namespace

std::vector<std::uint8_t> compress(Compression compression, const std::vector<std::uint8_t>& input) {
  std::vector<std::uint8_t> output;
  switch (compression) {
    case Compression::kNone:
      return input;
    case Compression::kZstd: {
      output.resize(ZSTD_compressBound(input.size()));
      const std::size_t size = ZSTD_compress(output.data(), output.size(), input.data(), input.size(), kZstdLevel);
      if (ZSTD_isError(size)) throw RecordingError(std::string("zstd compression failed: ") + ZSTD_getErrorName(size));
      output.resize(size);
      return output;
    }
    case Compression::kLz4: {
      output.resize(LZ4F_compressFrameBound(input.size(), nullptr));
      const std::size_t size = LZ4F_compressFrame(output.data(), output.size(), input.data(), input.size(), nullptr);
      if (LZ4F_isError(size)) throw RecordingError(std::string("lz4 compression failed: ") + LZ4F_getErrorName(size));
      output.resize(size);
      return output;
    }
  }
  return output;
}

std::vector<std::uint8_t> decompress(Compression compression, const std::uint8_t* data, std::size_t size,
                                     std::uint64_t uncompressed_size) {
  std::vector<std::uint8_t> output(uncompressed_size);
  switch (compression) {
    case Compression::kNone:
      if (size != uncompressed_size) throw RecordingError("uncompressed chunk size does not match its record");
      output.assign(data, data + size);
      return output;
    case Compression::kZstd: {
      const std::size_t produced = ZSTD_decompress(output.data(), output.size(), data, size);
      if (ZSTD_isError(produced)) throw RecordingError(std::string("zstd: ") + ZSTD_getErrorName(produced));
      if (produced != uncompressed_size) throw RecordingError("zstd chunk decompressed to the wrong size");
      return output;
    }
    case Compression::kLz4: {
      LZ4F_dctx* context = nullptr;
      if (LZ4F_isError(LZ4F_createDecompressionContext(&context, LZ4F_VERSION))) {
        throw RecordingError("lz4: cannot create a decompression context");
      }
      std::size_t in_done = 0;
      std::size_t out_done = 0;
      std::size_t hint = 1;
      while (hint != 0 && in_done < size) {
        std::size_t out_size = output.size() - out_done;
        std::size_t in_size = size - in_done;
        hint = LZ4F_decompress(context, output.data() + out_done, &out_size, data + in_done, &in_size, nullptr);
        if (LZ4F_isError(hint)) {
          LZ4F_freeDecompressionContext(context);
          throw RecordingError(std::string("lz4: ") + LZ4F_getErrorName(hint));
        }
        in_done += in_size;
        out_done += out_size;
        if (in_size == 0 && out_size == 0) break;  // no progress: the frame is cut short
      }
      LZ4F_freeDecompressionContext(context);
      if (hint != 0 || out_done != uncompressed_size) throw RecordingError("lz4 chunk decompressed to the wrong size");
      return output;
    }
  }
  return output;
}

}  // namespace sarloc::recording
