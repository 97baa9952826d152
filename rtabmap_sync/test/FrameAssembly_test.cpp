// The sync nodelets' input checks and frame building: good sets give the right frame (sizes,
// camera model, decimation, depth scale); each kind of bad input is an error naming the topic.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include <boost/make_shared.hpp>

#include "rtabmap_conversions/RGBDImageConversions.h"
#include "rtabmap_sync/FrameAssembly.h"

namespace rtabmap_sync {
namespace {

constexpr int kW = 64, kH = 48;
constexpr double kFx = 50.0, kCx = 32.0, kCy = 24.0;

sensor_msgs::Image image(int w, int h, const std::string& encoding, int bytesPerPixel, double stamp = 1.0) {
  sensor_msgs::Image m;
  m.header.stamp.fromSec(stamp);
  m.header.frame_id = "camera_optical";
  m.width = uint32_t(w);
  m.height = uint32_t(h);
  m.encoding = encoding;
  m.step = uint32_t(w * bytesPerPixel);
  m.data.resize(size_t(m.step) * size_t(h));
  for (size_t i = 0; i < m.data.size(); ++i) m.data[i] = uint8_t(i % 251);
  return m;
}

// 16UC1 depth whose pixel (u, v) is 1000 + 100 v + u millimetres: each value names its pixel.
sensor_msgs::Image depth16(int w, int h) {
  sensor_msgs::Image m = image(w, h, "16UC1", 2);
  auto* d = reinterpret_cast<uint16_t*>(m.data.data());
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) d[v * w + u] = uint16_t(1000 + 100 * v + u);
  }
  return m;
}

sensor_msgs::CameraInfo info(int w = kW, int h = kH, double tx = 0.0) {
  sensor_msgs::CameraInfo m;
  m.header.frame_id = "camera_optical";
  m.width = uint32_t(w);
  m.height = uint32_t(h);
  m.K = {kFx, 0, kCx, 0, kFx, kCy, 0, 0, 1};
  m.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  m.P = {kFx, 0, kCx, tx, 0, kFx, kCy, 0, 0, 0, 1, 0};
  return m;
}

std::string rgbdError(const sensor_msgs::Image& rgb, const sensor_msgs::Image& depth,
                      const sensor_msgs::CameraInfo& camInfo, RgbdFrameOptions options = {}) {
  std::string error;
  EXPECT_FALSE(rgbdFrame(rgb, depth, camInfo, options, &error).has_value());
  return error;
}

TEST(FrameAssembly, RgbdFrameKeepsImagesModelAndStamp) {
  std::optional<rtabmap::SensorData> f = rgbdFrame(image(kW, kH, "bgr8", 3, 12.25), depth16(kW, kH), info());
  ASSERT_TRUE(f.has_value());
  EXPECT_DOUBLE_EQ(f->stamp(), 12.25);
  EXPECT_EQ(f->imageRaw().size(), cv::Size(kW, kH));
  EXPECT_EQ(f->imageRaw().type(), CV_8UC3);
  ASSERT_EQ(f->depthOrRightRaw().type(), CV_16UC1);
  EXPECT_EQ(f->depthOrRightRaw().at<uint16_t>(5, 7), 1000 + 500 + 7);
  ASSERT_EQ(f->cameraModels().size(), 1u);
  EXPECT_DOUBLE_EQ(f->cameraModels()[0].fx(), kFx);
  // The camera_info had no D: the frame still encodes (as rgbd_sync publishes it), with zeros.
  const rtabmap_ros::RGBDImage msg = rtabmap_conversions::rgbdImageToMsg(*f, std_msgs::Header());
  EXPECT_EQ(msg.rgb_camera_info.D, std::vector<double>(5, 0.0));
  EXPECT_DOUBLE_EQ(msg.rgb_camera_info.K[0], kFx);
}

TEST(FrameAssembly, DecimationShrinksImagesAndModelAndPicksDepthPixels) {
  RgbdFrameOptions o;
  o.decimation = 2;
  o.depthScale = 2.0;
  std::optional<rtabmap::SensorData> f = rgbdFrame(image(kW, kH, "mono8", 1), depth16(kW, kH), info(), o);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->imageRaw().size(), cv::Size(kW / 2, kH / 2));
  EXPECT_EQ(f->depthOrRightRaw().size(), cv::Size(kW / 2, kH / 2));
  EXPECT_DOUBLE_EQ(f->cameraModels()[0].fx(), kFx / 2);
  EXPECT_DOUBLE_EQ(f->cameraModels()[0].cx(), kCx / 2);
  EXPECT_EQ(f->cameraModels()[0].imageSize(), cv::Size(kW / 2, kH / 2));
  // Every decimated depth is one of the source pixels (nearest, no averaging), times 2.
  const cv::Mat& d = f->depthOrRightRaw();
  for (int v = 0; v < d.rows; ++v) {
    for (int u = 0; u < d.cols; ++u) {
      ASSERT_EQ(d.at<uint16_t>(v, u) % 2, 0);
      const int code = d.at<uint16_t>(v, u) / 2 - 1000;
      const int su = code % 100, sv = code / 100;
      ASSERT_TRUE(su == 2 * u || su == 2 * u + 1) << u << "," << v << " <- " << su;
      ASSERT_TRUE(sv == 2 * v || sv == 2 * v + 1) << u << "," << v << " <- " << sv;
    }
  }
}

TEST(FrameAssembly, DepthScaleOnMetres) {
  sensor_msgs::Image depth = image(kW, kH, "32FC1", 4);
  auto* p = reinterpret_cast<float*>(depth.data.data());
  for (int i = 0; i < kW * kH; ++i) p[i] = 1.5f;
  RgbdFrameOptions o;
  o.depthScale = 0.5;
  std::optional<rtabmap::SensorData> f = rgbdFrame(image(kW, kH, "rgb8", 3), depth, info(), o);
  ASSERT_TRUE(f.has_value());
  EXPECT_FLOAT_EQ(f->depthOrRightRaw().at<float>(10, 10), 0.75f);
}

TEST(FrameAssembly, BadRgbdInputNamesTheProblem) {
  const sensor_msgs::Image rgb = image(kW, kH, "bgr8", 3);
  const sensor_msgs::Image depth = depth16(kW, kH);
  sensor_msgs::Image empty = rgb;
  empty.data.clear();
  empty.width = empty.height = empty.step = 0;
  EXPECT_EQ(rgbdError(empty, depth, info()).rfind("rgb/image: ", 0), 0u);
  EXPECT_EQ(rgbdError(rgb, empty, info()).rfind("depth/image: ", 0), 0u);

  const std::string encoding = rgbdError(rgb, image(kW, kH, "8UC3", 3), info());
  EXPECT_EQ(encoding.rfind("depth/image: ", 0), 0u) << encoding;
  EXPECT_NE(encoding.find("8UC3"), std::string::npos) << encoding;
  EXPECT_EQ(rgbdError(image(kW, kH, "yuv422", 2), depth, info()).rfind("rgb/image: ", 0), 0u);

  sensor_msgs::CameraInfo zeroK = info();
  zeroK.K.fill(0.0);
  zeroK.P.fill(0.0);
  EXPECT_EQ(rgbdError(rgb, depth, zeroK).rfind("rgb/camera_info: ", 0), 0u);

  EXPECT_EQ(rgbdError(rgb, depth16(kW / 2, kH / 2), info()),
            "depth/image is 32x24 but rgb/image is 64x48 (depth must be registered to rgb, same size)");
  EXPECT_EQ(rgbdError(rgb, depth, info(kW * 2, kH * 2)), "rgb/image is 64x48 but rgb/camera_info says 128x96");
  RgbdFrameOptions o;
  o.decimation = 5;
  EXPECT_EQ(rgbdError(rgb, depth, info(), o), "decimation 5 does not divide the image size 64x48");
}

TEST(FrameAssembly, CameraInfoWithoutSizeTakesTheImageSize) {
  EXPECT_TRUE(rgbdFrame(image(kW, kH, "bgr8", 3), depth16(kW, kH), info(0, 0)).has_value());
}

TEST(FrameAssembly, StereoFrameHasBaselineAndGreyRight) {
  const double baseline = 0.12;
  std::optional<rtabmap::SensorData> f = stereoFrame(image(kW, kH, "bgr8", 3, 3.5), image(kW, kH, "bgr8", 3),
                                                     info(), info(kW, kH, -kFx * baseline));
  ASSERT_TRUE(f.has_value());
  ASSERT_TRUE(f->isStereo());
  EXPECT_DOUBLE_EQ(f->stamp(), 3.5);
  EXPECT_EQ(f->depthOrRightRaw().type(), CV_8UC1);
  EXPECT_NEAR(-f->stereoCameraModels()[0].right().Tx() / f->stereoCameraModels()[0].right().fx(), baseline, 1e-9);
  const rtabmap_ros::RGBDImage msg = rtabmap_conversions::rgbdImageToMsg(*f, std_msgs::Header());
  EXPECT_NEAR(-msg.depth_camera_info.P[3] / msg.depth_camera_info.P[0], baseline, 1e-9);
}

TEST(FrameAssembly, BadStereoInputNamesTheProblem) {
  std::string error;
  const sensor_msgs::Image left = image(kW, kH, "mono8", 1);
  EXPECT_FALSE(stereoFrame(left, left, info(), info(), &error).has_value());  // Tx = 0: no baseline
  EXPECT_EQ(error.rfind("left/right camera_info: ", 0), 0u) << error;
  EXPECT_FALSE(stereoFrame(left, image(kW / 2, kH / 2, "mono8", 1), info(), info(kW, kH, -6.0), &error));
  EXPECT_NE(error.find("32x24 (right)"), std::string::npos) << error;
  EXPECT_FALSE(stereoFrame(left, image(kW, kH, "16UC1", 2), info(), info(kW, kH, -6.0), &error));
  EXPECT_EQ(error.rfind("right/image_rect: ", 0), 0u) << error;
}

TEST(FrameAssembly, RgbdImageCheck) {
  rtabmap_ros::RGBDImage msg;
  std::string error;
  EXPECT_FALSE(checkRgbdImage(msg, &error));
  EXPECT_NE(error.find("no image"), std::string::npos) << error;
  msg.rgb = image(kW, kH, "bgr8", 3);
  msg.rgb_camera_info = info(0, 0);  // size from the raw image
  EXPECT_TRUE(checkRgbdImage(msg, &error)) << error;
  msg.rgb_camera_info.K.fill(0.0);
  msg.rgb_camera_info.P.fill(0.0);
  EXPECT_FALSE(checkRgbdImage(msg, &error));
  EXPECT_EQ(error.rfind("rgb_camera_info: ", 0), 0u) << error;
}

// What stereo_sync publishes for one camera: rgb = left, depth = right (mono8), the right info
// with Tx = -fx * baseline.
rtabmap_ros::RGBDImage stereoRgbdImage(const std::string& frame, double baseline, double stamp) {
  rtabmap_ros::RGBDImage msg;
  msg.header.frame_id = frame;
  msg.header.stamp.fromSec(stamp);
  msg.rgb = image(kW, kH, "bgr8", 3, stamp);
  msg.depth = image(kW, kH, "mono8", 1, stamp);
  msg.rgb_camera_info = info();
  msg.depth_camera_info = info(kW, kH, -kFx * baseline);
  return msg;
}

TEST(FrameAssembly, SeveralStereoCamerasBecomeOneFrameSideBySide) {
  // rgbdx_sync's bundle of two stereo cameras (rgbd_cameras 0), then the same two cameras
  // synchronised separately (rgbd_cameras 2): one frame, left images side by side, right images
  // side by side, each camera placed by its own tf.
  const rtabmap::Transform front = rtabmap::Transform(0.1, 0, 1.0, 0, 0, 0) * rtabmap::CameraModel::opticalRotation();
  const rtabmap::Transform left = rtabmap::Transform(0, 0.1, 1.0, 0, 0, M_PI / 2) * rtabmap::CameraModel::opticalRotation();
  const SensorPoseFn pose = [&](const std::string& frame, const ros::Time&, std::string* error) {
    if (frame == "front_optical") return front;
    if (frame == "left_optical") return left;
    if (error) *error = "no tf to " + frame;
    return rtabmap::Transform();
  };
  auto bundle = boost::make_shared<rtabmap_ros::RGBDImages>();
  bundle->header.stamp.fromSec(4.0);
  bundle->rgbd_images = {stereoRgbdImage("front_optical", 0.12, 4.0), stereoRgbdImage("left_optical", 0.2, 4.0)};
  std::vector<rtabmap_ros::RGBDImageConstPtr> separate = {
      boost::make_shared<rtabmap_ros::RGBDImage>(bundle->rgbd_images[0]),
      boost::make_shared<rtabmap_ros::RGBDImage>(bundle->rgbd_images[1])};
  for (bool bundled : {true, false}) {
    SCOPED_TRACE(bundled ? "bundle" : "separate");
    std::string error;
    const std::optional<rtabmap::SensorData> f =
        rgbdCamerasFrame(bundled ? bundle : nullptr, bundled ? std::vector<rtabmap_ros::RGBDImageConstPtr>() : separate,
                         pose, &error);
    ASSERT_TRUE(f.has_value()) << error;
    ASSERT_TRUE(f->isStereo());
    ASSERT_EQ(f->stereoCameraModels().size(), 2u);
    EXPECT_EQ(f->imageRaw().size(), cv::Size(2 * kW, kH));
    EXPECT_EQ(f->depthOrRightRaw().size(), cv::Size(2 * kW, kH));
    EXPECT_EQ(f->depthOrRightRaw().type(), CV_8UC1);
    EXPECT_EQ(f->stereoCameraModels()[0].localTransform(), front);
    EXPECT_EQ(f->stereoCameraModels()[1].localTransform(), left);
    EXPECT_NEAR(f->stereoCameraModels()[0].baseline(), 0.12, 1e-9);
    EXPECT_NEAR(f->stereoCameraModels()[1].baseline(), 0.2, 1e-9);
    EXPECT_DOUBLE_EQ(f->stamp(), 4.0);
  }
  // A camera whose tf is missing is named.
  bundle->rgbd_images[1].header.frame_id = "rear_optical";
  std::string error;
  EXPECT_FALSE(rgbdCamerasFrame(bundle, {}, pose, &error).has_value());
  EXPECT_NE(error.find("rear_optical"), std::string::npos) << error;
  // Images of another size cannot sit side by side.
  bundle->rgbd_images[1] = stereoRgbdImage("left_optical", 0.2, 4.0);
  bundle->rgbd_images[1].depth = image(kW / 2, kH / 2, "mono8", 1);
  bundle->rgbd_images[1].rgb = image(kW / 2, kH / 2, "bgr8", 3);
  bundle->rgbd_images[1].rgb_camera_info = info(kW / 2, kH / 2);
  bundle->rgbd_images[1].depth_camera_info = info(kW / 2, kH / 2, -kFx * 0.2);
  EXPECT_FALSE(rgbdCamerasFrame(bundle, {}, pose, &error).has_value());
  EXPECT_NE(error.find("camera 1 has images of another size"), std::string::npos) << error;
}

}  // namespace
}  // namespace rtabmap_sync
