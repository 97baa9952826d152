#include "rtabmap_conversions/RGBDImageConversions.h"

#include <gtest/gtest.h>

#include <limits>

#include "TestHelpers.h"
#include "rtabmap_conversions/CameraInfoConversions.h"
#include "rtabmap_conversions/ImageConversions.h"
#include "rtabmap_core/codec/Compression.h"
#include "rtabmap_core/common/Error.h"

using namespace rtabmap_conversions;
using rtabmap::CameraModel;
using rtabmap::SensorData;
using rtabmap::Transform;
using rtabmap_conversions::test::randomImage;
using rtabmap_conversions::test::sameBits;
using rtabmap_conversions::test::smoothImage;

namespace {

const Transform kLocal(0.1, 0.0, 0.5, -M_PI / 2, 0.0, -M_PI / 2);

std_msgs::Header header(const std::string& frame = "camera_rgb_optical_frame") {
  std_msgs::Header h;
  h.frame_id = frame;
  h.stamp = ros::Time(77, 250000000);
  return h;
}

CameraModel model(int w = 64, int h = 48) { return CameraModel(50.0, 50.0, w / 2.0, h / 2.0, kLocal, 0.0, cv::Size(w, h)); }

SensorData rgbdFrame(int depthType) {
  cv::Mat depth = randomImage(48, 64, depthType, 3);
  if (depthType == CV_32FC1) depth.at<float>(1, 1) = std::numeric_limits<float>::quiet_NaN();
  return SensorData(smoothImage(48, 64, 3), depth, model(), 5, 77.25);
}

void addFeatures(SensorData& data, int n) {
  std::vector<cv::KeyPoint> kpts;
  std::vector<cv::Point3f> pts;
  for (int i = 0; i < n; ++i) {
    kpts.emplace_back(float(i * 3 % 64), float(i * 5 % 48), 7.0f, 45.0f * i, 0.01f * i, i % 4, i);
    pts.emplace_back(0.1f * i, -0.2f * i, 1.0f + i);
  }
  data.setFeatures(kpts, pts, randomImage(n, 32, CV_8UC1, 9));
}

SensorData decode(const rtabmap_ros::RGBDImage& msg, const Transform& local = kLocal) {
  std::string error;
  std::optional<SensorData> data = rgbdImageFromMsg(msg, local, &error);
  EXPECT_TRUE(data) << error;
  return data ? *data : SensorData();
}

}  // namespace

TEST(RGBDImageConversions, RawRgbdRoundTripsBitExactlyWithFeatures) {
  for (int depthType : {CV_16UC1, CV_32FC1}) {
    SensorData data = rgbdFrame(depthType);
    addFeatures(data, 20);
    const rtabmap_ros::RGBDImage msg = rgbdImageToMsg(data, header());
    EXPECT_EQ(msg.rgb.encoding, "bgr8");
    EXPECT_EQ(msg.depth.encoding, depthType == CV_16UC1 ? "16UC1" : "32FC1");
    EXPECT_TRUE(msg.rgb_compressed.data.empty());
    EXPECT_EQ(msg.rgb_camera_info.header.frame_id, "camera_rgb_optical_frame");
    const SensorData back = decode(msg);
    EXPECT_TRUE(sameBits(back.imageRaw(), data.imageRaw()));
    EXPECT_TRUE(sameBits(back.depthOrRightRaw(), data.depthOrRightRaw()));
    EXPECT_DOUBLE_EQ(back.stamp(), 77.25);
    ASSERT_EQ(back.cameraModels().size(), 1u);
    EXPECT_EQ(back.cameraModels()[0].localTransform(), kLocal);
    EXPECT_DOUBLE_EQ(back.cameraModels()[0].fx(), 50.0);
    ASSERT_EQ(back.keypoints().size(), 20u);
    EXPECT_EQ(back.keypoints()[7].pt, data.keypoints()[7].pt);
    EXPECT_EQ(back.keypoints()[7].octave, data.keypoints()[7].octave);
    EXPECT_EQ(back.keypoints()[7].class_id, 7);
    EXPECT_EQ(back.keypoints3D()[19], data.keypoints3D()[19]);
    EXPECT_TRUE(sameBits(back.descriptors(), data.descriptors()));
  }
}

TEST(RGBDImageConversions, CompressedRgbdKeepsDepthLossless) {
  for (int depthType : {CV_16UC1, CV_32FC1}) {
    const SensorData data = rgbdFrame(depthType);
    RGBDImageOptions options;
    options.compressed = true;
    const rtabmap_ros::RGBDImage msg = rgbdImageToMsg(data, header(), options);
    EXPECT_TRUE(msg.rgb.data.empty());
    EXPECT_EQ(msg.rgb_compressed.format, "bgr8; jpeg compressed bgr8");
    const SensorData back = decode(msg);
    EXPECT_LT(cv::norm(back.imageRaw(), data.imageRaw(), cv::NORM_L1) / double(data.imageRaw().total() * 3), 3.0);
    EXPECT_TRUE(sameBits(back.depthOrRightRaw(), data.depthOrRightRaw())) << "depth type " << depthType;
  }
}

TEST(RGBDImageConversions, AlreadyCompressedBytesArePassedThrough) {
  SensorData data = rgbdFrame(CV_16UC1);
  data.compress(".jpg");
  const rtabmap::Bytes jpeg = data.imageCompressed();
  data.clearRaw();
  RGBDImageOptions options;
  options.compressed = true;
  const rtabmap_ros::RGBDImage msg = rgbdImageToMsg(data, header(), options);
  EXPECT_EQ(msg.rgb_compressed.data, jpeg);  // no decode / re-encode
  const SensorData back = decode(msg);
  EXPECT_TRUE(sameBits(back.imageRaw(), rtabmap::codec::uncompressImage(jpeg)));
  EXPECT_TRUE(sameBits(back.depthOrRightRaw(), rgbdFrame(CV_16UC1).depthOrRightRaw()));

  // Raw output from compressed-only data decodes it.
  const rtabmap_ros::RGBDImage raw = rgbdImageToMsg(data, header());
  EXPECT_EQ(raw.depth.encoding, "16UC1");
  EXPECT_TRUE(sameBits(decode(raw).depthOrRightRaw(), rgbdFrame(CV_16UC1).depthOrRightRaw()));
}

TEST(RGBDImageConversions, StereoRoundTripsRawAndCompressed) {
  const rtabmap::StereoCameraModel stereo(60.0, 60.0, 32.0, 24.0, 0.12, kLocal, cv::Size(64, 48));
  const SensorData data(smoothImage(48, 64, 1), randomImage(48, 64, CV_8UC1, 4), stereo, 1, 3.5);
  RGBDImageOptions options;
  options.rightFrameId = "right_optical";
  for (bool compressed : {false, true}) {
    options.compressed = compressed;
    const rtabmap_ros::RGBDImage msg = rgbdImageToMsg(data, header("left_optical"), options);
    EXPECT_EQ(msg.depth_camera_info.header.frame_id, "right_optical");
    EXPECT_LT(msg.depth_camera_info.P[3], 0.0);
    const SensorData back = decode(msg);
    ASSERT_TRUE(back.isStereo());
    EXPECT_NEAR(back.stereoCameraModels()[0].baseline(), 0.12, 1e-12);
    EXPECT_EQ(back.stereoCameraModels()[0].localTransform(), kLocal);
    // The right image is always lossless (png when compressed).
    EXPECT_TRUE(sameBits(back.depthOrRightRaw(), data.depthOrRightRaw())) << "compressed " << compressed;
    if (!compressed) EXPECT_TRUE(sameBits(back.imageRaw(), data.imageRaw()));
  }
}

TEST(RGBDImageConversions, ColourRightImageIsMadeGrey) {
  const rtabmap::StereoCameraModel stereo(60.0, 60.0, 32.0, 24.0, 0.12, kLocal, cv::Size(64, 48));
  rtabmap_ros::RGBDImage msg = rgbdImageToMsg(SensorData(smoothImage(48, 64, 3), randomImage(48, 64, CV_8UC1), stereo),
                                              header());
  msg.depth = imageToMsg(smoothImage(48, 64, 3), header());
  const SensorData back = decode(msg);
  EXPECT_EQ(back.depthOrRightRaw().type(), CV_8UC1);
}

TEST(RGBDImageConversions, BadMessagesAreErrors) {
  std::string error;
  const rtabmap_ros::RGBDImage good = rgbdImageToMsg(rgbdFrame(CV_16UC1), header());
  auto expectError = [&](const rtabmap_ros::RGBDImage& msg, const std::string& words) {
    error.clear();
    EXPECT_FALSE(rgbdImageFromMsg(msg, kLocal, &error)) << words;
    EXPECT_NE(error.find(words), std::string::npos) << error;
  };
  rtabmap_ros::RGBDImage m = good;
  m.rgb = sensor_msgs::Image();
  expectError(m, "no rgb image");
  m = good;
  m.rgb_camera_info.K.fill(0.0);
  m.rgb_camera_info.P.fill(0.0);
  expectError(m, "zero focal length");
  m = good;
  m.depth = imageToMsg(randomImage(47, 64, CV_16UC1), header());
  expectError(m, "integer factor");
  m = good;
  m.depth = imageToMsg(randomImage(48, 64, CV_8UC1), header());  // mono8 "depth", no stereo baseline
  expectError(m, "not a depth image");
  m = good;
  m.rgb_camera_info.width = 640;
  m.rgb_camera_info.height = 480;
  expectError(m, "camera_info says 640x480");
  m = good;
  m.depth.data.resize(10);
  expectError(m, "depth");
  m = good;
  m.rgb.encoding = "32FC1";
  m.rgb.step = 64 * 4;
  m.rgb.data.resize(64 * 4 * 48);
  expectError(m, "holds depth");

  SensorData withFeatures = rgbdFrame(CV_16UC1);
  addFeatures(withFeatures, 10);
  m = rgbdImageToMsg(withFeatures, header());
  m.points.pop_back();
  expectError(m, "3D points");
  m = rgbdImageToMsg(withFeatures, header());
  m.key_points.pop_back();
  m.points.pop_back();
  expectError(m, "descriptors");
  m = rgbdImageToMsg(withFeatures, header());
  m.descriptors.resize(m.descriptors.size() / 2);
  expectError(m, "corrupt descriptors");
}

TEST(RGBDImageConversions, HalfResolutionDepthAndSizelessCameraInfoAreAccepted) {
  rtabmap_ros::RGBDImage msg = rgbdImageToMsg(rgbdFrame(CV_16UC1), header());
  msg.depth = imageToMsg(randomImage(24, 32, CV_16UC1), header());
  msg.rgb_camera_info.width = msg.rgb_camera_info.height = 0;  // some drivers leave them unset
  const SensorData back = decode(msg);
  EXPECT_EQ(back.depthOrRightRaw().size(), cv::Size(32, 24));
  EXPECT_EQ(back.cameraModels()[0].imageSize(), cv::Size(64, 48));
}

TEST(RGBDImageConversions, SeveralCamerasTravelAsRGBDImages) {
  const cv::Mat rgb = smoothImage(48, 128, 3);
  const cv::Mat depth = randomImage(48, 128, CV_16UC1);
  const Transform right(0, 0, 0.5, -M_PI / 2, 0, 0);
  CameraModel second = model();
  second.setLocalTransform(right);
  SensorData data(rgb, depth, std::vector<CameraModel>{model(), second}, 2, 9.0);
  std::vector<cv::KeyPoint> kpts = {cv::KeyPoint(10, 10, 3), cv::KeyPoint(100, 20, 3), cv::KeyPoint(70, 5, 3)};
  data.setFeatures(kpts, {}, randomImage(3, 16, CV_8UC1));
  const rtabmap_ros::RGBDImages msg = rgbdImagesToMsg(data, header("base"), {header("cam0"), header("cam1")});
  ASSERT_EQ(msg.rgbd_images.size(), 2u);
  EXPECT_EQ(msg.rgbd_images[1].header.frame_id, "cam1");
  EXPECT_EQ(msg.rgbd_images[0].key_points.size(), 1u);
  EXPECT_EQ(msg.rgbd_images[1].key_points.size(), 2u);
  EXPECT_FLOAT_EQ(msg.rgbd_images[1].key_points[0].pt.x, 36.0f);  // 100 - 64: in camera 1's image
  EXPECT_THROW(rgbdImageToMsg(data, header()), rtabmap::FormatError);

  std::string error;
  const std::optional<SensorData> back = rgbdImagesFromMsg(msg, {kLocal, right}, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_TRUE(sameBits(back->imageRaw(), rgb));
  EXPECT_TRUE(sameBits(back->depthOrRightRaw(), depth));
  ASSERT_EQ(back->cameraModels().size(), 2u);
  EXPECT_EQ(back->cameraModels()[1].localTransform(), right);
  ASSERT_EQ(back->keypoints().size(), 3u);
  EXPECT_EQ(back->descriptors().rows, 3);
  EXPECT_FALSE(rgbdImagesFromMsg(msg, {kLocal}, &error));
  EXPECT_NE(error.find("local transforms"), std::string::npos) << error;
}

TEST(RGBDImageConversions, SeveralStereoCamerasTravelAsRGBDImages) {
  // Two stereo cameras side by side: left images concatenated, right images the same way.
  const cv::Mat left = smoothImage(48, 128, 3);
  const cv::Mat right = randomImage(48, 128, CV_8UC1, 5);
  const Transform second(0, 0, 0.5, -M_PI / 2, 0, 0);
  const rtabmap::StereoCameraModel stereo0(60.0, 60.0, 32.0, 24.0, 0.12, kLocal, cv::Size(64, 48));
  const rtabmap::StereoCameraModel stereo1(62.0, 62.0, 31.0, 23.0, 0.2, second, cv::Size(64, 48));
  SensorData data(left, right, std::vector<rtabmap::StereoCameraModel>{stereo0, stereo1}, 2, 9.0);
  std::vector<cv::KeyPoint> kpts = {cv::KeyPoint(10, 10, 3), cv::KeyPoint(100, 20, 3), cv::KeyPoint(70, 5, 3)};
  data.setFeatures(kpts, {}, randomImage(3, 16, CV_8UC1));
  EXPECT_THROW(rgbdImageToMsg(data, header()), rtabmap::FormatError);
  for (bool compressed : {false, true}) {
    SCOPED_TRACE(compressed ? "compressed" : "raw");
    RGBDImageOptions options;
    options.compressed = compressed;
    const rtabmap_ros::RGBDImages msg = rgbdImagesToMsg(data, header("base"), {header("cam0"), header("cam1")}, options);
    ASSERT_EQ(msg.rgbd_images.size(), 2u);
    EXPECT_EQ(msg.rgbd_images[1].header.frame_id, "cam1");
    // Each entry is a stereo RGBDImage of its own camera: right info with Tx = -fx * baseline.
    EXPECT_NEAR(-msg.rgbd_images[0].depth_camera_info.P[3] / msg.rgbd_images[0].depth_camera_info.P[0], 0.12, 1e-9);
    EXPECT_NEAR(-msg.rgbd_images[1].depth_camera_info.P[3] / msg.rgbd_images[1].depth_camera_info.P[0], 0.2, 1e-9);
    EXPECT_EQ(msg.rgbd_images[0].key_points.size(), 1u);
    EXPECT_EQ(msg.rgbd_images[1].key_points.size(), 2u);
    EXPECT_FLOAT_EQ(msg.rgbd_images[1].key_points[0].pt.x, 36.0f);  // 100 - 64: in camera 1's image

    std::string error;
    const std::optional<SensorData> back = rgbdImagesFromMsg(msg, {kLocal, second}, &error);
    ASSERT_TRUE(back) << error;
    ASSERT_TRUE(back->isStereo());
    ASSERT_EQ(back->stereoCameraModels().size(), 2u);
    EXPECT_TRUE(back->cameraModels().empty());
    EXPECT_EQ(back->stereoCameraModels()[0].localTransform(), kLocal);
    EXPECT_EQ(back->stereoCameraModels()[1].localTransform(), second);
    EXPECT_NEAR(back->stereoCameraModels()[0].baseline(), 0.12, 1e-9);
    EXPECT_NEAR(back->stereoCameraModels()[1].baseline(), 0.2, 1e-9);
    EXPECT_DOUBLE_EQ(back->stereoCameraModels()[1].left().fx(), 62.0);
    EXPECT_EQ(back->stereoCameraModels()[1].left().imageSize(), cv::Size(64, 48));
    // The right images are lossless either way; the left ones when raw.
    EXPECT_TRUE(sameBits(back->depthOrRightRaw(), right));
    if (!compressed) EXPECT_TRUE(sameBits(back->imageRaw(), left));
    ASSERT_EQ(back->keypoints().size(), 3u);
    EXPECT_FLOAT_EQ(back->keypoints()[1].pt.x, 100.0f);  // back in the combined image
    EXPECT_EQ(back->descriptors().rows, 3);
  }
}

TEST(RGBDImageConversions, RGBDImagesOfMixedOrUnequalCamerasAreRefused) {
  const rtabmap::StereoCameraModel stereo(60.0, 60.0, 32.0, 24.0, 0.12, kLocal, cv::Size(64, 48));
  const SensorData pair(smoothImage(48, 64, 3), randomImage(48, 64, CV_8UC1, 4), stereo, 1, 3.5);
  rtabmap_ros::RGBDImages msg;
  msg.rgbd_images.push_back(rgbdImageToMsg(pair, header("cam0")));
  msg.rgbd_images.push_back(rgbdImageToMsg(rgbdFrame(CV_16UC1), header("cam1")));
  std::string error;
  EXPECT_FALSE(rgbdImagesFromMsg(msg, {kLocal, kLocal}, &error));
  EXPECT_NE(error.find("all RGB-D or all stereo"), std::string::npos) << error;
  // A stereo camera of another size cannot sit beside the first.
  const rtabmap::StereoCameraModel small(30.0, 30.0, 16.0, 12.0, 0.12, kLocal, cv::Size(32, 24));
  msg.rgbd_images[1] =
      rgbdImageToMsg(SensorData(smoothImage(24, 32, 3), randomImage(24, 32, CV_8UC1, 6), small), header("cam1"));
  EXPECT_FALSE(rgbdImagesFromMsg(msg, {kLocal, kLocal}, &error));
  EXPECT_NE(error.find("camera 1 has images of another size"), std::string::npos) << error;
  // A stereo entry that lost its right image cannot sit beside a stereo camera either.
  msg.rgbd_images[1] = rgbdImageToMsg(pair, header("cam1"));
  msg.rgbd_images[1].depth = sensor_msgs::Image();
  EXPECT_FALSE(rgbdImagesFromMsg(msg, {kLocal, kLocal}, &error));
  EXPECT_NE(error.find("camera 1 is without depth or right image"), std::string::npos) << error;
  EXPECT_NE(error.find("camera 0 is stereo"), std::string::npos) << error;
}
