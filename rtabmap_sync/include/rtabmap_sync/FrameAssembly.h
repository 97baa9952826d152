#pragma once
// What the sync nodelets do with a synchronised set, without ROS plumbing (unit-tested):
// check the messages through rtabmap_conversions and build the core frame, or say precisely
// what is wrong (which topic, which field) so the node can log it and go on.
#include <rtabmap_ros/RGBDImage.h>
#include <rtabmap_ros/RGBDImages.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/LaserScan.h"
#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap_sync {

struct RgbdFrameOptions {
  // Keep one pixel in `decimation` per axis; the image size must be a multiple of it. The
  // camera model is scaled with the images.
  int decimation = 1;
  // Multiplies every depth value (corrects a sensor's depth scale error).
  double depthScale = 1.0;
};

// rgb/image + depth/image + rgb/camera_info -> an RGB-D frame stamped with the rgb stamp.
// Errors: undecodable or empty images, unknown encodings (rgb: mono8/bgr8/rgb8/bgra8/rgba8/
// bayer; depth: 16UC1/mono16/32FC1), an invalid camera_info (zero K, ...), sizes that differ
// between the images and the camera_info, a decimation that does not divide the size.
std::optional<rtabmap::SensorData> rgbdFrame(const sensor_msgs::Image& rgb, const sensor_msgs::Image& depth,
                                             const sensor_msgs::CameraInfo& info,
                                             const RgbdFrameOptions& options = {}, std::string* error = nullptr);

// left/image_rect + right/image_rect + both camera_infos (rectified, right Tx < 0) -> a stereo
// frame (right image as grey, as the core's stereo matching wants it).
std::optional<rtabmap::SensorData> stereoFrame(const sensor_msgs::Image& left, const sensor_msgs::Image& right,
                                               const sensor_msgs::CameraInfo& leftInfo,
                                               const sensor_msgs::CameraInfo& rightInfo,
                                               std::string* error = nullptr);

// An RGBDImage rgbdx_sync may bundle: an image (raw or compressed) and a valid camera_info.
// Images are not decoded (the consumer does), so this stays cheap.
bool checkRgbdImage(const rtabmap_ros::RGBDImage& msg, std::string* error = nullptr);

// Several RGB-D cameras (or several stereo cameras, never mixed) side by side as one frame:
// `bundle` (rtabmap_ros/RGBDImages from rgbdx_sync, rgbd_cameras 0) when set, else the
// synchronised `images` (rgbd_image0..N-1); each camera placed on the robot by
// sensorPose(frame_id, stamp, error), the node's tf lookup. The error says which lookup or which
// camera's images failed.
using SensorPoseFn = std::function<rtabmap::Transform(const std::string&, const ros::Time&, std::string*)>;
std::optional<rtabmap::SensorData> rgbdCamerasFrame(const rtabmap_ros::RGBDImagesConstPtr& bundle,
                                                    const std::vector<rtabmap_ros::RGBDImageConstPtr>& images,
                                                    const SensorPoseFn& sensorPose, std::string* error);

// The laser input of a synchronised set: `scan` when there is one, else `cloud` (scan_cloud),
// with `local` the sensor's pose on the robot. The error names the topic and what is wrong.
std::optional<rtabmap::LaserScan> syncedScan(const sensor_msgs::LaserScanConstPtr& scan,
                                             const sensor_msgs::PointCloud2ConstPtr& cloud,
                                             const rtabmap::Transform& local, std::string* error = nullptr);

}  // namespace rtabmap_sync
