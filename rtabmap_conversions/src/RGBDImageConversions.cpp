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
  if (data.stereoCameraModels().size() > 1) {
    throw rtabmap::FormatError("rgbdImageToMsg: the frame has " + std::to_string(data.stereoCameraModels().size()) +
                               " stereo cameras; an RGBDImage holds one (use rgbdImagesToMsg)");
  } else if (stereo) {
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

namespace {

// Camera i's share (columns [i*w, (i+1)*w), w = width / n) of side-by-side images; empty stays
// empty.
cv::Mat cameraColumns(const cv::Mat& image, int i, int n) {
  return image.empty() ? cv::Mat() : image.colRange(i * image.cols / n, (i + 1) * image.cols / n).clone();
}

// The features of `data` in camera i's columns [i*width, (i+1)*width), in its own coordinates.
void setCameraFeatures(const rtabmap::SensorData& data, int i, float width, rtabmap::SensorData& part) {
  std::vector<cv::KeyPoint> kpts;
  std::vector<cv::Point3f> pts;
  cv::Mat descriptors;
  for (size_t k = 0; k < data.keypoints().size(); ++k) {
    cv::KeyPoint kp = data.keypoints()[k];
    if (kp.pt.x < i * width || kp.pt.x >= (i + 1) * width) continue;
    kp.pt.x -= i * width;
    kpts.push_back(kp);
    if (!data.keypoints3D().empty()) pts.push_back(data.keypoints3D()[k]);
    if (!data.descriptors().empty()) descriptors.push_back(data.descriptors().row(static_cast<int>(k)));
  }
  part.setFeatures(kpts, pts, descriptors);
}

}  // namespace

rtabmap_ros::RGBDImages rgbdImagesToMsg(const rtabmap::SensorData& data, const std_msgs::Header& header,
                                        const std::vector<std_msgs::Header>& cameraHeaders,
                                        const RGBDImageOptions& options) {
  const bool stereo = data.isStereo();
  const size_t cameras = stereo ? data.stereoCameraModels().size() : data.cameraModels().size();
  if (cameras == 0 || cameraHeaders.size() != cameras) {
    throw rtabmap::FormatError("rgbdImagesToMsg: expected cameras with one header each (" + std::to_string(cameras) +
                               (stereo ? " stereo" : "") + " cameras, " + std::to_string(cameraHeaders.size()) +
                               " headers)");
  }
  rtabmap::SensorData whole = data;
  whole.uncompress(true, true, false, false);
  const cv::Mat& image = whole.imageRaw();
  const cv::Mat& second = whole.depthOrRightRaw();
  const int n = static_cast<int>(cameras);
  rtabmap_ros::RGBDImages msg;
  msg.header = header;
  for (int i = 0; i < n; ++i) {
    rtabmap::SensorData part;
    const size_t c = static_cast<size_t>(i);
    const int modelWidth = stereo ? data.stereoCameraModels()[c].left().imageWidth() : data.cameraModels()[c].imageWidth();
    if (stereo) {
      part.setStereoImage(cameraColumns(image, i, n), cameraColumns(second, i, n), {data.stereoCameraModels()[c]});
    } else {
      part.setRGBDImage(cameraColumns(image, i, n), cameraColumns(second, i, n), {data.cameraModels()[c]});
    }
    // Features belong to the camera whose columns hold them.
    setCameraFeatures(data, i, image.empty() ? float(modelWidth) : float(image.cols / n), part);
    msg.rgbd_images.push_back(rgbdImageToMsg(part, cameraHeaders[c], options));
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
  std::vector<cv::Mat> images, seconds;
  std::vector<rtabmap::CameraModel> models;
  std::vector<rtabmap::StereoCameraModel> stereoModels;
  std::vector<cv::KeyPoint> kpts;
  std::vector<cv::Point3f> pts;
  cv::Mat descriptors;
  bool allPoints = true;
  for (size_t i = 0; i < msg.rgbd_images.size(); ++i) {
    std::optional<rtabmap::SensorData> part = rgbdImageFromMsg(msg.rgbd_images[i], localTransforms[i], error);
    if (!part) return std::nullopt;
    const std::string what = "RGBDImages camera " + std::to_string(i);
    if (i > 0 && part->isStereo() != !stereoModels.empty()) {
      // Side by side in one frame, the second images are all depth or all right images.
      const std::string kind = part->isStereo()                     ? "stereo"
                               : part->depthOrRightRaw().empty() ? "without depth or right image (depth and "
                                                                   "depth_compressed empty)"
                                                                 : "RGB-D";
      return detail::fail(error, what + " is " + kind + " but camera 0 is " + (stereoModels.empty() ? "RGB-D" : "stereo") +
                                     ": the cameras of an RGBDImages must be all RGB-D or all stereo");
    }
    if (!images.empty() && (part->imageRaw().size() != images[0].size() || part->imageRaw().type() != images[0].type() ||
                            part->depthOrRightRaw().size() != seconds[0].size() ||
                            part->depthOrRightRaw().type() != seconds[0].type())) {
      return detail::fail(error, what + " has images of another size or type than camera 0 (" +
                                     sizeString(part->imageRaw().size()) + " and " +
                                     sizeString(part->depthOrRightRaw().size()) + " vs " + sizeString(images[0].size()) +
                                     " and " + sizeString(seconds[0].size()) +
                                     "): side by side in one frame, every camera must have the same image size");
    }
    const float offset = static_cast<float>(i) * static_cast<float>(part->imageRaw().cols);
    for (cv::KeyPoint kp : part->keypoints()) {
      kp.pt.x += offset;
      kpts.push_back(kp);
    }
    allPoints = allPoints && part->keypoints3D().size() == part->keypoints().size();
    pts.insert(pts.end(), part->keypoints3D().begin(), part->keypoints3D().end());
    if (!part->descriptors().empty()) descriptors.push_back(part->descriptors());
    images.push_back(part->imageRaw());
    seconds.push_back(part->depthOrRightRaw());
    if (part->isStereo()) {
      stereoModels.push_back(part->stereoCameraModels().front());
    } else {
      models.push_back(part->cameraModels().front());
    }
  }
  cv::Mat image, second;
  cv::hconcat(images, image);
  if (!seconds[0].empty()) cv::hconcat(seconds, second);
  const double stamp = msg.header.stamp.toSec();
  rtabmap::SensorData data = stereoModels.empty() ? rtabmap::SensorData(image, second, models, 0, stamp)
                                                  : rtabmap::SensorData(image, second, stereoModels, 0, stamp);
  if (descriptors.rows != static_cast<int>(kpts.size())) descriptors = cv::Mat();
  data.setFeatures(kpts, allPoints ? pts : std::vector<cv::Point3f>(), descriptors);
  return data;
}

}  // namespace rtabmap_conversions
