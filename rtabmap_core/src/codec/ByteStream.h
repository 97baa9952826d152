#pragma once
// Internal (not installed): little-endian writer and bounds-checked reader for the binary blobs
// of the codec and geometry areas. Every read checks the remaining byte count first, so a
// truncated or corrupt blob ends in FormatError, never in a read past the end.
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "rtabmap_core/common/Error.h"

namespace rtabmap::detail {

class ByteWriter {
 public:
  explicit ByteWriter(std::vector<unsigned char>& out) : out_(out) {}

  void raw(const void* data, size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    out_.insert(out_.end(), p, p + size);
  }
  void u8(uint8_t v) { out_.push_back(v); }
  void u32(uint32_t v) {
    for (int i = 0; i < 4; ++i) out_.push_back(static_cast<unsigned char>(v >> (8 * i)));
  }
  void i32(int32_t v) { u32(static_cast<uint32_t>(v)); }
  void u64(uint64_t v) {
    for (int i = 0; i < 8; ++i) out_.push_back(static_cast<unsigned char>(v >> (8 * i)));
  }
  void f64(double v) {
    uint64_t bits;
    std::memcpy(&bits, &v, sizeof(bits));
    u64(bits);
  }
  void str(const std::string& s) {
    u32(static_cast<uint32_t>(s.size()));
    raw(s.data(), s.size());
  }
  void bytes(const std::vector<unsigned char>& b) {
    u32(static_cast<uint32_t>(b.size()));
    raw(b.data(), b.size());
  }

 private:
  std::vector<unsigned char>& out_;
};

class ByteReader {
 public:
  // `what` names the blob in error messages ("CameraModel blob").
  ByteReader(const unsigned char* data, size_t size, std::string what)
      : data_(data), size_(data ? size : 0), what_(std::move(what)) {}

  size_t remaining() const { return size_ - pos_; }
  size_t position() const { return pos_; }
  const unsigned char* current() const { return data_ + pos_; }

  void need(size_t n, const char* field) const {
    if (n > remaining()) {
      throw FormatError(what_ + ": truncated at byte " + std::to_string(pos_) + " reading " +
                        field + " (" + std::to_string(n) + " bytes needed, " +
                        std::to_string(remaining()) + " left)");
    }
  }
  void skip(size_t n, const char* field) {
    need(n, field);
    pos_ += n;
  }
  void raw(void* out, size_t n, const char* field) {
    need(n, field);
    if (n) std::memcpy(out, data_ + pos_, n);
    pos_ += n;
  }
  uint8_t u8(const char* field) {
    need(1, field);
    return data_[pos_++];
  }
  uint32_t u32(const char* field) {
    need(4, field);
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<uint32_t>(data_[pos_ + i]) << (8 * i);
    pos_ += 4;
    return v;
  }
  int32_t i32(const char* field) { return static_cast<int32_t>(u32(field)); }
  uint64_t u64(const char* field) {
    need(8, field);
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= static_cast<uint64_t>(data_[pos_ + i]) << (8 * i);
    pos_ += 8;
    return v;
  }
  double f64(const char* field) {
    const uint64_t bits = u64(field);
    double v;
    std::memcpy(&v, &bits, sizeof(v));
    return v;
  }
  // A length-prefixed string of at most maxLength bytes.
  std::string str(const char* field, size_t maxLength = 1u << 20) {
    const uint32_t n = u32(field);
    if (n > maxLength) fail(std::string(field) + " length " + std::to_string(n) + " is implausible");
    need(n, field);
    std::string s(reinterpret_cast<const char*>(data_ + pos_), n);
    pos_ += n;
    return s;
  }
  std::vector<unsigned char> bytes(const char* field) {
    const uint32_t n = u32(field);
    need(n, field);
    std::vector<unsigned char> b(data_ + pos_, data_ + pos_ + n);
    pos_ += n;
    return b;
  }
  [[noreturn]] void fail(const std::string& message) const {
    throw FormatError(what_ + ": " + message);
  }

 private:
  const unsigned char* data_;
  size_t size_;
  size_t pos_ = 0;
  std::string what_;
};

}  // namespace rtabmap::detail
