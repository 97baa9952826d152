#pragma once
// Synthetic camera views of fiducial markers for tests: a white wall with ArUco / AprilTag markers
// drawn by OpenCV at known poses, rendered through a pinhole model by a homography (exact for a
// plane), with the matching depth image (32FC1, metres) of the wall and markers.
#include <opencv2/core/mat.hpp>

#include <vector>

#include "rtabmap_core/geometry/CameraModel.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap::test {

struct MarkerInView {
  int id = 1;
  float length = 0.2f;       // side (m), black border included
  Transform cameraToMarker;  // optical frame -> marker frame (x right, y up, z out of the marker)
};

// A marker `length` wide at `distance` straight ahead of the optical frame, facing the camera,
// turned by `yaw` about its vertical axis, offset by (dx, dy) in the image plane.
Transform markerAhead(double distance, double yaw = 0.0, double dx = 0.0, double dy = 0.0);

// The grey image (white background) and its depth (the background at `wallDepth`, 0 = none).
struct MarkerView {
  cv::Mat grey, depth;
};
MarkerView renderMarkers(const CameraModel& model, const std::vector<MarkerInView>& markers, int dictionary,
                         float wallDepth = 0.0f);

}  // namespace rtabmap::test
