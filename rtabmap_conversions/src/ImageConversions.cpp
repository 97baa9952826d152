#include "rtabmap_conversions/ImageConversions.h"

#include <cv_bridge/cv_bridge.h>

#include <algorithm>
#include <sensor_msgs/image_encodings.h>

#include "Support.h"
#include "rtabmap_core/common/Error.h"

namespace enc = sensor_msgs::image_encodings;

namespace rtabmap_conversions {

namespace {

enum class Want { kAny, kDepth, kColor };

// The core encoding a message is converted to, "" if the message encoding is not accepted.
std::string targetEncoding(const std::string& encoding, Want want) {
  const bool depth = encoding == enc::TYPE_16UC1 || encoding == enc::MONO16 || encoding == enc::TYPE_32FC1;
  if (want == Want::kDepth) return depth ? (encoding == enc::TYPE_32FC1 ? enc::TYPE_32FC1 : enc::TYPE_16UC1) : "";
  if (depth) return want == Want::kAny ? (encoding == enc::TYPE_32FC1 ? enc::TYPE_32FC1 : enc::TYPE_16UC1) : "";
  if (encoding == enc::MONO8 || encoding == enc::TYPE_8UC1) return enc::MONO8;
  if (encoding == enc::BGR8 || encoding == enc::RGB8 || encoding == enc::TYPE_8UC3 || enc::isBayer(encoding)) {
    return enc::BGR8;
  }
  if (encoding == enc::BGRA8 || encoding == enc::RGBA8) return enc::BGRA8;
  return "";
}

const char* expectedList(Want want) {
  switch (want) {
    case Want::kDepth:
      return "16UC1 or mono16 (millimetres) or 32FC1 (metres)";
    case Want::kColor:
      return "mono8, bgr8, rgb8, bgra8, rgba8 or bayer_*";
    default:
      return "mono8, bgr8, rgb8, bgra8, rgba8, bayer_*, 16UC1, mono16 or 32FC1";
  }
}

// Checks what cv_bridge trusts blindly: that step and data cover width x height.
bool checkLayout(const sensor_msgs::Image& msg, std::string* error) {
  const std::string what = "image (frame '" + msg.header.frame_id + "', encoding '" + msg.encoding + "')";
  if (msg.width == 0 || msg.height == 0) {
    detail::fail(error, what + " is empty (" + std::to_string(msg.width) + "x" + std::to_string(msg.height) + ")");
    return false;
  }
  int bytesPerPixel = 0;
  try {
    bytesPerPixel = enc::numChannels(msg.encoding) * enc::bitDepth(msg.encoding) / 8;
  } catch (const std::exception&) {
    detail::fail(error, what + " has an unknown encoding");
    return false;
  }
  const uint64_t rowBytes = uint64_t(msg.width) * uint64_t(bytesPerPixel);
  if (msg.step < rowBytes) {
    detail::fail(error, what + ": step " + std::to_string(msg.step) + " is shorter than a row of " +
                            std::to_string(msg.width) + " pixels (" + std::to_string(rowBytes) + " bytes)");
    return false;
  }
  const uint64_t needed = uint64_t(msg.step) * uint64_t(msg.height);
  if (msg.data.size() < needed) {
    detail::fail(error, what + ": " + std::to_string(msg.data.size()) + " data bytes for " +
                            std::to_string(msg.width) + "x" + std::to_string(msg.height) + " pixels with step " +
                            std::to_string(msg.step) + " (" + std::to_string(needed) + " bytes needed)");
    return false;
  }
  return true;
}

// cv_bridge reinterprets a byte-swapped 16/32-bit image as a 2-channel 8-bit one instead of
// swapping it: swap here, on a copy (rare: no common driver publishes big-endian images).
sensor_msgs::Image toHostOrder(const sensor_msgs::Image& msg) {
  sensor_msgs::Image out = msg;
  const size_t bytes = size_t(enc::bitDepth(msg.encoding) / 8);
  const size_t rowBytes = size_t(out.width) * size_t(enc::numChannels(msg.encoding)) * bytes;
  for (uint32_t r = 0; r < out.height; ++r) {
    uint8_t* row = out.data.data() + size_t(r) * out.step;
    for (size_t i = 0; i < rowBytes; i += bytes) std::reverse(row + i, row + i + bytes);
  }
  out.is_bigendian = !msg.is_bigendian;
  return out;
}

bool hostIsBigEndian() {
  const uint16_t one = 1;
  return *reinterpret_cast<const uint8_t*>(&one) == 0;
}

std::optional<cv::Mat> convert(const sensor_msgs::Image& input, Want want, std::string* error) {
  const sensor_msgs::Image* source = &input;
  const std::string target = targetEncoding(input.encoding, want);
  if (target.empty()) {
    return detail::fail(error, "image of frame '" + input.header.frame_id + "' has encoding '" + input.encoding +
                                   "'; expected " + expectedList(want));
  }
  if (!checkLayout(input, error)) return std::nullopt;
  std::optional<sensor_msgs::Image> swapped;
  if (bool(input.is_bigendian) != hostIsBigEndian() && enc::bitDepth(input.encoding) > 8) {
    swapped = toHostOrder(input);
    source = &*swapped;
  }
  const sensor_msgs::Image& msg = *source;
  try {
    // mono16 and 16UC1 are the same bytes; cv_bridge would scale a mono16 -> 16UC1 request.
    if (target == enc::TYPE_16UC1 || target == enc::TYPE_32FC1) {
      return cv_bridge::toCvCopy(msg)->image;
    }
    return cv_bridge::toCvCopy(msg, target)->image;
  } catch (const std::exception& e) {
    return detail::fail(error, "image of frame '" + msg.header.frame_id + "' (" + msg.encoding +
                                   ") could not be converted: " + e.what());
  }
}

}  // namespace

std::string imageEncoding(int cvType) {
  switch (cvType) {
    case CV_8UC1:
      return enc::MONO8;
    case CV_8UC3:
      return enc::BGR8;
    case CV_8UC4:
      return enc::BGRA8;
    case CV_16UC1:
      return enc::TYPE_16UC1;
    case CV_32FC1:
      return enc::TYPE_32FC1;
    default:
      return "";
  }
}

sensor_msgs::Image imageToMsg(const cv::Mat& image, const std_msgs::Header& header) {
  const std::string encoding = imageEncoding(image.type());
  if (image.empty() || encoding.empty()) {
    throw rtabmap::FormatError("imageToMsg: " + std::string(image.empty() ? "empty image" : "image type " +
                               std::to_string(image.type()) + " has no ROS encoding (expected CV_8UC1, CV_8UC3, "
                               "CV_8UC4, CV_16UC1 or CV_32FC1)"));
  }
  sensor_msgs::Image msg;
  cv_bridge::CvImage(header, encoding, image).toImageMsg(msg);
  return msg;
}

std::optional<cv::Mat> imageFromMsg(const sensor_msgs::Image& msg, std::string* error) {
  return convert(msg, Want::kAny, error);
}

std::optional<cv::Mat> depthFromMsg(const sensor_msgs::Image& msg, std::string* error) {
  return convert(msg, Want::kDepth, error);
}

std::optional<cv::Mat> colorFromMsg(const sensor_msgs::Image& msg, std::string* error) {
  return convert(msg, Want::kColor, error);
}

}  // namespace rtabmap_conversions
