#include "rtabmap_conversions/BagLayout.h"

#include "rtabmap_core/common/Error.h"

namespace rtabmap_conversions::bag {

namespace {

// Splits base -> optical into base -> camera_link (body axes) and camera_link -> optical.
void addCamera(const rtabmap::Transform& baseToOptical, const char* opticalFrame, StaticTransforms& out) {
  if (baseToOptical.isNull()) return;
  const rtabmap::Transform optical = rtabmap::CameraModel::opticalRotation();
  out[kCameraFrame] = {kBaseFrame, baseToOptical * optical.inverse()};
  out[opticalFrame] = {kCameraFrame, optical};
}

}  // namespace

const char* scanFrame(const rtabmap::LaserScan& scan) {
  return scan.is2d() ? kLaserFrame : kVelodyneFrame;
}

const char* scanTopic(const rtabmap::LaserScan& scan) {
  if (!scan.is2d()) return kCloudTopic;
  return scan.hasBeamGeometry() ? kScanTopic : kScanCloudTopic;
}

void addStaticTransforms(const rtabmap::SensorData& data, StaticTransforms& out) {
  // A scan without points is still a scan (every beam a no-return, in an open space): its
  // format says a laser is there. SensorData::laserScanInfo() describes only a scan that has
  // points (or a compressed one), so a raw scan's own format and mounting come first.
  const rtabmap::LaserScan& raw = data.laserScanRaw();
  rtabmap::LaserScan::Format format = raw.format();
  rtabmap::Transform mounting = raw.localTransform();
  if (format == rtabmap::LaserScan::kUnknown) {
    const rtabmap::SensorData::ScanInfo info = data.laserScanInfo();
    format = info.format;
    mounting = info.localTransform;
  }
  if (format != rtabmap::LaserScan::kUnknown) {
    out[rtabmap::LaserScan::is2d(format) ? kLaserFrame : kVelodyneFrame] = {kBaseFrame, mounting};
  }
  if (data.stereoCameraModels().size() > 1) {
    throw rtabmap::FormatError("a frame with " + std::to_string(data.stereoCameraModels().size()) +
                               " stereo cameras: the bag layout has one RGB-D or stereo camera");
  }
  if (data.isStereo()) {
    const rtabmap::StereoCameraModel& stereo = data.stereoCameraModels().front();
    addCamera(stereo.localTransform(), kLeftOpticalFrame, out);
    if (!stereo.localTransform().isNull()) {
      out[kRightOpticalFrame] = {kCameraFrame, rtabmap::CameraModel::opticalRotation() *
                                                   rtabmap::Transform(stereo.baseline(), 0, 0, 0, 0, 0)};
    }
  } else if (data.cameraModels().size() == 1) {
    addCamera(data.cameraModels().front().localTransform(), kRgbOpticalFrame, out);
  } else if (data.cameraModels().size() > 1) {
    throw rtabmap::FormatError("a frame with " + std::to_string(data.cameraModels().size()) +
                               " cameras: the bag layout has one RGB-D or stereo camera");
  }
  if (!data.imu().empty()) out[kImuFrame] = {kBaseFrame, data.imu().localTransform};
}

}  // namespace rtabmap_conversions::bag
