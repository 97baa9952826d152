#pragma once
// rtabmap_ros/LandmarkDetection -> rtabmap::Landmark: detections from another node (an AprilTag or
// ArUco detector relayed to this message) that the rtabmap node adds to the next frame it maps.
#include <optional>
#include <string>

#include "rtabmap_core/geometry/Landmark.h"
#include "rtabmap_ros/LandmarkDetection.h"

namespace rtabmap_conversions {

// The landmark in the detection's frame (header.frame_id; the caller brings it to the base
// frame). A covariance of zeros takes the diagonal (linear x3, angular x3).
// Errors: an id below 1, an empty frame_id, a NaN, infinite or zero-length pose, a negative or
// non-finite size, a covariance with NaN or a non-positive diagonal.
std::optional<rtabmap::Landmark> landmarkFromMsg(const rtabmap_ros::LandmarkDetection& msg, double linearVariance,
                                                 double angularVariance, std::string* error = nullptr);

}  // namespace rtabmap_conversions
