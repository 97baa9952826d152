#include "rtabmap_core/codec/Compression.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <initializer_list>
#include <limits>

#include "../codec/ByteStream.h"
#include "rtabmap_core/common/Error.h"

namespace rtabmap::codec {

namespace {

// "RTZ" + format version: compressData blobs (matrix header + zlib payload).
constexpr unsigned char kDataMagic[4] = {'R', 'T', 'Z', 1};
constexpr size_t kDataHeaderSize = 4 + 4 + 4 + 4 + 8;  // magic, rows, cols, type, raw size
// "RTB" + format version: compressBytes blobs (raw size + zlib payload).
constexpr unsigned char kBytesMagic[4] = {'R', 'T', 'B', 1};
constexpr size_t kBytesHeaderSize = 4 + 8;
constexpr unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
constexpr int kZlibLevel = 6;
// Deflate cannot compress better than about 1032:1, so a header announcing more raw bytes than
// that for its payload is corrupt: checking it before allocating keeps a 30-byte garbage blob
// from asking for terabytes.
constexpr uint64_t kMaxDeflateRatio = 1032;
constexpr uint64_t kMaxRawSize = uint64_t(1) << 40;

std::string typeName(int type) {
  static const char* depths[] = {"8U", "8S", "16U", "16S", "32S", "32F", "64F", "16F"};
  return std::string("CV_") + depths[CV_MAT_DEPTH(type)] + "C" + std::to_string(CV_MAT_CN(type));
}

bool hasPrefix(const unsigned char* data, size_t size, const unsigned char* prefix, size_t n) {
  return data && size >= n && std::memcmp(data, prefix, n) == 0;
}

Bytes deflate(const unsigned char* raw, size_t size) {
  uLongf bound = compressBound(static_cast<uLong>(size));
  Bytes out(bound);
  const int rc = compress2(out.data(), &bound, raw, static_cast<uLong>(size), kZlibLevel);
  if (rc != Z_OK) throw Error("zlib compress2 failed (code " + std::to_string(rc) + ")");
  out.resize(bound);
  return out;
}

// Inflates exactly `rawSize` bytes into `out`; anything else (short, long, bad stream) is corrupt.
void inflateExact(const unsigned char* payload, size_t payloadSize, unsigned char* out,
                  uint64_t rawSize, const char* what) {
  if (rawSize > kMaxDeflateRatio * payloadSize + 64) {
    throw FormatError(std::string(what) + ": header announces " + std::to_string(rawSize) +
                      " bytes for a payload of " + std::to_string(payloadSize) +
                      " bytes, more than zlib can encode (corrupt header)");
  }
  if (rawSize > std::numeric_limits<uLong>::max() || payloadSize > std::numeric_limits<uLong>::max()) {
    throw FormatError(std::string(what) + ": size too large for zlib");
  }
  uLongf destLen = static_cast<uLongf>(rawSize);
  // zlib wants a non-null destination even for 0 bytes.
  unsigned char dummy = 0;
  const int rc = ::uncompress(rawSize ? out : &dummy, &destLen, payload, static_cast<uLong>(payloadSize));
  if (rc != Z_OK || destLen != rawSize) {
    throw FormatError(std::string(what) + ": corrupt or truncated zlib payload (" +
                      (rc == Z_OK ? "size mismatch"
                                  : rc == Z_BUF_ERROR ? "truncated or longer than announced"
                                                      : rc == Z_DATA_ERROR ? "bad data" : "error " + std::to_string(rc)) +
                      ")");
  }
}

// Fuzzing fix (fuzz/regressions/codec/gdcm_assert_dicom_probe.rejected): cv::imdecode probes
// every decoder OpenCV was built with, and some abort the process on malformed input (GDCM's
// DICOM reader asserts), so a corrupt blob could kill the node. Only the raster formats an
// image blob legitimately holds reach imdecode: jpeg, png, tiff, bmp, webp, told by their
// signatures.
bool hasImageSignature(const unsigned char* d, size_t n) {
  auto starts = [&](std::initializer_list<unsigned char> magic, size_t at = 0) {
    return n >= at + magic.size() && std::equal(magic.begin(), magic.end(), d + at);
  };
  return starts({0xFF, 0xD8, 0xFF}) || starts({0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A}) ||
         starts({'I', 'I', 0x2A, 0x00}) || starts({'M', 'M', 0x00, 0x2A}) || starts({'B', 'M'}) ||
         (starts({'R', 'I', 'F', 'F'}) && starts({'W', 'E', 'B', 'P'}, 8));
}

std::string normalizeFormat(const std::string& format) {
  std::string f = format;
  std::transform(f.begin(), f.end(), f.begin(), [](unsigned char c) { return std::tolower(c); });
  if (!f.empty() && f[0] != '.') f = "." + f;
  return f;
}

}  // namespace

Bytes compressImage(const cv::Mat& image, const std::string& format) {
  if (image.empty()) return {};
  const std::string f = normalizeFormat(format);
  const int depth = image.depth();
  const int cn = image.channels();
  const std::string what = "compressImage(" + typeName(image.type()) + ", \"" + format + "\")";
  if (depth == CV_32F || depth == CV_64F || depth == CV_16F) {
    throw FormatError(what + ": floating-point matrices are not images; use "
                             "codec::compressDepth (CV_32FC1 depth) or codec::compressData");
  }
  const bool jpg = f == ".jpg" || f == ".jpeg" || f == ".jpe";
  const bool png = f == ".png";
  const bool tiff = f == ".tif" || f == ".tiff";
  if (depth != CV_8U && depth != CV_16U) {
    throw FormatError(what + ": only 8-bit and 16-bit unsigned images are encodable; use "
                             "codec::compressData");
  }
  if (depth == CV_16U && !(png || tiff)) {
    throw FormatError(what + ": 16-bit images must use a lossless 16-bit format (\".png\")");
  }
  if (jpg && cn != 1 && cn != 3) {
    throw FormatError(what + ": jpeg holds 1 or 3 channels; use \".png\"");
  }
  if (cn != 1 && cn != 3 && cn != 4) {
    throw FormatError(what + ": images have 1, 3 or 4 channels; use codec::compressData");
  }
  Bytes out;
  try {
    if (!cv::imencode(f, image, out)) {
      throw FormatError(what + ": OpenCV could not encode this format");
    }
  } catch (const cv::Exception& e) {
    throw FormatError(what + ": " + e.what());
  }
  return out;
}

cv::Mat uncompressImage(const unsigned char* data, size_t size) {
  if (!data || size == 0) return cv::Mat();
  // libjpeg decodes a truncated stream into a partly grey image with only a warning: require
  // the end-of-image marker (allowing a little trailing padding some encoders add).
  if (size >= 2 && data[0] == 0xFF && data[1] == 0xD8) {
    bool eoi = false;
    for (size_t i = size - 1; i >= 1 && i + 32 >= size && !eoi; --i) {
      eoi = data[i - 1] == 0xFF && data[i] == 0xD9;
    }
    if (!eoi) {
      throw FormatError("uncompressImage: jpeg of " + std::to_string(size) +
                        " bytes has no end-of-image marker (truncated)");
    }
  }
  if (!hasImageSignature(data, size)) {
    throw FormatError("uncompressImage: " + std::to_string(size) +
                      " bytes are not a jpeg, png, tiff, bmp or webp stream");
  }
  cv::Mat image;
  try {
    // imdecode takes a non-const Mat header but only reads it.
    const cv::Mat buffer(1, static_cast<int>(std::min<size_t>(size, std::numeric_limits<int>::max())),
                         CV_8UC1, const_cast<unsigned char*>(data));
    image = cv::imdecode(buffer, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    throw FormatError(std::string("uncompressImage: corrupt image bytes (") + e.what() + ")");
  }
  if (image.empty()) {
    throw FormatError("uncompressImage: " + std::to_string(size) +
                      " bytes are not a decodable image (corrupt or truncated)");
  }
  return image;
}

cv::Mat uncompressImage(const Bytes& bytes) { return uncompressImage(bytes.data(), bytes.size()); }

Bytes compressData(const cv::Mat& data) {
  if (data.empty()) return {};
  if (data.dims > 2) {
    throw FormatError("compressData: only 2D matrices are supported (got " +
                      std::to_string(data.dims) + " dimensions)");
  }
  // A ROI view is not one block of memory; copy it into one.
  const cv::Mat m = data.isContinuous() ? data : data.clone();
  const uint64_t rawSize = static_cast<uint64_t>(m.total()) * m.elemSize();
  const Bytes payload = deflate(m.data, rawSize);
  Bytes out;
  out.reserve(kDataHeaderSize + payload.size());
  detail::ByteWriter w(out);
  w.raw(kDataMagic, 4);
  w.u32(static_cast<uint32_t>(m.rows));
  w.u32(static_cast<uint32_t>(m.cols));
  w.i32(m.type());
  w.u64(rawSize);
  w.raw(payload.data(), payload.size());
  return out;
}

cv::Mat uncompressData(const unsigned char* data, size_t size) {
  if (!data || size == 0) return cv::Mat();
  detail::ByteReader r(data, size, "uncompressData");
  if (size < 4 || std::memcmp(data, kDataMagic, 3) != 0) {
    r.fail("not a compressData blob (bad magic)");
  }
  if (data[3] != kDataMagic[3]) {
    r.fail("format version " + std::to_string(data[3]) + " is not supported (expected " +
           std::to_string(kDataMagic[3]) + "; written by a newer version?)");
  }
  r.skip(4, "magic");
  const uint32_t rows = r.u32("rows");
  const uint32_t cols = r.u32("cols");
  const int32_t type = r.i32("type");
  const uint64_t rawSize = r.u64("raw size");
  if (rows == 0 || cols == 0 || rows > uint32_t(std::numeric_limits<int>::max()) ||
      cols > uint32_t(std::numeric_limits<int>::max())) {
    r.fail("invalid matrix size " + std::to_string(rows) + "x" + std::to_string(cols));
  }
  if (type < 0 || type != CV_MAKETYPE(CV_MAT_DEPTH(type), CV_MAT_CN(type)) ||
      CV_MAT_DEPTH(type) > CV_16F) {
    r.fail("invalid matrix type " + std::to_string(type));
  }
  const uint64_t elem = CV_ELEM_SIZE(type);
  // Overflow-safe rows * cols * elem, compared with the announced size before any allocation.
  if (uint64_t(rows) > kMaxRawSize / cols || uint64_t(rows) * cols > kMaxRawSize / elem ||
      uint64_t(rows) * cols * elem != rawSize) {
    r.fail("header is inconsistent (" + std::to_string(rows) + "x" + std::to_string(cols) + " " +
           typeName(type) + " vs " + std::to_string(rawSize) + " bytes)");
  }
  const size_t payloadSize = r.remaining();
  if (rawSize > kMaxDeflateRatio * payloadSize + 64) {
    r.fail("header announces " + std::to_string(rawSize) + " bytes for a payload of " +
           std::to_string(payloadSize) + " bytes (corrupt or truncated)");
  }
  cv::Mat m(static_cast<int>(rows), static_cast<int>(cols), type);
  inflateExact(r.current(), payloadSize, m.data, rawSize, "uncompressData");
  return m;
}

cv::Mat uncompressData(const Bytes& bytes) { return uncompressData(bytes.data(), bytes.size()); }

Bytes compressDepth(const cv::Mat& depth) {
  if (depth.empty()) return {};
  if (depth.type() == CV_16UC1) return compressImage(depth, ".png");
  if (depth.type() == CV_32FC1) return compressData(depth);
  throw FormatError("compressDepth: depth images are CV_16UC1 (mm) or CV_32FC1 (m), not " +
                    typeName(depth.type()));
}

cv::Mat uncompressDepth(const Bytes& bytes) {
  if (bytes.empty()) return cv::Mat();
  cv::Mat depth;
  if (hasPrefix(bytes.data(), bytes.size(), kDataMagic, 3)) {
    depth = uncompressData(bytes);
  } else if (hasPrefix(bytes.data(), bytes.size(), kPngSignature, sizeof(kPngSignature))) {
    depth = uncompressImage(bytes);
  } else {
    throw FormatError("uncompressDepth: " + std::to_string(bytes.size()) +
                      " bytes are neither a png nor a compressData blob");
  }
  if (depth.type() != CV_16UC1 && depth.type() != CV_32FC1) {
    throw FormatError("uncompressDepth: decoded a " + typeName(depth.type()) +
                      " matrix, not a depth image (CV_16UC1 or CV_32FC1)");
  }
  return depth;
}

cv::Mat uncompressAny(const unsigned char* data, size_t size) {
  if (!data || size == 0) return cv::Mat();
  if (hasPrefix(data, size, kDataMagic, 3)) return uncompressData(data, size);
  return uncompressImage(data, size);
}

cv::Mat uncompressAny(const Bytes& bytes) { return uncompressAny(bytes.data(), bytes.size()); }

bool isCompressedData(const Bytes& bytes) {
  return hasPrefix(bytes.data(), bytes.size(), kDataMagic, 3);
}

Bytes compressBytes(const Bytes& raw) {
  if (raw.empty()) return {};
  const Bytes payload = deflate(raw.data(), raw.size());
  Bytes out;
  out.reserve(kBytesHeaderSize + payload.size());
  detail::ByteWriter w(out);
  w.raw(kBytesMagic, 4);
  w.u64(raw.size());
  w.raw(payload.data(), payload.size());
  return out;
}

Bytes uncompressBytes(const Bytes& compressed) {
  if (compressed.empty()) return {};
  detail::ByteReader r(compressed.data(), compressed.size(), "uncompressBytes");
  // Fuzzing fix (fuzz/regressions/codec/rtb_magic_only.rejected): the magic alone ("RTB", 3
  // bytes) passed, and the version byte was read past the end: require the 4-byte magic.
  if (compressed.size() < 4 || !hasPrefix(compressed.data(), compressed.size(), kBytesMagic, 3)) {
    r.fail("not a compressBytes blob (bad magic)");
  }
  if (compressed[3] != kBytesMagic[3]) {
    r.fail("format version " + std::to_string(compressed[3]) + " is not supported");
  }
  r.skip(4, "magic");
  const uint64_t rawSize = r.u64("raw size");
  const size_t payloadSize = r.remaining();
  if (rawSize == 0 || rawSize > kMaxRawSize || rawSize > kMaxDeflateRatio * payloadSize + 64) {
    r.fail("header announces " + std::to_string(rawSize) + " bytes for a payload of " +
           std::to_string(payloadSize) + " bytes (corrupt or truncated)");
  }
  Bytes out(static_cast<size_t>(rawSize));
  inflateExact(r.current(), payloadSize, out.data(), rawSize, "uncompressBytes");
  return out;
}

}  // namespace rtabmap::codec
