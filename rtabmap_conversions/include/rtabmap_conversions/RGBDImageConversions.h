#pragma once
// rtabmap_ros/RGBDImage(s) <-> rtabmap::SensorData: one synchronised camera frame.
//
// RGB-D: rgb = colour or grey image, depth = registered depth (16UC1 mm or 32FC1 m),
// rgb_camera_info = its calibration (depth_camera_info: the same, depth being registered).
// Stereo: rgb = rectified left, depth = rectified right (grey), rgb_camera_info /
// depth_camera_info = left / right infos, the right one with Tx = -fx * baseline: a message is
// stereo when its right info has Tx < 0 and its second image is not a depth image.
// Each image travels either raw (rgb, depth) or compressed (rgb_compressed, depth_compressed,
// see CompressedImageConversions.h: jpeg / png for images, lossless compressedDepth png or
// "rtabmap zlib" for depth); a reader takes the raw one when both are set.
// Features extracted upstream (odometry) ride along: key_points, points (3D, same count or
// none) and descriptors (FeatureConversions.h).
//
// RGBDImages holds several RGB-D cameras, or several stereo cameras; the core keeps them side by
// side in one SensorData (images concatenated horizontally, one camera model each; for stereo
// the left images side by side and the right images side by side the same way).
#include <rtabmap_ros/RGBDImage.h>
#include <rtabmap_ros/RGBDImages.h>
#include <std_msgs/Header.h>

#include <optional>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap_conversions {

struct RGBDImageOptions {
  // Fill rgb_compressed / depth_compressed instead of rgb / depth. Bytes the SensorData already
  // holds compressed are passed through as they are; raw images are compressed with
  // imageFormat ("jpeg" or "png") and lossless depth.
  bool compressed = false;
  std::string imageFormat = "jpeg";
  // frame_id of the right camera of a stereo pair ("" = header.frame_id).
  std::string rightFrameId;
};

// header: stamp and the camera (left / rgb) optical frame. Throws rtabmap::FormatError for a
// SensorData with several cameras (use rgbdImagesToMsg) or no camera model.
rtabmap_ros::RGBDImage rgbdImageToMsg(const rtabmap::SensorData& data, const std_msgs::Header& header,
                                      const RGBDImageOptions& options = {});
// localTransform: base frame -> camera optical frame (header.frame_id), from tf. The result has
// raw images, the camera model(s), the features, stamp = header stamp, id 0. Errors: no image,
// undecodable images, an invalid camera_info, image sizes that disagree with the camera_info
// or with each other, a second image that is neither depth nor a stereo right image, feature
// arrays of different lengths.
std::optional<rtabmap::SensorData> rgbdImageFromMsg(const rtabmap_ros::RGBDImage& msg,
                                                    const rtabmap::Transform& localTransform,
                                                    std::string* error = nullptr);

// One RGBDImage per camera model of `data` (RGB-D or stereo); headers[i] for camera i. For
// stereo, options.rightFrameId applies to every camera.
rtabmap_ros::RGBDImages rgbdImagesToMsg(const rtabmap::SensorData& data, const std_msgs::Header& header,
                                        const std::vector<std_msgs::Header>& cameraHeaders,
                                        const RGBDImageOptions& options = {});
// localTransforms[i]: base -> optical frame of camera i. Cameras must be all RGB-D or all
// stereo, with images of the same size and type (else the error says which camera differs);
// features are concatenated (keypoint x shifted by the camera's column offset).
std::optional<rtabmap::SensorData> rgbdImagesFromMsg(const rtabmap_ros::RGBDImages& msg,
                                                     const std::vector<rtabmap::Transform>& localTransforms,
                                                     std::string* error = nullptr);

}  // namespace rtabmap_conversions
