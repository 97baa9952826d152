#include "rtabmap_conversions/RGBDImageConversions.h"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "Support.h"
#include "rtabmap_conversions/CameraInfoConversions.h"
#include "rtabmap_conversions/CompressedImageConversions.h"
#include "rtabmap_conversions/FeatureConversions.h"
#include "rtabmap_conversions/ImageConversions.h"
#include "rtabmap_core/codec/Compression.h"
#include "rtabmap_core/common/Error.h"

namespace rtabmap_conversions {

namespace {

bool isDepthType(int type) { return type == CV_16UC1 || type == CV_32FC1; }

std::string sizeString(const cv::Size& s) { return std::to_string(s.width) + "x" + std::to_string(s.height); }

// The raw image of a message part, or the decoded compressed one; an empty Mat when the part is
// absent. Returns false (and *error) when a present part cannot be decoded.
bool decodePart(const sensor_msgs::Image& raw, const sensor_msgs::CompressedImage& compressed, const char* name,
                cv::Mat& out, std::string* error) {
  std::string why;
  std::optional<cv::Mat> image;
  if (!raw.data.empty()) {
    image = imageFromMsg(raw, &why);
  } else if (!compressed.data.empty()) {
    image = compressedImageFromMsg(compressed, &why);
  } else {
    out = cv::Mat();
    return true;
  }
  if (!image) {
    detail::fail(error, std::string("RGBDImage ") + name + ": " + why);
    return false;
  }
  out = *image;
  return true;
}

// A camera_info without an image size (some drivers) takes the size of the image it came with.
sensor_msgs::CameraInfo withSize(sensor_msgs::CameraInfo info, const cv::Mat& image) {
  if ((info.width == 0 || info.height == 0) && !image.empty()) {
    info.width = static_cast<uint32_t>(image.cols);
    info.height = static_cast<uint32_t>(image.rows);
  }
  return info;
}

sensor_msgs::CompressedImage compressRaw(const cv::Mat& image, const std_msgs::Header& header, bool depth,
                                         const std::string& format) {
  if (depth) return compressedDepthLosslessToMsg(image, header);
  const bool jpegOk = image.type() == CV_8UC1 || image.type() == CV_8UC3;
  return compressedImageToMsg(image, header, jpegOk ? format : "png");
}

}  // namespace

rtabmap_ros::RGBDImage rgbdImageToMsg(const rtabmap::SensorData& data, const std_msgs::Header& header,
                                      const RGBDImageOptions& options) {
  rtabmap_ros::RGBDImage msg;
  msg.header = header;
  std_msgs::Header rightHeader = header;
  if (!options.rightFrameId.empty()) rightHeader.frame_id = options.rightFrameId;
  const bool stereo = data.isStereo();
  if (stereo) {
    stereoModelToMsgs(data.stereoCameraModels().front(), header, rightHeader, msg.rgb_camera_info,
                      msg.depth_camera_info);
  } else if (data.cameraModels().size() == 1) {
    msg.rgb_camera_info = cameraModelToMsg(data.cameraModels().front(), header);
    msg.depth_camera_info = msg.rgb_camera_info;
  } else {
    throw rtabmap::FormatError("rgbdImageToMsg: the frame has " + std::to_string(data.cameraModels().size()) +
                               " cameras; an RGBDImage holds one (use rgbdImagesToMsg)");
  }
  const std_msgs::Header& secondHeader = stereo ? rightHeader : header;
  const bool secondIsDepth = !stereo;
  if (options.compressed) {
    // Already compressed bytes are passed through: no decode / re-encode, no extra jpeg loss.
    if (!data.imageCompressed().empty()) {
      msg.rgb_compressed = compressedBytesToMsg(data.imageCompressed(), header, false);
    } else if (!data.imageRaw().empty()) {
      msg.rgb_compressed = compressRaw(data.imageRaw(), header, false, options.imageFormat);
    }
    if (!data.depthOrRightCompressed().empty()) {
      msg.depth_compressed = compressedBytesToMsg(data.depthOrRightCompressed(), secondHeader, secondIsDepth);
    } else if (!data.depthOrRightRaw().empty()) {
      // The right image of a pair stays lossless: jpeg blocks would bias every disparity.
      msg.depth_compressed = compressRaw(data.depthOrRightRaw(), secondHeader, secondIsDepth, "png");
    }
  } else {
    cv::Mat rgb = data.imageRaw();
    cv::Mat second = data.depthOrRightRaw();
    if (rgb.empty() && !data.imageCompressed().empty()) rgb = rtabmap::codec::uncompressAny(data.imageCompressed());
    if (second.empty() && !data.depthOrRightCompressed().empty()) {
      second = secondIsDepth ? rtabmap::codec::uncompressDepth(data.depthOrRightCompressed())
                             : rtabmap::codec::uncompressAny(data.depthOrRightCompressed());
    }
    if (!rgb.empty()) msg.rgb = imageToMsg(rgb, header);
    if (!second.empty()) msg.depth = imageToMsg(second, secondHeader);
  }
  msg.key_points = keypointsToMsg(data.keypoints());
  msg.points = pointsToMsg(data.keypoints3D());
  msg.descriptors = descriptorsToMsg(data.descriptors());
  return msg;
}

std::optional<rtabmap::SensorData> rgbdImageFromMsg(const rtabmap_ros::RGBDImage& msg,
                                                    const rtabmap::Transform& localTransform, std::string* error) {
  cv::Mat rgb, second;
  if (!decodePart(msg.rgb, msg.rgb_compressed, "rgb", rgb, error)) return std::nullopt;
  if (!decodePart(msg.depth, msg.depth_compressed, "depth", second, error)) return std::nullopt;
  const std::string what = "RGBDImage of frame '" + msg.header.frame_id + "'";
  if (rgb.empty()) return detail::fail(error, what + " has no rgb image (neither rgb nor rgb_compressed)");
  if (isDepthType(rgb.type())) {
    return detail::fail(error, what + ": the rgb image holds depth (type " + std::to_string(rgb.type()) + ")");
  }
  const double rightTx = msg.depth_camera_info.P[3];
  const bool secondIsDepth = !second.empty() && isDepthType(second.type());
  const bool stereo = !second.empty() && !secondIsDepth && rightTx < 0.0;
  if (!second.empty() && !secondIsDepth && !stereo) {
    return detail::fail(error, what + ": the depth image is not a depth image (16UC1 or 32FC1), and the "
                                      "depth_camera_info has no stereo baseline (Tx = P[3] = " +
                                   std::to_string(rightTx) + ", expected < 0 for a right camera)");
  }
  rtabmap::SensorData data;
  try {
    if (stereo) {
      std::optional<rtabmap::StereoCameraModel> model =
          stereoModelFromMsgs(withSize(msg.rgb_camera_info, rgb), withSize(msg.depth_camera_info, second),
                              localTransform, error);
      if (!model) return std::nullopt;
      if (rgb.size() != model->left().imageSize() || second.size() != rgb.size()) {
        return detail::fail(error, what + ": stereo images " + sizeString(rgb.size()) + " and " +
                                       sizeString(second.size()) + " do not match the camera_info size " +
                                       sizeString(model->left().imageSize()));
      }
      cv::Mat right = second;
      if (right.channels() != 1) cv::cvtColor(second, right, second.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
      data = rtabmap::SensorData(rgb, right, *model, 0, msg.header.stamp.toSec());
    } else {
      std::optional<rtabmap::CameraModel> model =
          cameraModelFromMsg(withSize(msg.rgb_camera_info, rgb), localTransform, error);
      if (!model) return std::nullopt;
      if (rgb.size() != model->imageSize()) {
        return detail::fail(error, what + ": rgb image is " + sizeString(rgb.size()) + " but its camera_info says " +
                                       sizeString(model->imageSize()));
      }
      // Registered depth may be decimated (e.g. 320x240 for a 640x480 colour image), by the
      // same integer factor in both directions; anything else cannot be registered.
      if (!second.empty() && (rgb.cols % second.cols != 0 || rgb.rows % second.rows != 0 ||
                              rgb.cols / second.cols != rgb.rows / second.rows)) {
        return detail::fail(error, what + ": depth image " + sizeString(second.size()) +
                                       " is not the rgb image size " + sizeString(rgb.size()) +
                                       " divided by an integer factor");
      }
      data = rtabmap::SensorData(rgb, second, *model, 0, msg.header.stamp.toSec());
    }
  } catch (const std::exception& e) {
    return detail::fail(error, what + ": " + e.what());
  }
  if (!msg.key_points.empty() || !msg.points.empty() || !msg.descriptors.empty()) {
    const std::vector<cv::KeyPoint> kpts = keypointsFromMsg(msg.key_points);
    if (!msg.points.empty() && msg.points.size() != kpts.size()) {
      return detail::fail(error, what + ": " + std::to_string(msg.points.size()) + " 3D points for " +
                                     std::to_string(kpts.size()) + " key points");
    }
    std::string why;
    std::optional<cv::Mat> descriptors = descriptorsFromMsg(msg.descriptors, static_cast<int>(kpts.size()), &why);
    if (!descriptors) return detail::fail(error, what + ": " + why);
    data.setFeatures(kpts, pointsFromMsg(msg.points), *descriptors);
  }
  return data;
}

rtabmap_ros::RGBDImages rgbdImagesToMsg(const rtabmap::SensorData& data, const std_msgs::Header& header,
                                        const std::vector<std_msgs::Header>& cameraHeaders,
                                        const RGBDImageOptions& options) {
  const std::vector<rtabmap::CameraModel>& models = data.cameraModels();
  if (models.empty() || data.isStereo() || cameraHeaders.size() != models.size()) {
    throw rtabmap::FormatError("rgbdImagesToMsg: expected RGB-D cameras with one header each (" +
                               std::to_string(models.size()) + " cameras, " +
                               std::to_string(cameraHeaders.size()) + " headers)");
  }
  rtabmap::SensorData whole = data;
  whole.uncompress(true, true, false, false);
  const cv::Mat& rgb = whole.imageRaw();
  const cv::Mat& depth = whole.depthOrRightRaw();
  const int n = static_cast<int>(models.size());
  rtabmap_ros::RGBDImages msg;
  msg.header = header;
  for (int i = 0; i < n; ++i) {
    rtabmap::SensorData part;
    const cv::Mat rgbPart = rgb.empty() ? cv::Mat() : rgb.colRange(i * rgb.cols / n, (i + 1) * rgb.cols / n).clone();
    const cv::Mat depthPart =
        depth.empty() ? cv::Mat() : depth.colRange(i * depth.cols / n, (i + 1) * depth.cols / n).clone();
    part.setRGBDImage(rgbPart, depthPart, {models[size_t(i)]});
    // Features belong to the camera whose columns hold them.
    std::vector<cv::KeyPoint> kpts;
    std::vector<cv::Point3f> pts;
    std::vector<int> rows;
    const float width = rgb.empty() ? float(models[size_t(i)].imageWidth()) : float(rgb.cols / n);
    for (size_t k = 0; k < data.keypoints().size(); ++k) {
      cv::KeyPoint kp = data.keypoints()[k];
      if (kp.pt.x < i * width || kp.pt.x >= (i + 1) * width) continue;
      kp.pt.x -= i * width;
      kpts.push_back(kp);
      if (!data.keypoints3D().empty()) pts.push_back(data.keypoints3D()[k]);
      rows.push_back(static_cast<int>(k));
    }
    cv::Mat descriptors;
    if (!data.descriptors().empty()) {
      for (int r : rows) descriptors.push_back(data.descriptors().row(r));
    }
    part.setFeatures(kpts, pts, descriptors);
    msg.rgbd_images.push_back(rgbdImageToMsg(part, cameraHeaders[size_t(i)], options));
  }
  return msg;
}

std::optional<rtabmap::SensorData> rgbdImagesFromMsg(const rtabmap_ros::RGBDImages& msg,
                                                     const std::vector<rtabmap::Transform>& localTransforms,
                                                     std::string* error) {
  if (msg.rgbd_images.empty()) return detail::fail(error, "RGBDImages has no cameras");
  if (localTransforms.size() != msg.rgbd_images.size()) {
    return detail::fail(error, "RGBDImages has " + std::to_string(msg.rgbd_images.size()) + " cameras but " +
                                   std::to_string(localTransforms.size()) + " local transforms were given");
  }
  std::vector<cv::Mat> rgbs, depths;
  std::vector<rtabmap::CameraModel> models;
  std::vector<cv::KeyPoint> kpts;
  std::vector<cv::Point3f> pts;
  cv::Mat descriptors;
  bool allPoints = true;
  for (size_t i = 0; i < msg.rgbd_images.size(); ++i) {
    std::optional<rtabmap::SensorData> part = rgbdImageFromMsg(msg.rgbd_images[i], localTransforms[i], error);
    if (!part) return std::nullopt;
    const std::string what = "RGBDImages camera " + std::to_string(i);
    if (part->isStereo()) return detail::fail(error, what + " is stereo; RGBDImages takes RGB-D cameras");
    if (!rgbs.empty() && (part->imageRaw().size() != rgbs[0].size() || part->imageRaw().type() != rgbs[0].type() ||
                          part->depthOrRightRaw().size() != depths[0].size() ||
                          part->depthOrRightRaw().type() != depths[0].type())) {
      return detail::fail(error, what + " has images of another size or type than camera 0");
    }
    const float offset = static_cast<float>(i) * static_cast<float>(part->imageRaw().cols);
    for (cv::KeyPoint kp : part->keypoints()) {
      kp.pt.x += offset;
      kpts.push_back(kp);
    }
    allPoints = allPoints && part->keypoints3D().size() == part->keypoints().size();
    pts.insert(pts.end(), part->keypoints3D().begin(), part->keypoints3D().end());
    if (!part->descriptors().empty()) descriptors.push_back(part->descriptors());
    rgbs.push_back(part->imageRaw());
    depths.push_back(part->depthOrRightRaw());
    models.push_back(part->cameraModels().front());
  }
  cv::Mat rgb, depth;
  cv::hconcat(rgbs, rgb);
  if (!depths[0].empty()) cv::hconcat(depths, depth);
  rtabmap::SensorData data(rgb, depth, models, 0, msg.header.stamp.toSec());
  if (descriptors.rows != static_cast<int>(kpts.size())) descriptors = cv::Mat();
  data.setFeatures(kpts, allPoints ? pts : std::vector<cv::Point3f>(), descriptors);
  return data;
}

}  // namespace rtabmap_conversions
