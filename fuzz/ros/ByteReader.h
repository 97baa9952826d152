#pragma once
// Turns fuzz bytes into message fields: each take*() consumes the next bytes (zeros once they
// run out), so every byte string is a valid recipe and libFuzzer's mutations map to fields.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace rtabmap::fuzz {

class ByteReader {
 public:
  ByteReader(const uint8_t* data, size_t size) : data_(data), size_(size) {}

  template <typename T>
  T take() {
    T value{};
    const size_t n = std::min(sizeof(T), size_ - offset_);
    if (n > 0) std::memcpy(&value, data_ + offset_, n);
    offset_ += n;
    return value;
  }
  // 0..max, uniformly enough for sizes and counts.
  uint32_t takeSmall(uint32_t max) { return take<uint32_t>() % (max + 1); }
  // Mostly a small count, sometimes any 32-bit value (sizes a driver should never send).
  uint32_t takeSize(uint32_t smallMax) {
    return take<uint8_t>() < 240 ? takeSmall(smallMax) : take<uint32_t>();
  }
  // Mostly a plausible value (eighths from -4096 to 4096), sometimes any bit pattern
  // (NaN, infinities, denormals).
  template <typename Real>
  Real takeReal() {
    return take<uint8_t>() < 224 ? static_cast<Real>(take<int16_t>()) / Real(8) : take<Real>();
  }
  std::vector<uint8_t> takeBytes(size_t maxSize) {
    const size_t n = std::min<size_t>(takeSmall(static_cast<uint32_t>(maxSize)), size_ - offset_);
    std::vector<uint8_t> bytes(data_ + offset_, data_ + offset_ + n);
    offset_ += n;
    return bytes;
  }
  // One of `choices`, or (last option) a short arbitrary string.
  std::string takeName(const std::vector<std::string>& choices) {
    const uint32_t i = takeSmall(static_cast<uint32_t>(choices.size()));
    if (i < choices.size()) return choices[i];
    const std::vector<uint8_t> raw = takeBytes(16);
    return std::string(raw.begin(), raw.end());
  }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t offset_ = 0;
};

}  // namespace rtabmap::fuzz
