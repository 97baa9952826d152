// Dataset -> bag -> messages read back, compared with what the dataset readers yield, on the
// real datasets of ../shared/data (each test skips when its data is absent), and the
// rtabmap-bag tool itself on the ACES log.
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <nlohmann/json.hpp>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <set>

#include "BagTestSupport.h"
#include "TestHelpers.h"
#include "common/TestData.h"
#include "rtabmap_conversions/DatasetBag.h"
#include "rtabmap_conversions/ImageConversions.h"
#include "rtabmap_conversions/PointCloudConversions.h"
#include "rtabmap_conversions/TransformConversions.h"

using namespace rtabmap_conversions;
using rtabmap::DatasetRecord;
using rtabmap_conversions::test::readTopic;
using rtabmap_conversions::test::sameBits;
using rtabmap_conversions::test::topicCounts;

namespace {

std::vector<DatasetRecord> readAll(const std::string& format, const std::string& path,
                                   const rtabmap::DatasetReaderOptions& options) {
  std::unique_ptr<rtabmap::DatasetReader> reader = rtabmap::openDatasetReader(format, path, options);
  std::vector<DatasetRecord> records;
  DatasetRecord r;
  while (reader->next(r)) records.push_back(r);
  return records;
}

BagSummary convert(const std::string& format, const std::string& input, const std::string& output,
                   const rtabmap::DatasetReaderOptions& options) {
  std::unique_ptr<rtabmap::DatasetReader> reader = rtabmap::openDatasetReader(format, input, options);
  return convertDatasetToBag(*reader, output);
}

size_t distinctOdomStamps(const std::vector<DatasetRecord>& records) {
  std::set<double> stamps;
  for (const DatasetRecord& r : records) {
    if (r.kind != DatasetRecord::Kind::kImu && !r.data.odomPose().isNull()) stamps.insert(r.stamp);
  }
  return stamps.size();
}

// The shipped copy of the ACES log (data/radish) when ../shared/data is absent.
std::string acesLog() {
  const std::string shared = rtabmap::test::sharedDataPath("radish/aces.clf.bz2");
  if (!shared.empty()) return shared;
  const std::string shipped = std::string(RTABMAP_ROS_SOURCE_DIR) + "/data/radish/aces.clf.bz2";
  return std::filesystem::exists(shipped) ? shipped : "";
}

}  // namespace

TEST(DatasetBagRealData, CarmenScansAndOdometryMatchTheReader) {
  const std::string log = acesLog();
  if (log.empty()) GTEST_SKIP() << "needs radish/aces.clf.bz2 (../shared/data or data/)";
  rtabmap::DatasetReaderOptions options;
  options.maxFrames = 400;
  const std::vector<DatasetRecord> records = readAll("carmen", log, options);
  rtabmap::test::TempDir dir("rtabmap_bag_carmen");
  const BagSummary summary = convert("carmen", log, dir.file("aces.bag"), options);
  EXPECT_EQ(summary.frames, 400u);
  EXPECT_EQ(summary.timeOffset, 0.0);  // the log's own clock starts at 70 s: no offset needed

  const auto scans = readTopic<sensor_msgs::LaserScan>(dir.file("aces.bag"), "/scan");
  ASSERT_EQ(scans.size(), 400u);
  size_t frame = 0;
  for (const DatasetRecord& r : records) {
    if (r.kind != DatasetRecord::Kind::kFrame) continue;
    const sensor_msgs::LaserScan& msg = scans[frame++].msg;
    EXPECT_EQ(msg.header.stamp, ros::Time(r.stamp));
    const std::vector<float> expected = r.data.laserScanRaw().toRanges();
    ASSERT_EQ(msg.ranges.size(), expected.size());
    EXPECT_EQ(std::memcmp(msg.ranges.data(), expected.data(), expected.size() * sizeof(float)), 0) << "frame " << frame;
    EXPECT_FLOAT_EQ(msg.range_max, float(r.data.laserScanRaw().rangeMax()));
  }
  EXPECT_EQ(readTopic<nav_msgs::Odometry>(dir.file("aces.bag"), "/odom").size(), distinctOdomStamps(records));
  EXPECT_EQ(readTopic<tf2_msgs::TFMessage>(dir.file("aces.bag"), "/tf").size(), distinctOdomStamps(records));
  const auto statics = readTopic<tf2_msgs::TFMessage>(dir.file("aces.bag"), "/tf_static");
  ASSERT_EQ(statics.size(), 1u);
  EXPECT_EQ(statics[0].msg.transforms[0].child_frame_id, "laser");
}

TEST(DatasetBagRealData, SevenScenesImagesAreBitExact) {
  RTABMAP_REQUIRE_DATA(folder, "rgbd_7scenes");
  rtabmap::DatasetReaderOptions options;
  options.maxFrames = 15;
  const std::vector<DatasetRecord> records = readAll("7scenes", folder, options);
  rtabmap::test::TempDir dir("rtabmap_bag_7scenes");
  const std::string bagPath = dir.file("7scenes.bag");
  const BagSummary summary = convert("7scenes", folder, bagPath, options);
  EXPECT_EQ(summary.frames, 15u);
  const auto rgb = readTopic<sensor_msgs::Image>(bagPath, "/camera/rgb/image_rect_color");
  const auto depth = readTopic<sensor_msgs::Image>(bagPath, "/camera/depth_registered/image_raw");
  const auto info = readTopic<sensor_msgs::CameraInfo>(bagPath, "/camera/rgb/camera_info");
  const auto gt = readTopic<nav_msgs::Odometry>(bagPath, "/ground_truth");
  ASSERT_EQ(rgb.size(), 15u);
  ASSERT_EQ(depth.size(), 15u);
  ASSERT_EQ(info.size(), 15u);
  for (size_t i = 0; i < records.size(); ++i) {
    const rtabmap::SensorData& data = records[i].data;
    EXPECT_EQ(rgb[i].msg.header.stamp, ros::Time(records[i].stamp + summary.timeOffset));
    EXPECT_TRUE(sameBits(*imageFromMsg(rgb[i].msg), data.imageRaw())) << "frame " << i;
    EXPECT_TRUE(sameBits(*imageFromMsg(depth[i].msg), data.depthOrRightRaw())) << "frame " << i;
    EXPECT_DOUBLE_EQ(info[i].msg.P[0], data.cameraModels()[0].fx());
  }
  size_t withGt = 0;
  for (const DatasetRecord& r : records) withGt += r.data.groundTruth().isNull() ? 0 : 1;
  EXPECT_EQ(gt.size(), withGt);
}

TEST(DatasetBagRealData, EurocStereoAndImu) {
  RTABMAP_REQUIRE_DATA(folder, "euroc_v1_01_micro");
  rtabmap::DatasetReaderOptions options;
  options.maxFrames = 10;
  const std::vector<DatasetRecord> records = readAll("euroc", folder, options);
  rtabmap::test::TempDir dir("rtabmap_bag_euroc");
  const std::string bagPath = dir.file("euroc.bag");
  convert("euroc", folder, bagPath, options);
  size_t imu = 0;
  std::vector<const DatasetRecord*> frames;
  for (const DatasetRecord& r : records) {
    if (!r.data.imu().empty()) ++imu;
    if (r.kind == DatasetRecord::Kind::kFrame) frames.push_back(&r);
  }
  ASSERT_EQ(frames.size(), 10u);
  const auto left = readTopic<sensor_msgs::Image>(bagPath, "/stereo_camera/left/image_rect");
  const auto right = readTopic<sensor_msgs::Image>(bagPath, "/stereo_camera/right/image_rect");
  const auto rightInfo = readTopic<sensor_msgs::CameraInfo>(bagPath, "/stereo_camera/right/camera_info");
  ASSERT_EQ(left.size(), 10u);
  ASSERT_EQ(right.size(), 10u);
  EXPECT_EQ(readTopic<sensor_msgs::Imu>(bagPath, "/imu/data").size(), imu);
  for (size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(left[i].time, ros::Time(frames[i]->stamp));
    EXPECT_TRUE(sameBits(*imageFromMsg(left[i].msg), frames[i]->data.imageRaw())) << i;
    EXPECT_TRUE(sameBits(*imageFromMsg(right[i].msg), frames[i]->data.depthOrRightRaw())) << i;
  }
  EXPECT_LT(rightInfo[0].msg.P[3], 0.0);  // rectified pair: right Tx = -fx * baseline
  EXPECT_NEAR(-rightInfo[0].msg.P[3] / rightInfo[0].msg.P[0], frames[0]->data.stereoCameraModels()[0].baseline(), 1e-9);
}

// KITTI Velodyne scans: /velodyne_points holds every point of the .bin files bit-exactly (XYZI),
// in the velodyne frame mounted on base_link by /tf_static, and /ground_truth the sequence's
// poses at the scans' own stamps (frame number / 10 Hz without times.txt).
TEST(DatasetBagRealData, KittiVelodyneScansAreBitExact) {
  RTABMAP_REQUIRE_DATA(folder, "kitti00_velodyne");
  const std::vector<DatasetRecord> records = readAll("kitti", folder, {});
  ASSERT_EQ(records.size(), 4u);  // scans 94, 95, 198 and 199
  rtabmap::test::TempDir dir("rtabmap_bag_kitti");
  const std::string bagPath = dir.file("kitti.bag");
  const BagSummary summary = convert("kitti", folder, bagPath, {});
  EXPECT_EQ(summary.frames, 4u);
  EXPECT_EQ(summary.timeOffset, 0.0);  // the first stamp is 9.4 s
  const auto clouds = readTopic<sensor_msgs::PointCloud2>(bagPath, "/velodyne_points");
  const auto gt = readTopic<nav_msgs::Odometry>(bagPath, "/ground_truth");
  ASSERT_EQ(clouds.size(), 4u);
  ASSERT_EQ(gt.size(), 4u);
  for (size_t i = 0; i < records.size(); ++i) {
    const rtabmap::LaserScan& expected = records[i].data.laserScanRaw();
    const sensor_msgs::PointCloud2& msg = clouds[i].msg;
    EXPECT_EQ(msg.header.stamp, ros::Time(records[i].stamp));
    EXPECT_EQ(msg.header.frame_id, "velodyne");
    std::string why;
    const std::optional<rtabmap::LaserScan> back = laserScanFromCloudMsg(msg, expected.localTransform(), &why);
    ASSERT_TRUE(back) << why;
    EXPECT_EQ(back->format(), rtabmap::LaserScan::kXYZI);
    EXPECT_GT(back->size(), 100000);  // an HDL-64 sweep
    EXPECT_TRUE(sameBits(back->data(), expected.data())) << "scan " << i;
    // The poses file has 7 significant digits: its rotations are orthonormal to ~1e-7 only,
    // and a quaternion cannot hold more than the orthonormal part.
    const rtabmap::Transform pose = transformFromPoseMsg(gt[i].msg.pose.pose);
    EXPECT_LT((pose.toMatrix4d() - records[i].data.groundTruth().toMatrix4d()).cwiseAbs().maxCoeff(), 1e-6);
    EXPECT_EQ(gt[i].msg.header.stamp, msg.header.stamp);
  }
  const auto statics = readTopic<tf2_msgs::TFMessage>(bagPath, "/tf_static");
  ASSERT_EQ(statics.size(), 1u);
  ASSERT_EQ(statics[0].msg.transforms.size(), 1u);
  EXPECT_EQ(statics[0].msg.transforms[0].header.frame_id, "base_link");
  EXPECT_EQ(statics[0].msg.transforms[0].child_frame_id, "velodyne");
  const rtabmap::Transform mounting = transformFromMsg(statics[0].msg.transforms[0].transform);
  EXPECT_LT((mounting.toMatrix4d() - records[0].data.laserScanRaw().localTransform().toMatrix4d()).cwiseAbs().maxCoeff(),
            1e-9);
}

// The check: `rtabmap-bag --format carmen` on ACES gives 7,374 scans, tf, and
// monotonic stamps (what `rosbag play --clock` publishes on /clock).
TEST(DatasetBagRealData, ToolConvertsTheWholeAcesLog) {
  const std::string log = acesLog();
  if (log.empty()) GTEST_SKIP() << "needs radish/aces.clf.bz2 (../shared/data or data/)";
  rtabmap::test::TempDir dir("rtabmap_bag_tool");
  const std::string bagPath = dir.file("aces.bag");
  const std::string command = std::string(RTABMAP_ROS_TOOLS_DIR) + "/rtabmap-bag --json --format carmen '" + log +
                              "' '" + bagPath + "' 2>&1";
  const auto start = std::chrono::steady_clock::now();
  FILE* pipe = popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output, lastLine;
  char buffer[4096];
  while (fgets(buffer, sizeof(buffer), pipe)) {
    output += buffer;
    lastLine = buffer;
  }
  const int status = pclose(pipe);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(status, 0) << output;
  EXPECT_LT(seconds, 30.0);
  const nlohmann::json summary = nlohmann::json::parse(lastLine);
  EXPECT_EQ(summary["topics"]["/scan"], 7374);
  EXPECT_EQ(summary["frames"], 7374);
  EXPECT_EQ(summary["out_of_order_records"], 0);  // written in time order: no reordering left to rosbag

  const std::map<std::string, size_t> counts = topicCounts(bagPath);
  EXPECT_EQ(counts.at("/scan"), 7374u);
  EXPECT_GT(counts.at("/tf"), 7000u);
  EXPECT_EQ(counts.at("/tf_static"), 1u);
  EXPECT_EQ(counts.at("/odom"), counts.at("/tf"));

  // Played in bag-time order, message stamps never go back, and equal the bag times (so the
  // /clock rosbag play publishes is the data's own time).
  rosbag::Bag bag(bagPath, rosbag::bagmode::Read);
  rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{"/scan", "/tf"}));
  ros::Time previous;
  size_t checked = 0;
  for (const rosbag::MessageInstance& m : view) {
    ros::Time stamp;
    if (auto scan = m.instantiate<sensor_msgs::LaserScan>()) stamp = scan->header.stamp;
    if (auto tf = m.instantiate<tf2_msgs::TFMessage>()) stamp = tf->transforms.at(0).header.stamp;
    EXPECT_EQ(stamp, m.getTime());
    EXPECT_GE(stamp, previous);
    previous = stamp;
    ++checked;
  }
  EXPECT_EQ(checked, counts.at("/scan") + counts.at("/tf"));
}
