#pragma once
// sensor_msgs/CameraInfo <-> rtabmap::CameraModel / StereoCameraModel.
//
// Everything CameraInfo carries travels: K, D, R, P, the distortion model name, the image
// size. Binning and region of interest, when a driver sets them, are applied (the model then
// describes the binned / cropped image the driver publishes, as image_geometry does); models
// are always written back without them. The camera's pose on the robot (the model's local
// transform: base frame -> camera optical frame) is not in CameraInfo: it comes from tf,
// e.g. lookupTransform(buffer, "base_link", info.header.frame_id, stamp, wait) (TfLookup.h).
//
// A rectified stereo pair is two CameraInfo whose right P has Tx = P[3] = -fx * baseline, as
// stereo_image_proc and every stereo driver publish them.
#include <sensor_msgs/CameraInfo.h>
#include <std_msgs/Header.h>

#include <optional>
#include <string>

#include "rtabmap_core/geometry/CameraModel.h"
#include "rtabmap_core/geometry/StereoCameraModel.h"

namespace rtabmap_conversions {

sensor_msgs::CameraInfo cameraModelToMsg(const rtabmap::CameraModel& model, const std_msgs::Header& header);
// The model of the image the info describes. Errors (std::nullopt and *error): zero or
// negative focal length in both K and P (an uncalibrated camera), NaN or infinite entries, a
// zero image size, a distortion model that is unknown or whose coefficient count does not fit,
// unequal binning in x and y, a region of interest outside the image.
std::optional<rtabmap::CameraModel> cameraModelFromMsg(
    const sensor_msgs::CameraInfo& msg,
    const rtabmap::Transform& localTransform = rtabmap::CameraModel::opticalRotation(),
    std::string* error = nullptr);

// Both infos of a rectified pair; localTransform is the left camera's (base -> left optical
// frame). Errors: either model invalid, right Tx >= 0 (no baseline), different image sizes or
// rectified focal lengths.
std::optional<rtabmap::StereoCameraModel> stereoModelFromMsgs(
    const sensor_msgs::CameraInfo& left, const sensor_msgs::CameraInfo& right,
    const rtabmap::Transform& localTransform = rtabmap::CameraModel::opticalRotation(),
    std::string* error = nullptr);
void stereoModelToMsgs(const rtabmap::StereoCameraModel& model, const std_msgs::Header& leftHeader,
                       const std_msgs::Header& rightHeader, sensor_msgs::CameraInfo& left,
                       sensor_msgs::CameraInfo& right);

}  // namespace rtabmap_conversions
