// Dataset -> bag for the layouts ../shared/data has no sample of (TUM RGB-D, plain image
// folders): a tiny dataset is written on disk in the layout's own format, converted, and the
// bag is compared with what the layout's files say (pixel values, depth scale, stamps, poses,
// calibration, frames).
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_msgs/TFMessage.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "BagTestSupport.h"
#include "TestHelpers.h"
#include "common/TestData.h"
#include "rtabmap_conversions/DatasetBag.h"
#include "rtabmap_conversions/ImageConversions.h"
#include "rtabmap_conversions/TransformConversions.h"
#include "rtabmap_core/geometry/CameraModel.h"

using namespace rtabmap_conversions;
using rtabmap_conversions::test::readTopic;
using rtabmap_conversions::test::topicCounts;

namespace {

namespace fs = std::filesystem;

BagSummary convert(const std::string& format, const std::string& input, const std::string& output) {
  std::unique_ptr<rtabmap::DatasetReader> reader = rtabmap::openDatasetReader(format, input, {});
  return convertDatasetToBag(*reader, output);
}

// Depth in the TUM files: 5000 per metre.
cv::Mat tumDepth(int frame) {
  cv::Mat depth(48, 64, CV_16UC1);
  for (int v = 0; v < depth.rows; ++v) {
    for (int u = 0; u < depth.cols; ++u) depth.at<uint16_t>(v, u) = uint16_t(5000 + 5 * (u + v + frame));
  }
  depth.at<uint16_t>(0, 0) = 0;  // no depth stays no depth
  return depth;
}

struct TumSample {
  std::vector<double> stamps = {1305031102.175304, 1305031102.211214, 1305031102.243211};
  std::vector<cv::Mat> rgb;
};

// A freiburg1 folder (the name picks the published fr1 intrinsics): three colour frames, each
// with a depth image 4 ms later, and motion-capture poses every 10 ms around them.
TumSample writeTum(const fs::path& dir) {
  TumSample sample;
  fs::create_directories(dir / "rgb");
  fs::create_directories(dir / "depth");
  std::ofstream rgbList(dir / "rgb.txt"), depthList(dir / "depth.txt"), gt(dir / "groundtruth.txt");
  rgbList << "# color images\n# timestamp filename\n";
  depthList << "# depth maps\n";
  gt << "# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n";
  for (size_t i = 0; i < sample.stamps.size(); ++i) {
    char name[64];
    std::snprintf(name, sizeof(name), "%.6f.png", sample.stamps[i]);
    sample.rgb.push_back(rtabmap_conversions::test::randomImage(48, 64, CV_8UC3, unsigned(11 + i)));
    cv::imwrite((dir / "rgb" / name).string(), sample.rgb.back());
    rgbList.precision(6);
    rgbList << std::fixed << sample.stamps[i] << " rgb/" << name << "\n";
    std::snprintf(name, sizeof(name), "%.6f.png", sample.stamps[i] + 0.004);
    cv::imwrite((dir / "depth" / name).string(), tumDepth(int(i)));
    depthList.precision(6);
    depthList << std::fixed << sample.stamps[i] + 0.004 << " depth/" << name << "\n";
  }
  // A constant pose: the interpolated ground truth at every frame is this one.
  for (double t = sample.stamps.front() - 0.05; t < sample.stamps.back() + 0.05; t += 0.01) {
    gt.precision(4);
    gt << std::fixed << t << " 1.5 -0.25 0.75 0 0 0.38268343 0.92387953\n";
  }
  return sample;
}

rtabmap::Transform staticChain(const tf2_msgs::TFMessage& msg, const std::string& child) {
  std::map<std::string, std::pair<std::string, rtabmap::Transform>> byChild;
  for (const auto& t : msg.transforms) byChild[t.child_frame_id] = {t.header.frame_id, transformFromMsg(t.transform)};
  rtabmap::Transform chain = rtabmap::Transform::Identity();
  for (std::string frame = child; frame != "base_link";) {
    auto it = byChild.find(frame);
    if (it == byChild.end()) return rtabmap::Transform();
    chain = it->second.second * chain;
    frame = it->second.first;
  }
  return chain;
}

double maxDifference(const rtabmap::Transform& a, const rtabmap::Transform& b) {
  return (a.toMatrix4d() - b.toMatrix4d()).cwiseAbs().maxCoeff();
}

}  // namespace

TEST(DatasetBagFormats, TumRgbdFolder) {
  rtabmap::test::TempDir dir("rtabmap_bag_tum");
  const fs::path folder = fs::path(dir.file("rgbd_dataset_freiburg1_tiny"));
  const TumSample sample = writeTum(folder);
  const std::string bagPath = dir.file("tum.bag");
  const BagSummary summary = convert("tum", folder.string(), bagPath);
  EXPECT_EQ(summary.frames, 3u);
  EXPECT_EQ(summary.timeOffset, 0.0);

  const auto rgb = readTopic<sensor_msgs::Image>(bagPath, "/camera/rgb/image_rect_color");
  const auto depth = readTopic<sensor_msgs::Image>(bagPath, "/camera/depth_registered/image_raw");
  const auto info = readTopic<sensor_msgs::CameraInfo>(bagPath, "/camera/rgb/camera_info");
  const auto gt = readTopic<nav_msgs::Odometry>(bagPath, "/ground_truth");
  ASSERT_EQ(rgb.size(), 3u);
  ASSERT_EQ(depth.size(), 3u);
  ASSERT_EQ(info.size(), 3u);
  ASSERT_EQ(gt.size(), 3u);
  const rtabmap::Transform worldToOptical(1.5, -0.25, 0.75, 0.0, 0.0, M_PI / 4);
  for (size_t i = 0; i < 3; ++i) {
    // Stamped with the colour image's time (microseconds in rgb.txt).
    EXPECT_NEAR(rgb[i].msg.header.stamp.toSec(), sample.stamps[i], 1e-6);
    EXPECT_EQ(rgb[i].msg.header.stamp, depth[i].msg.header.stamp);
    EXPECT_EQ(rgb[i].msg.header.frame_id, "camera_rgb_optical_frame");
    EXPECT_EQ(rgb[i].msg.encoding, "bgr8");
    EXPECT_TRUE(rtabmap_conversions::test::sameBits(*imageFromMsg(rgb[i].msg), sample.rgb[i])) << i;
    // 16UC1 millimetres: the file's 5000-per-metre values divided by 5.
    ASSERT_EQ(depth[i].msg.encoding, "16UC1");
    const cv::Mat mm = *imageFromMsg(depth[i].msg);
    const cv::Mat file = tumDepth(int(i));
    EXPECT_EQ(mm.at<uint16_t>(0, 0), 0);
    EXPECT_EQ(mm.at<uint16_t>(10, 20), file.at<uint16_t>(10, 20) / 5);
    EXPECT_EQ(mm.at<uint16_t>(47, 63), file.at<uint16_t>(47, 63) / 5);
    // freiburg1's published intrinsics.
    EXPECT_DOUBLE_EQ(info[i].msg.K[0], 517.3);
    EXPECT_DOUBLE_EQ(info[i].msg.K[2], 318.6);
    EXPECT_DOUBLE_EQ(info[i].msg.K[4], 516.5);
    EXPECT_DOUBLE_EQ(info[i].msg.K[5], 255.3);
    EXPECT_EQ(info[i].msg.width, 64u);
    // Ground truth: the pose of base_link, i.e. world_T_optical * opticalRotation^-1.
    EXPECT_EQ(gt[i].msg.header.frame_id, "world");
    EXPECT_EQ(gt[i].msg.child_frame_id, "base_link");
    const rtabmap::Transform base = transformFromPoseMsg(gt[i].msg.pose.pose);
    EXPECT_LT(maxDifference(base * rtabmap::CameraModel::opticalRotation(), worldToOptical), 1e-6) << i;
  }
  // Hand-held camera: base_link is at the camera, so the static chain to the optical frame is
  // the optical rotation alone. No odometry in the layout: no /odom, no /tf.
  const auto statics = readTopic<tf2_msgs::TFMessage>(bagPath, "/tf_static");
  ASSERT_EQ(statics.size(), 1u);
  const rtabmap::Transform chain = staticChain(statics[0].msg, "camera_rgb_optical_frame");
  ASSERT_FALSE(chain.isNull());
  EXPECT_LT(maxDifference(chain, rtabmap::CameraModel::opticalRotation()), 1e-9);
  const std::map<std::string, size_t> counts = topicCounts(bagPath);
  EXPECT_EQ(counts.count("/odom"), 0u);
  EXPECT_EQ(counts.count("/tf"), 0u);
}

TEST(DatasetBagFormats, ImageFolderWithoutCalibration) {
  rtabmap::test::TempDir dir("rtabmap_bag_images");
  const fs::path folder = fs::path(dir.file("images"));
  fs::create_directories(folder);
  std::vector<cv::Mat> images;
  for (int i = 0; i < 3; ++i) {
    images.push_back(rtabmap_conversions::test::randomImage(30, 40, CV_8UC3, unsigned(21 + i)));
    cv::imwrite((folder / ("img" + std::to_string(i) + ".png")).string(), images.back());
  }
  const std::string bagPath = dir.file("images.bag");
  const BagSummary summary = convert("images", folder.string(), bagPath);
  EXPECT_EQ(summary.frames, 3u);
  // Synthesised 1 Hz stamps start at 0, which ROS reads as "no stamp": shifted to 1 s.
  EXPECT_EQ(summary.timeOffset, 1.0);
  const auto rgb = readTopic<sensor_msgs::Image>(bagPath, "/camera/rgb/image_rect_color");
  ASSERT_EQ(rgb.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(rgb[i].msg.header.stamp, ros::Time(1.0 + double(i)));
    EXPECT_TRUE(rtabmap_conversions::test::sameBits(*imageFromMsg(rgb[i].msg), images[i])) << i;
  }
  // Without calibration the images are published alone: no camera_info, no depth.
  const std::map<std::string, size_t> counts = topicCounts(bagPath);
  EXPECT_EQ(counts.count("/camera/rgb/camera_info"), 0u);
  EXPECT_EQ(counts.count("/camera/depth_registered/image_raw"), 0u);
}
