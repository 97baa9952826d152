#pragma once
// Depth registration: a depth image taken by one camera, re-expressed as the depth the colour
// camera would see at each of its pixels. This is what an RGB-D driver does when depth
// registration is on (OpenNI's depth_registration); the core assumes registered depth
// everywhere (one CameraModel per RGB-D image), so a dataset whose depth was recorded in the
// depth camera's own image (Microsoft 7-Scenes) is registered once, when it is read.
#include <opencv2/core/mat.hpp>

#include "rtabmap_core/geometry/CameraModel.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap {

// depth: CV_16UC1 (mm) or CV_32FC1 (m), in depthModel's image; 0 (and NaN for 32FC1) is "no
// measurement". depthToColour maps a point from the depth camera's optical frame to the colour
// camera's optical frame (X_colour = depthToColour * X_depth). Returns a depth image of the
// same type, of colourModel's image size, in colourModel's image: each valid depth pixel is
// lifted to 3D with depthModel, moved to the colour frame and projected to the nearest colour
// pixel; where several land on one pixel the nearest surface wins (occlusion), and colour pixels
// no depth pixel reaches stay 0 (outside the depth camera's view, in the shadow of a nearer
// surface, or between samples when the colour image is sampled more finely than the depth's).
// Throws std::invalid_argument for another image type, a model that cannot project, or a
// colour model without an image size.
cv::Mat registerDepth(const cv::Mat& depth, const CameraModel& depthModel,
                      const CameraModel& colourModel, const Transform& depthToColour);

}  // namespace rtabmap
