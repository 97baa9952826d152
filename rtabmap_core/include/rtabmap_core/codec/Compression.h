#pragma once
// Compression of sensor data for the database and for ROS messages: images through OpenCV
// codecs (jpg for colour, png for 16-bit depth: lossless), any other matrix (float depth,
// scans, grids, descriptors) through zlib with a small header (rows, cols, type) so it
// decompresses to the identical cv::Mat.
#include <opencv2/core/mat.hpp>

#include <string>
#include <vector>

namespace rtabmap {

using Bytes = std::vector<unsigned char>;

namespace codec {

// Encodes an image with an OpenCV codec extension (".jpg", ".png"). 16-bit single-channel
// images must use ".png" (lossless); 32-bit float images are not images: use compressData.
// Throws FormatError for an unsupported type/format pair. Empty image -> empty bytes.
Bytes compressImage(const cv::Mat& image, const std::string& format = ".png");
// Decodes what compressImage produced, keeping depth and channels (IMREAD_UNCHANGED).
// Throws FormatError on corrupt bytes, including a jpeg cut before its end marker (which
// libjpeg would otherwise decode into a partly grey image). Empty bytes -> empty image.
cv::Mat uncompressImage(const Bytes& bytes);
cv::Mat uncompressImage(const unsigned char* data, size_t size);

// zlib (level 6) of any 2D continuous or non-continuous matrix, header included: "RTZ" + a
// format version byte, then rows, cols, type (32-bit) and the raw byte count (64-bit), all
// little-endian. Every header field is checked against the payload before allocating.
Bytes compressData(const cv::Mat& data);
// Throws FormatError on corrupt or truncated bytes (never returns a partial matrix).
cv::Mat uncompressData(const Bytes& bytes);
cv::Mat uncompressData(const unsigned char* data, size_t size);

// Depth images: CV_16UC1 (mm) -> png; CV_32FC1 (m) -> zlib (lossless either way).
// uncompressDepth tells the two apart by their headers and refuses any other result type.
Bytes compressDepth(const cv::Mat& depth);
cv::Mat uncompressDepth(const Bytes& bytes);

// Added (geometry/codec owner): decodes either form, told apart by the compressData header,
// for byte fields that may hold an image codec stream or a compressData blob (e.g. a colour
// image stored as png or, for unusual types, as zlib). Throws FormatError on corrupt bytes.
cv::Mat uncompressAny(const Bytes& bytes);
cv::Mat uncompressAny(const unsigned char* data, size_t size);
// True if the bytes begin with the compressData header (whatever their integrity).
bool isCompressedData(const Bytes& bytes);

// Raw zlib on bytes (for strings such as serialised parameters), behind a small header ("RTB"
// + version, raw size) so that corrupt or truncated input throws FormatError.
Bytes compressBytes(const Bytes& raw);
Bytes uncompressBytes(const Bytes& compressed);

}  // namespace codec
}  // namespace rtabmap
