#pragma once
// Little-endian encoding and decoding of MCAP record fields (internal to the container code).
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "sarloc/recording/mcap_records.hpp"

namespace sarloc::recording::detail {

class ByteWriter {
 public:
  template <class T>
  void put(T value) {
    for (std::size_t i = 0; i < sizeof(T); ++i) bytes_.push_back(static_cast<std::uint8_t>(static_cast<std::uint64_t>(value) >> (8 * i)));
  }
  void put_string(const std::string& text) {
    put<std::uint32_t>(static_cast<std::uint32_t>(text.size()));
    bytes_.insert(bytes_.end(), text.begin(), text.end());
  }
  void put_bytes(const std::uint8_t* data, std::size_t size) { bytes_.insert(bytes_.end(), data, data + size); }
  void put_map(const StringMap& map) {
    ByteWriter inner;
    for (const auto& [key, value] : map) {
      inner.put_string(key);
      inner.put_string(value);
    }
    put<std::uint32_t>(static_cast<std::uint32_t>(inner.bytes().size()));
    put_bytes(inner.bytes().data(), inner.bytes().size());
  }
  /// Opcode, content length, content.
  void put_record(Opcode opcode, const ByteWriter& content) {
    put<std::uint8_t>(static_cast<std::uint8_t>(opcode));
    put<std::uint64_t>(content.bytes().size());
    put_bytes(content.bytes().data(), content.bytes().size());
  }
  const std::vector<std::uint8_t>& bytes() const { return bytes_; }
  std::vector<std::uint8_t>& bytes() { return bytes_; }

 private:
  std::vector<std::uint8_t> bytes_;
};

/// Reads fields of one record's content; throws RecordingError past its end.
class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  template <class T>
  T get() {
    need(sizeof(T));
    std::uint64_t value = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) value |= static_cast<std::uint64_t>(data_[at_ + i]) << (8 * i);
    at_ += sizeof(T);
    return static_cast<T>(value);
  }
  std::string get_string() {
    const auto size = get<std::uint32_t>();
    need(size);
    std::string text(reinterpret_cast<const char*>(data_ + at_), size);
    at_ += size;
    return text;
  }
  StringMap get_map() {
    const auto size = get<std::uint32_t>();
    need(size);
    ByteReader inner(data_ + at_, size);
    at_ += size;
    StringMap map;
    while (!inner.done()) {
      std::string key = inner.get_string();
      map[key] = inner.get_string();
    }
    return map;
  }
  const std::uint8_t* take(std::size_t size) {
    need(size);
    const std::uint8_t* start = data_ + at_;
    at_ += size;
    return start;
  }
  std::size_t remaining() const { return size_ - at_; }
  bool done() const { return at_ == size_; }

 private:
  void need(std::size_t size) const {
    if (size > size_ - at_) throw RecordingError("record field runs past the end of its record");
  }
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t at_ = 0;
};

}  // namespace sarloc::recording::detail
