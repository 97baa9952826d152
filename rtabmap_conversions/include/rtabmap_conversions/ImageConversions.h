#pragma once
// sensor_msgs/Image <-> cv::Mat, through cv_bridge, in the core's image conventions:
//   grey   CV_8UC1  mono8 (also 8UC1)
//   colour CV_8UC3  BGR: bgr8 kept, rgb8 and bayer_* converted (also 8UC3, taken as bgr8)
//          CV_8UC4  BGRA: bgra8 kept, rgba8 converted
//   depth  CV_16UC1 millimetres: 16UC1 and mono16 (the same bytes: openni drivers say mono16)
//          CV_32FC1 metres: 32FC1
// Converting back picks the encoding from the matrix type (mono8, bgr8, bgra8, 16UC1, 32FC1),
// so every type above round-trips bit-exactly.
//
// Messages come from outside: a wrong encoding, a step or data size that does not match the
// width and height, or an empty image gives std::nullopt and the reason in *error, never an
// exception or a read past the buffer.
#include <opencv2/core/mat.hpp>
#include <sensor_msgs/Image.h>
#include <std_msgs/Header.h>

#include <optional>
#include <string>

namespace rtabmap_conversions {

// The ROS encoding of a core image type (see above), or "" for a type the core never holds.
std::string imageEncoding(int cvType);

// Throws rtabmap::FormatError for an empty image or a type without an encoding.
sensor_msgs::Image imageToMsg(const cv::Mat& image, const std_msgs::Header& header);

// Any image of the table above (grey, colour, or depth), converted to the core's type.
std::optional<cv::Mat> imageFromMsg(const sensor_msgs::Image& msg, std::string* error = nullptr);
// A depth image only: 16UC1 / mono16 (mm) or 32FC1 (m); anything else is an error that names
// the encoding. NaN and 0 stay in the image (both mean "no depth" to the core).
std::optional<cv::Mat> depthFromMsg(const sensor_msgs::Image& msg, std::string* error = nullptr);
// A grey or colour image only (mono8, bgr8, rgb8, bgra8, rgba8, bayer_*): what features are
// extracted from.
std::optional<cv::Mat> colorFromMsg(const sensor_msgs::Image& msg, std::string* error = nullptr);

}  // namespace rtabmap_conversions
