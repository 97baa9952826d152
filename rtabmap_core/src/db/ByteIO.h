#pragma once
// Plain-value serialisation shared by the blob codecs (Blobs.cpp, FeatureBlobs.cpp): a writer
// appending values to bytes, and a reader that throws FormatError instead of reading past the
// end of a damaged blob.
#include <cstring>
#include <string>
#include <vector>

#include "rtabmap_core/codec/Compression.h"
#include "rtabmap_core/common/Error.h"

namespace rtabmap::db::blob {

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "the long-term memory stores numbers little-endian; add byte swapping for this platform"
#endif

// Appends plain values to a byte buffer.
class ByteWriter {
 public:
  explicit ByteWriter(size_t reserve = 0) { bytes_.reserve(reserve); }
  template <typename T>
  void put(const T& value) {
    const auto* p = reinterpret_cast<const unsigned char*>(&value);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  void putBytes(const unsigned char* data, size_t size) { bytes_.insert(bytes_.end(), data, data + size); }
  Bytes take() { return std::move(bytes_); }

 private:
  Bytes bytes_;
};

// Reads plain values, throwing FormatError (naming the blob) past the end.
class ByteReader {
 public:
  ByteReader(const unsigned char* data, size_t size, const char* what)
      : data_(data), size_(size), what_(what) {}
  template <typename T>
  T get() {
    T value;
    require(sizeof(T));
    std::memcpy(&value, data_ + offset_, sizeof(T));
    offset_ += sizeof(T);
    return value;
  }
  const unsigned char* take(size_t n) {
    require(n);
    const unsigned char* p = data_ + offset_;
    offset_ += n;
    return p;
  }
  void expectEnd() const {
    if (offset_ != size_) fail("has " + std::to_string(size_ - offset_) + " trailing bytes");
  }

 private:
  void require(size_t n) const {
    if (n > size_ - offset_) fail("is truncated (" + std::to_string(size_) + " bytes)");
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw FormatError(std::string("stored ") + what_ + " " + what);
  }
  const unsigned char* data_;
  size_t size_;
  size_t offset_ = 0;
  const char* what_;
};

inline void requireMultiple(size_t size, size_t unit, const char* what) {
  if (size % unit != 0) {
    throw FormatError(std::string("stored ") + what + " has " + std::to_string(size) +
                      " bytes, not a multiple of " + std::to_string(unit));
  }
}

// Little fixed-size arrays of one type.
template <typename T>
Bytes encodeArray(const std::vector<T>& values) {
  Bytes bytes(values.size() * sizeof(T));
  if (!values.empty()) std::memcpy(bytes.data(), values.data(), bytes.size());
  return bytes;
}

template <typename T>
std::vector<T> decodeArray(const unsigned char* data, size_t size, const char* what) {
  requireMultiple(size, sizeof(T), what);
  std::vector<T> values(size / sizeof(T));
  if (size) std::memcpy(values.data(), data, size);
  return values;
}

}  // namespace rtabmap::db::blob
