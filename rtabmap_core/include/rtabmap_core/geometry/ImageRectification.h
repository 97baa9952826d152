#pragma once
// Rtabmap/ImagesAlreadyRectified false: raw camera images (a driver's image_raw) rectified with
// their calibration (CameraModel: K, D, R, P) before features, depth or grids are taken from
// them. Each camera of a side-by-side image on its own; a depth image registered to the raw
// colour image (the same size or a whole fraction of it) by nearest neighbour, never
// interpolated; a stereo pair through its rectification. The frame's models become their
// rectified() ones, so rectifying the frame again (odometry, then SLAM) changes nothing.
#include "rtabmap_core/geometry/SensorData.h"

namespace rtabmap {

// True when some camera of the frame has distortion or a rectification rotation.
bool needsRectification(const SensorData& data);

// The frame with rectified images (compressed-only images are decoded first); the frame itself
// when nothing needs rectifying. Throws FormatError when an image does not have its
// calibration's size.
SensorData rectifyImages(const SensorData& data);

}  // namespace rtabmap
