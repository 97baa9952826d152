#pragma once
// The topics and frames of the bags rtabmap-bag writes (and rtabmap-sim --bag), chosen so the
// classic rtabmap_ros launch files run on them unchanged (REP-105 frames):
//
//   topic                                  type                    frame_id
//   /tf                                    tf2_msgs/TFMessage      odom -> base_link (odometry)
//   /tf_static                             tf2_msgs/TFMessage      base_link -> sensors (latched)
//   /odom                                  nav_msgs/Odometry       odom, child base_link
//   /ground_truth                          nav_msgs/Odometry       world, child base_link
//   /scan                                  sensor_msgs/LaserScan   laser
//   /velodyne_points                       sensor_msgs/PointCloud2 velodyne (3D scans)
//   /scan_cloud                            sensor_msgs/PointCloud2 laser (planar scans without
//                                                                  beam geometry)
//   /camera/rgb/image_rect_color           sensor_msgs/Image       camera_rgb_optical_frame
//   /camera/depth_registered/image_raw     sensor_msgs/Image       camera_rgb_optical_frame
//                                          (16UC1 mm or 32FC1 m, as the dataset has it)
//   /camera/rgb/camera_info                sensor_msgs/CameraInfo  camera_rgb_optical_frame
//   /stereo_camera/left/image_rect         sensor_msgs/Image       camera_left_optical_frame
//   /stereo_camera/right/image_rect        sensor_msgs/Image       camera_right_optical_frame
//   /stereo_camera/left/camera_info        sensor_msgs/CameraInfo  camera_left_optical_frame
//   /stereo_camera/right/camera_info       sensor_msgs/CameraInfo  camera_right_optical_frame
//   /imu/data                              sensor_msgs/Imu         imu_link
//
// Camera frames follow REP-103: camera_link has the robot's body axes (x forward, y left,
// z up) at the camera's position; the optical frames below it have z forward, x right, y down,
// and are what image headers name. The static tf chain is
//   base_link -> camera_link -> camera_rgb_optical_frame            (RGB-D or mono camera)
//   base_link -> camera_link -> camera_left_optical_frame
//                            -> camera_right_optical_frame          (rectified stereo: the
//                                                                    right one baseline metres
//                                                                    along the left's x axis)
//   base_link -> laser | velodyne,  base_link -> imu_link
// with camera_link = (base_link -> optical) * CameraModel::opticalRotation()^-1, so the chain
// multiplies back exactly to the camera model's local transform.
#include <map>
#include <string>

#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap_conversions::bag {

inline constexpr const char* kTfTopic = "/tf";
inline constexpr const char* kTfStaticTopic = "/tf_static";
inline constexpr const char* kOdomTopic = "/odom";
inline constexpr const char* kGroundTruthTopic = "/ground_truth";
inline constexpr const char* kScanTopic = "/scan";
inline constexpr const char* kCloudTopic = "/velodyne_points";
inline constexpr const char* kScanCloudTopic = "/scan_cloud";
inline constexpr const char* kRgbTopic = "/camera/rgb/image_rect_color";
inline constexpr const char* kDepthTopic = "/camera/depth_registered/image_raw";
inline constexpr const char* kRgbInfoTopic = "/camera/rgb/camera_info";
inline constexpr const char* kLeftTopic = "/stereo_camera/left/image_rect";
inline constexpr const char* kRightTopic = "/stereo_camera/right/image_rect";
inline constexpr const char* kLeftInfoTopic = "/stereo_camera/left/camera_info";
inline constexpr const char* kRightInfoTopic = "/stereo_camera/right/camera_info";
inline constexpr const char* kImuTopic = "/imu/data";

inline constexpr const char* kWorldFrame = "world";
inline constexpr const char* kOdomFrame = "odom";
inline constexpr const char* kBaseFrame = "base_link";
inline constexpr const char* kLaserFrame = "laser";
inline constexpr const char* kVelodyneFrame = "velodyne";
inline constexpr const char* kCameraFrame = "camera_link";
inline constexpr const char* kRgbOpticalFrame = "camera_rgb_optical_frame";
inline constexpr const char* kLeftOpticalFrame = "camera_left_optical_frame";
inline constexpr const char* kRightOpticalFrame = "camera_right_optical_frame";
inline constexpr const char* kImuFrame = "imu_link";

// One static transform: parent -> child (the pose of child in parent).
struct StaticTransform {
  std::string parent;
  rtabmap::Transform transform;
};
using StaticTransforms = std::map<std::string, StaticTransform>;  // keyed by child frame

// The static transforms a sensor frame implies (its scan's, cameras' and IMU's mountings),
// added to / replacing those of `out`. Throws rtabmap::FormatError for a frame with several
// cameras (one RGB-D or stereo camera per dataset is what the topics above describe).
void addStaticTransforms(const rtabmap::SensorData& data, StaticTransforms& out);
// The frame a planar or 3D scan is published in, and its topic.
const char* scanFrame(const rtabmap::LaserScan& scan);
const char* scanTopic(const rtabmap::LaserScan& scan);

}  // namespace rtabmap_conversions::bag
