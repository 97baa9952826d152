#pragma once
// sensor_msgs/CompressedImage <-> cv::Mat, in the layouts the image_transport plugins publish,
// so a node can subscribe to `image/compressed` or `depth/compressedDepth` topics directly:
//
//  "compressed" transport: format "<encoding>; jpeg compressed <target>" or
//    "<encoding>; png compressed <target>" (older publishers: just "jpeg" / "png"); the data is
//    the codec stream. Decoded to the core's types (BGR, grey, 16-bit).
//  "compressedDepth" transport: format "16UC1; compressedDepth png" or
//    "32FC1; compressedDepth png" (older: "16UC1; compressedDepth"); the data starts with a
//    12-byte header (int32 format, float32 quantisation parameters A and B) followed by a PNG.
//    16UC1 is lossless PNG of the millimetres. 32FC1 is stored as 16-bit quantised inverse
//    depth q = A / depth + B (q = 0: no depth), decoded as depth = A / (q - B), NaN for q = 0:
//    lossy, with a resolution that degrades with depth (about 1 cm at 1 m, 30 cm at 5 m with
//    the transport's defaults).
//  "<encoding>; rtabmap zlib": the core's lossless zlib blob (codec::compressData), used by
//    RGBDImage for 32FC1 depth, which compressedDepth could only store lossily.
//
// The RVL codec of newer compressedDepth publishers is not supported (a clear error says so).
#include <opencv2/core/mat.hpp>
#include <sensor_msgs/CompressedImage.h>
#include <std_msgs/Header.h>

#include <optional>
#include <string>

#include "rtabmap_core/codec/Compression.h"

namespace rtabmap_conversions {

// The compressed transport: format "jpeg" or "png". Colour (CV_8UC3 BGR), grey (CV_8UC1), and
// with png also BGRA (CV_8UC4) and 16-bit (CV_16UC1). Throws rtabmap::FormatError for another
// type or format (the caller chose them).
sensor_msgs::CompressedImage compressedImageToMsg(const cv::Mat& image, const std_msgs::Header& header,
                                                  const std::string& format = "jpeg");
// The compressedDepth transport: CV_16UC1 (lossless) or CV_32FC1 (inverse-depth quantisation;
// depths >= depthMax, <= 0 or NaN become "no depth"). depthQuantization is the transport's
// "depth_quantization" parameter (larger = finer). Throws rtabmap::FormatError for other types.
sensor_msgs::CompressedImage compressedDepthToMsg(const cv::Mat& depth, const std_msgs::Header& header,
                                                  double depthMax = 10.0, double depthQuantization = 100.0);
// Lossless: CV_16UC1 -> compressedDepth png; CV_32FC1 -> "32FC1; rtabmap zlib".
sensor_msgs::CompressedImage compressedDepthLosslessToMsg(const cv::Mat& depth, const std_msgs::Header& header);
// Wraps bytes the core already compressed (SensorData::imageCompressed(), ...: jpeg, png or a
// zlib blob, told apart by their first bytes) in the matching format without re-encoding.
// depth = true marks 16-bit png bytes as compressedDepth (header prepended).
sensor_msgs::CompressedImage compressedBytesToMsg(const rtabmap::Bytes& bytes, const std_msgs::Header& header,
                                                  bool depth);

// Any of the formats above. Bad formats, truncated or corrupt data give std::nullopt with the
// reason in *error.
std::optional<cv::Mat> compressedImageFromMsg(const sensor_msgs::CompressedImage& msg,
                                              std::string* error = nullptr);

}  // namespace rtabmap_conversions
