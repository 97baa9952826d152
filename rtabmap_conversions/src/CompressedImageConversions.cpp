#include "rtabmap_conversions/CompressedImageConversions.h"

#include <opencv2/core.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "Support.h"
#include "rtabmap_conversions/ImageConversions.h"
#include "rtabmap_core/common/Error.h"

namespace rtabmap_conversions {

namespace {

// The compressedDepth header: int32 format (0 = inverse depth, the only one defined) and the
// two float32 quantisation parameters, in host byte order as the transport writes it.
constexpr size_t kDepthHeaderSize = 12;
constexpr int32_t kInverseDepthFormat = 0;

rtabmap::Bytes depthHeader(float a, float b) {
  rtabmap::Bytes header(kDepthHeaderSize);
  std::memcpy(header.data(), &kInverseDepthFormat, 4);
  std::memcpy(header.data() + 4, &a, 4);
  std::memcpy(header.data() + 8, &b, 4);
  return header;
}

bool startsWith(const rtabmap::Bytes& bytes, std::initializer_list<unsigned char> magic) {
  if (bytes.size() < magic.size()) return false;
  return std::equal(magic.begin(), magic.end(), bytes.begin());
}
bool isJpeg(const rtabmap::Bytes& b) { return startsWith(b, {0xFF, 0xD8, 0xFF}); }
bool isPng(const rtabmap::Bytes& b) { return startsWith(b, {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A}); }

std::string trim(const std::string& s) {
  const size_t first = s.find_first_not_of(' ');
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(' ') - first + 1);
}

std::optional<cv::Mat> decodeCompressedDepth(const sensor_msgs::CompressedImage& msg, const std::string& encoding,
                                             const std::string& rest, std::string* error) {
  const std::string what = "compressedDepth image of frame '" + msg.header.frame_id + "'";
  if (rest.find("rvl") != std::string::npos) {
    return detail::fail(error, what + " uses the RVL codec, which is not supported; publish it with "
                                      "the png format (compressedDepth parameter format:=png)");
  }
  if (encoding != "16UC1" && encoding != "mono16" && encoding != "32FC1") {
    return detail::fail(error, what + " declares encoding '" + encoding + "'; expected 16UC1 or 32FC1");
  }
  if (msg.data.size() <= kDepthHeaderSize) {
    return detail::fail(error, what + " has " + std::to_string(msg.data.size()) +
                                   " bytes: not even its 12-byte header and an image");
  }
  float a = 0.0f, b = 0.0f;
  std::memcpy(&a, msg.data.data() + 4, 4);
  std::memcpy(&b, msg.data.data() + 8, 4);
  cv::Mat png;
  try {
    png = rtabmap::codec::uncompressImage(msg.data.data() + kDepthHeaderSize, msg.data.size() - kDepthHeaderSize);
  } catch (const std::exception& e) {
    return detail::fail(error, what + ": corrupt png after the header (" + e.what() + ")");
  }
  if (png.type() != CV_16UC1) {
    return detail::fail(error, what + ": the png holds type " + std::to_string(png.type()) +
                                   " instead of 16-bit grey");
  }
  if (encoding != "32FC1") return png;
  if (!std::isfinite(a) || !std::isfinite(b) || a == 0.0f) {
    return detail::fail(error, what + ": invalid quantisation parameters A=" + std::to_string(a) +
                                   " B=" + std::to_string(b));
  }
  cv::Mat depth(png.size(), CV_32FC1);
  for (int r = 0; r < png.rows; ++r) {
    const uint16_t* q = png.ptr<uint16_t>(r);
    float* d = depth.ptr<float>(r);
    for (int c = 0; c < png.cols; ++c) {
      d[c] = q[c] == 0 ? std::numeric_limits<float>::quiet_NaN() : a / (static_cast<float>(q[c]) - b);
    }
  }
  return depth;
}

}  // namespace

sensor_msgs::CompressedImage compressedImageToMsg(const cv::Mat& image, const std_msgs::Header& header,
                                                  const std::string& format) {
  const std::string encoding = imageEncoding(image.type());
  const bool jpeg = format == "jpeg" || format == "jpg";
  if (!jpeg && format != "png") {
    throw rtabmap::FormatError("compressedImageToMsg: format '" + format + "'; expected jpeg or png");
  }
  if (image.empty() || encoding.empty() || image.type() == CV_32FC1 ||
      (jpeg && image.type() != CV_8UC1 && image.type() != CV_8UC3)) {
    throw rtabmap::FormatError("compressedImageToMsg: cannot store image type " + std::to_string(image.type()) +
                               (image.empty() ? " (empty)" : "") + " as " + format);
  }
  sensor_msgs::CompressedImage msg;
  msg.header = header;
  const std::string codec = jpeg ? "jpeg" : "png";
  msg.format = encoding + "; " + codec + " compressed " + encoding;
  msg.data = rtabmap::codec::compressImage(image, jpeg ? ".jpg" : ".png");
  return msg;
}

sensor_msgs::CompressedImage compressedDepthToMsg(const cv::Mat& depth, const std_msgs::Header& header,
                                                  double depthMax, double depthQuantization) {
  sensor_msgs::CompressedImage msg;
  msg.header = header;
  if (depth.type() == CV_16UC1 && !depth.empty()) {
    msg.format = "16UC1; compressedDepth png";
    msg.data = depthHeader(0.0f, 0.0f);
    const rtabmap::Bytes png = rtabmap::codec::compressImage(depth, ".png");
    msg.data.insert(msg.data.end(), png.begin(), png.end());
    return msg;
  }
  if (depth.type() != CV_32FC1 || depth.empty() || !(depthMax > 0.0) || !(depthQuantization > 0.0)) {
    throw rtabmap::FormatError("compressedDepthToMsg: expected a CV_16UC1 or CV_32FC1 depth image, depthMax > 0 "
                               "and depthQuantization > 0");
  }
  // Quantised inverse depth: q(depthMax) = 1 and q grows as 1/depth, so near depths get the
  // finest steps; q = 0 is reserved for "no depth".
  const float z0 = static_cast<float>(depthQuantization);
  const float a = z0 * (z0 + 1.0f);
  const float b = 1.0f - a / static_cast<float>(depthMax);
  cv::Mat q(depth.size(), CV_16UC1);
  for (int r = 0; r < depth.rows; ++r) {
    const float* d = depth.ptr<float>(r);
    uint16_t* out = q.ptr<uint16_t>(r);
    for (int c = 0; c < depth.cols; ++c) {
      const float z = d[c];
      if (!(z > 0.0f) || !(z < depthMax)) {
        out[c] = 0;
        continue;
      }
      const float v = a / z + b;
      out[c] = v >= 65535.0f ? 65535 : static_cast<uint16_t>(std::max(1.0f, v));
    }
  }
  msg.format = "32FC1; compressedDepth png";
  msg.data = depthHeader(a, b);
  const rtabmap::Bytes png = rtabmap::codec::compressImage(q, ".png");
  msg.data.insert(msg.data.end(), png.begin(), png.end());
  return msg;
}

sensor_msgs::CompressedImage compressedDepthLosslessToMsg(const cv::Mat& depth, const std_msgs::Header& header) {
  if (depth.type() == CV_16UC1) return compressedDepthToMsg(depth, header);
  if (depth.type() != CV_32FC1 || depth.empty()) {
    throw rtabmap::FormatError("compressedDepthLosslessToMsg: expected a CV_16UC1 or CV_32FC1 depth image");
  }
  sensor_msgs::CompressedImage msg;
  msg.header = header;
  msg.format = "32FC1; rtabmap zlib";
  msg.data = rtabmap::codec::compressData(depth);
  return msg;
}

sensor_msgs::CompressedImage compressedBytesToMsg(const rtabmap::Bytes& bytes, const std_msgs::Header& header,
                                                  bool depth) {
  sensor_msgs::CompressedImage msg;
  msg.header = header;
  if (rtabmap::codec::isCompressedData(bytes)) {
    msg.format = "rtabmap zlib";
    msg.data = bytes;
  } else if (depth && isPng(bytes)) {
    msg.format = "16UC1; compressedDepth png";
    msg.data = depthHeader(0.0f, 0.0f);
    msg.data.insert(msg.data.end(), bytes.begin(), bytes.end());
  } else if (isPng(bytes)) {
    msg.format = "png";
    msg.data = bytes;
  } else if (isJpeg(bytes)) {
    msg.format = "jpeg";
    msg.data = bytes;
  } else {
    throw rtabmap::FormatError("compressedBytesToMsg: " + std::to_string(bytes.size()) +
                               " bytes that are neither jpeg, png nor a zlib blob of the core");
  }
  return msg;
}

std::optional<cv::Mat> compressedImageFromMsg(const sensor_msgs::CompressedImage& msg, std::string* error) {
  const std::string what = "compressed image of frame '" + msg.header.frame_id + "' (format '" + msg.format + "')";
  if (msg.data.empty()) return detail::fail(error, what + " has no data");
  const size_t semicolon = msg.format.find(';');
  const std::string encoding = trim(msg.format.substr(0, semicolon));
  const std::string rest = semicolon == std::string::npos ? "" : msg.format.substr(semicolon + 1);
  if (rest.find("compressedDepth") != std::string::npos) return decodeCompressedDepth(msg, encoding, rest, error);
  const bool zlib = msg.format.find("rtabmap zlib") != std::string::npos;
  const bool known = zlib || msg.format.find("jpeg") != std::string::npos ||
                     msg.format.find("jpg") != std::string::npos || msg.format.find("png") != std::string::npos;
  if (!known) {
    return detail::fail(error, what + ": unknown format; expected jpeg, png (compressed transport), "
                                      "compressedDepth png, or rtabmap zlib");
  }
  cv::Mat image;
  try {
    image = zlib ? rtabmap::codec::uncompressData(msg.data) : rtabmap::codec::uncompressImage(msg.data);
  } catch (const std::exception& e) {
    return detail::fail(error, what + ": corrupt data (" + e.what() + ")");
  }
  if (imageEncoding(image.type()).empty()) {
    return detail::fail(error, what + " decodes to image type " + std::to_string(image.type()) +
                                   ", which is neither grey, colour nor depth");
  }
  return image;
}

}  // namespace rtabmap_conversions
