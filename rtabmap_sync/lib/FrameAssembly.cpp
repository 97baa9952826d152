#include "rtabmap_sync/FrameAssembly.h"

#include <opencv2/imgproc.hpp>

#include "rtabmap_conversions/CameraInfoConversions.h"
#include "rtabmap_conversions/ImageConversions.h"
#include "rtabmap_conversions/LaserScanConversions.h"
#include "rtabmap_conversions/PointCloudConversions.h"
#include "rtabmap_conversions/RGBDImageConversions.h"

namespace rtabmap_sync {

namespace {

std::nullopt_t fail(std::string* error, const std::string& why) {
  if (error) *error = why;
  return std::nullopt;
}

std::string sizeString(const cv::Size& s) { return std::to_string(s.width) + "x" + std::to_string(s.height); }

// Some drivers leave the camera_info size at 0; it is then the size of its image. An empty D
// (no distortion) is spelled out as plumb_bob zeros: the output camera_info then has the D
// its distortion model says, and rtabmap_conversions' cameraModelToMsg cannot copy an empty
// D matrix (it crashes with SIGFPE in cv::MatConstIterator).
sensor_msgs::CameraInfo completed(sensor_msgs::CameraInfo info, const cv::Mat& image) {
  if (info.width == 0 || info.height == 0) {
    info.width = uint32_t(image.cols);
    info.height = uint32_t(image.rows);
  }
  if (info.D.empty()) {
    info.distortion_model = "plumb_bob";
    info.D.assign(5, 0.0);
  }
  return info;
}

// Nearest neighbour for depth: averaging across an object boundary would invent depths that
// exist on neither surface.
cv::Mat decimate(const cv::Mat& image, int d, bool depth) {
  cv::Mat out;
  cv::resize(image, out, cv::Size(image.cols / d, image.rows / d), 0, 0, depth ? cv::INTER_NEAREST : cv::INTER_AREA);
  return out;
}

cv::Mat scaleDepth(const cv::Mat& depth, double scale) {
  cv::Mat out;
  depth.convertTo(out, depth.type(), scale);  // 16UC1 saturates at 65535 mm
  return out;
}

}  // namespace

std::optional<rtabmap::SensorData> rgbdFrame(const sensor_msgs::Image& rgbMsg, const sensor_msgs::Image& depthMsg,
                                             const sensor_msgs::CameraInfo& info, const RgbdFrameOptions& options,
                                             std::string* error) {
  std::string why;
  std::optional<cv::Mat> rgb = rtabmap_conversions::colorFromMsg(rgbMsg, &why);
  if (!rgb) return fail(error, "rgb/image: " + why);
  std::optional<cv::Mat> depth = rtabmap_conversions::depthFromMsg(depthMsg, &why);
  if (!depth) return fail(error, "depth/image: " + why);
  std::optional<rtabmap::CameraModel> model =
      rtabmap_conversions::cameraModelFromMsg(completed(info, *rgb), rtabmap::CameraModel::opticalRotation(), &why);
  if (!model) return fail(error, "rgb/camera_info: " + why);
  if (rgb->size() != model->imageSize()) {
    return fail(error, "rgb/image is " + sizeString(rgb->size()) + " but rgb/camera_info says " +
                           sizeString(model->imageSize()));
  }
  if (depth->size() != rgb->size()) {
    return fail(error, "depth/image is " + sizeString(depth->size()) + " but rgb/image is " + sizeString(rgb->size()) +
                           " (depth must be registered to rgb, same size)");
  }
  const int d = options.decimation;
  if (d < 1 || rgb->cols % d != 0 || rgb->rows % d != 0) {
    return fail(error, "decimation " + std::to_string(d) + " does not divide the image size " + sizeString(rgb->size()));
  }
  cv::Mat outRgb = d > 1 ? decimate(*rgb, d, false) : *rgb;
  cv::Mat outDepth = d > 1 ? decimate(*depth, d, true) : *depth;
  if (options.depthScale != 1.0) outDepth = scaleDepth(outDepth, options.depthScale);
  const rtabmap::CameraModel outModel = d > 1 ? model->scaled(1.0 / d) : *model;
  return rtabmap::SensorData(outRgb, outDepth, outModel, 0, rgbMsg.header.stamp.toSec());
}

std::optional<rtabmap::SensorData> stereoFrame(const sensor_msgs::Image& leftMsg, const sensor_msgs::Image& rightMsg,
                                               const sensor_msgs::CameraInfo& leftInfo,
                                               const sensor_msgs::CameraInfo& rightInfo, std::string* error) {
  std::string why;
  std::optional<cv::Mat> left = rtabmap_conversions::colorFromMsg(leftMsg, &why);
  if (!left) return fail(error, "left/image_rect: " + why);
  std::optional<cv::Mat> right = rtabmap_conversions::colorFromMsg(rightMsg, &why);
  if (!right) return fail(error, "right/image_rect: " + why);
  if (right->channels() != 1) {
    cv::Mat grey;
    cv::cvtColor(*right, grey, right->channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
    right = grey;
  }
  std::optional<rtabmap::StereoCameraModel> model = rtabmap_conversions::stereoModelFromMsgs(
      completed(leftInfo, *left), completed(rightInfo, *right), rtabmap::CameraModel::opticalRotation(), &why);
  if (!model) return fail(error, "left/right camera_info: " + why);
  const cv::Size expected = model->left().imageSize();
  if (left->size() != expected || right->size() != expected) {
    return fail(error, "stereo images are " + sizeString(left->size()) + " (left) and " + sizeString(right->size()) +
                           " (right) but the camera_infos say " + sizeString(expected));
  }
  return rtabmap::SensorData(*left, *right, *model, 0, leftMsg.header.stamp.toSec());
}

bool checkRgbdImage(const rtabmap_ros::RGBDImage& msg, std::string* error) {
  if (msg.rgb.data.empty() && msg.rgb_compressed.data.empty()) {
    fail(error, "no image (rgb and rgb_compressed are empty)");
    return false;
  }
  sensor_msgs::CameraInfo info = msg.rgb_camera_info;
  if ((info.width == 0 || info.height == 0) && !msg.rgb.data.empty()) {
    info.width = msg.rgb.width;
    info.height = msg.rgb.height;
  }
  std::string why;
  if (!rtabmap_conversions::cameraModelFromMsg(info, rtabmap::CameraModel::opticalRotation(), &why)) {
    fail(error, "rgb_camera_info: " + why);
    return false;
  }
  return true;
}

std::optional<rtabmap::LaserScan> syncedScan(const sensor_msgs::LaserScanConstPtr& scan,
                                             const sensor_msgs::PointCloud2ConstPtr& cloud,
                                             const rtabmap::Transform& local, std::string* error) {
  std::string why;
  std::optional<rtabmap::LaserScan> out = scan ? rtabmap_conversions::laserScanFromMsg(*scan, local, &why)
                                               : rtabmap_conversions::laserScanFromCloudMsg(*cloud, local, &why);
  if (!out && error) *error = std::string(scan ? "scan" : "scan_cloud") + ": " + why;
  return out;
}

std::optional<rtabmap::SensorData> rgbdCamerasFrame(const rtabmap_ros::RGBDImagesConstPtr& bundle,
                                                    const std::vector<rtabmap_ros::RGBDImageConstPtr>& images,
                                                    const SensorPoseFn& sensorPose, std::string* error) {
  rtabmap_ros::RGBDImages cameras;
  if (bundle) {
    cameras = *bundle;
  } else {
    if (images.empty()) return fail(error, "no RGB-D camera in the synchronised set");
    cameras.header = images.front()->header;
    for (const auto& m : images) cameras.rgbd_images.push_back(*m);
  }
  std::vector<rtabmap::Transform> locals;
  for (const rtabmap_ros::RGBDImage& image : cameras.rgbd_images) {
    locals.push_back(sensorPose(image.header.frame_id, image.header.stamp, error));
    if (locals.back().isNull()) return std::nullopt;
  }
  std::string why;
  std::optional<rtabmap::SensorData> frame = rtabmap_conversions::rgbdImagesFromMsg(cameras, locals, &why);
  if (!frame && error) *error = "rgbd_images: " + why;
  return frame;
}

}  // namespace rtabmap_sync
