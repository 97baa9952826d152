#include "GroundAlignment.h"

#include <Eigen/Geometry>

#include <exception>

#include "rtabmap_core/maps/GroundPlane.h"
#include "rtabmap_core/maps/LocalGridOptions.h"
#include "rtabmap_core/maps/LocalGridStages.h"

namespace rtabmap::odometry_detail {
namespace {

// The points the frame sees, in its base frame, within 5 m (the floor near the robot).
Cloud cloudOf(const SensorData& frame) {
  LocalGridOptions o;
  o.rangeMax = 5.0f;
  SensorData data = frame;
  data.uncompress(true, true, true, false);
  const bool depthOrStereo = !data.depthOrRightRaw().empty() &&
                             (data.isStereo() ? !data.imageRaw().empty() : !data.cameraModels().empty());
  if (depthOrStereo) {
    std::vector<CameraModel> models;
    const cv::Mat depth = depthOfFrame(data, o.stereo, &models);
    return cloudFromDepth(depth, cv::Mat(), models, o);
  }
  if (!data.laserScanRaw().empty() && !data.laserScanRaw().is2d()) return cloudFromScan(data.laserScanRaw(), o);
  return Cloud();
}

}  // namespace

Transform groundAlignedPose(const SensorData& data, std::string* why) {
  Cloud cloud;
  try {
    cloud = voxelFilter(cloudOf(data), 0.05f);
  } catch (const std::exception& e) {
    if (why) *why = e.what();
    return Transform();
  }
  if (cloud.empty()) {
    if (why) *why = "the frame has no depth image, stereo pair or 3D scan to find the floor in";
    return Transform();
  }
  const std::optional<GroundPlane> floor = findGroundPlane(cloud);
  if (!floor) {
    if (why) *why = "no floor found in the first frame (no plane below the sensor holding 20% of its points)";
    return Transform();
  }
  // The rotation taking the floor's normal to z, the smallest one (about a horizontal axis):
  // a floor point p then has z = n . p + height = 0.
  const Eigen::Quaterniond level = Eigen::Quaterniond::FromTwoVectors(floor->normal, Eigen::Vector3d::UnitZ());
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = level.toRotationMatrix();
  pose.translation() = Eigen::Vector3d(0.0, 0.0, floor->height);
  return Transform(pose);
}

}  // namespace rtabmap::odometry_detail
