#include "rtabmap_conversions/DatasetBag.h"

#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>

#include <limits>

#include "BagTestSupport.h"
#include "TestHelpers.h"
#include "common/TestData.h"
#include "rtabmap_conversions/BagLayout.h"
#include "rtabmap_conversions/ImageConversions.h"
#include "rtabmap_conversions/TransformConversions.h"
#include "rtabmap_core/common/Error.h"

using namespace rtabmap_conversions;
using rtabmap::CameraModel;
using rtabmap::DatasetRecord;
using rtabmap::LaserScan;
using rtabmap::SensorData;
using rtabmap::Transform;
using rtabmap_conversions::test::randomImage;
using rtabmap_conversions::test::readTopic;
using rtabmap_conversions::test::sameBits;
using rtabmap_conversions::test::ScriptedReader;
using rtabmap_conversions::test::topicCounts;

namespace {

const Transform kCamera(0.1, 0.02, 0.5, -M_PI / 2, 0.0, -M_PI / 2 + 0.05);
const Transform kLaser(0.2, 0.0, 0.3, 0.0, 0.0, 0.01);
const Transform kImu(0.0, 0.05, 0.1, 0.0, 0.0, M_PI / 2);

std::vector<float> ranges(int seed) {
  std::vector<float> r(181);
  for (int i = 0; i < 181; ++i) r[size_t(i)] = 1.0f + 0.01f * float((i * 7 + seed) % 300);
  r[20] = std::numeric_limits<float>::infinity();
  return r;
}

DatasetRecord imuRecord(double stamp) {
  DatasetRecord r;
  r.kind = DatasetRecord::Kind::kImu;
  r.stamp = stamp;
  rtabmap::IMU imu;
  imu.angularVelocity = Eigen::Vector3d(0.0, 0.0, stamp);
  imu.linearAcceleration = Eigen::Vector3d(0.0, 0.0, 9.8);
  imu.localTransform = kImu;
  r.data.setIMU(imu);
  r.data.setStamp(stamp);
  return r;
}

DatasetRecord odomRecord(double stamp, double x) {
  DatasetRecord r;
  r.kind = DatasetRecord::Kind::kOdometry;
  r.stamp = stamp;
  r.data.setStamp(stamp);
  r.data.setOdom(Transform(x, 0.0, 0.1 * x), Eigen::Matrix<double, 6, 6>::Identity() * 0.01);
  return r;
}

DatasetRecord rgbdLaserFrame(double stamp, int id) {
  DatasetRecord r;
  r.kind = DatasetRecord::Kind::kFrame;
  r.stamp = stamp;
  r.data = SensorData(LaserScan::fromRanges(ranges(id), -M_PI / 2, M_PI / 180, 0.1, 20.0, kLaser),
                      randomImage(48, 64, CV_8UC3, unsigned(id)), randomImage(48, 64, CV_16UC1, unsigned(id) + 50),
                      CameraModel(50.0, 50.0, 32.0, 24.0, kCamera, 0.0, cv::Size(64, 48)), id, stamp);
  r.data.setOdom(Transform(0.5 * id, 0.0, 0.1 * id), Eigen::Matrix<double, 6, 6>::Identity() * 0.02);
  r.data.setGroundTruth(Transform(0.5 * id + 0.01, 0.0, 0.1 * id));
  return r;
}

// base_link -> child through the /tf_static message (parents resolved recursively).
Transform staticChain(const tf2_msgs::TFMessage& msg, const std::string& child) {
  for (const auto& t : msg.transforms) {
    if (t.child_frame_id != child) continue;
    const Transform local = transformFromMsg(t.transform);
    return t.header.frame_id == bag::kBaseFrame ? local : staticChain(msg, t.header.frame_id) * local;
  }
  return Transform();
}

}  // namespace

class DatasetBagTest : public ::testing::Test {
 protected:
  rtabmap::test::TempDir dir{"rtabmap_bag_test"};
  std::string path = dir.file("out.bag");
};

TEST_F(DatasetBagTest, RgbdLaserImuOdometryLayout) {
  ScriptedReader reader({imuRecord(0.0), imuRecord(0.01), rgbdLaserFrame(0.02, 1), imuRecord(0.03),
                         odomRecord(0.05, 0.7), rgbdLaserFrame(0.07, 2), odomRecord(0.07, 1.0)});
  const BagSummary summary = convertDatasetToBag(reader, path);
  EXPECT_EQ(summary.records, 7u);
  EXPECT_EQ(summary.frames, 2u);
  EXPECT_EQ(summary.timeOffset, 1.0);  // synthetic clock starting at 0
  EXPECT_EQ(summary.outOfOrder, 0u);
  EXPECT_NEAR(summary.startTime, 1.0 - 1e-6, 1e-9);  // /tf_static, just before the first record
  EXPECT_DOUBLE_EQ(summary.endTime, 1.07);
  EXPECT_GT(summary.bytes, 0u);

  const std::map<std::string, size_t> expected = {
      {"/tf_static", 1}, {"/imu/data", 3}, {"/odom", 3}, {"/tf", 3}, {"/ground_truth", 2}, {"/scan", 2},
      {"/camera/rgb/image_rect_color", 2}, {"/camera/depth_registered/image_raw", 2}, {"/camera/rgb/camera_info", 2}};
  EXPECT_EQ(topicCounts(path), expected);
  for (const auto& [topic, count] : expected) EXPECT_EQ(summary.messagesPerTopic.at(topic), count) << topic;

  // /tf_static: first, at the first stamp, latched, with every mounting.
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  rosbag::View all(bag);
  ASSERT_GT(all.size(), 0u);
  EXPECT_EQ(all.begin()->getTopic(), "/tf_static");
  EXPECT_EQ(all.begin()->getTime(), ros::Time(1.0) - ros::Duration(0, 1000));
  for (const rosbag::ConnectionInfo* c : all.getConnections()) {
    EXPECT_EQ(c->header->at("latching"), c->topic == "/tf_static" ? "1" : "0") << c->topic;
    EXPECT_EQ(c->header->at("callerid"), "/rtabmap_bag");
  }
  const auto statics = readTopic<tf2_msgs::TFMessage>(path, "/tf_static");
  ASSERT_EQ(statics.size(), 1u);
  const tf2_msgs::TFMessage& st = statics[0].msg;
  EXPECT_TRUE(staticChain(st, "laser").toEigen().isApprox(kLaser.toEigen(), 1e-9));
  EXPECT_TRUE(staticChain(st, "imu_link").toEigen().isApprox(kImu.toEigen(), 1e-9));
  EXPECT_TRUE(staticChain(st, "camera_rgb_optical_frame").toEigen().isApprox(kCamera.toEigen(), 1e-9));
  // camera_link has body axes (REP-103): its x is the optical frame's z.
  const Transform cameraLink = staticChain(st, "camera_link");
  EXPECT_TRUE(cameraLink.rotationMatrix().col(0).isApprox(kCamera.rotationMatrix().col(2), 1e-9));

  // Odometry: /odom and /tf agree, once per stamp (the odometry record at 0.07 duplicates the frame's).
  const auto odom = readTopic<nav_msgs::Odometry>(path, "/odom");
  const auto tf = readTopic<tf2_msgs::TFMessage>(path, "/tf");
  ASSERT_EQ(odom.size(), 3u);
  ASSERT_EQ(tf.size(), 3u);
  const double odomStamps[] = {1.02, 1.05, 1.07};
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(odom[i].time, ros::Time(odomStamps[i]));
    EXPECT_EQ(odom[i].msg.header.stamp, odom[i].time);
    EXPECT_EQ(odom[i].msg.header.frame_id, "odom");
    EXPECT_EQ(odom[i].msg.child_frame_id, "base_link");
    ASSERT_EQ(tf[i].msg.transforms.size(), 1u);
    EXPECT_EQ(tf[i].msg.transforms[0].header.stamp, odom[i].time);
    EXPECT_EQ(tf[i].msg.transforms[0].child_frame_id, "base_link");
    EXPECT_EQ(tf[i].msg.transforms[0].transform.translation.x, odom[i].msg.pose.pose.position.x);
  }
  EXPECT_DOUBLE_EQ(odom[1].msg.pose.pose.position.x, 0.7);
  EXPECT_DOUBLE_EQ(odom[0].msg.pose.covariance[0], 0.02);

  const auto gt = readTopic<nav_msgs::Odometry>(path, "/ground_truth");
  ASSERT_EQ(gt.size(), 2u);
  EXPECT_EQ(gt[1].msg.header.frame_id, "world");
  EXPECT_DOUBLE_EQ(gt[1].msg.pose.pose.position.x, 1.01);

  // Scans: ranges of the dataset, no-return beams as +Inf, in the laser frame.
  const auto scans = readTopic<sensor_msgs::LaserScan>(path, "/scan");
  ASSERT_EQ(scans.size(), 2u);
  EXPECT_EQ(scans[1].msg.header.frame_id, "laser");
  EXPECT_EQ(scans[1].msg.header.stamp, ros::Time(1.07));
  const std::vector<float> source = ranges(2);
  ASSERT_EQ(scans[1].msg.ranges.size(), source.size());
  for (size_t i = 0; i < source.size(); ++i) {
    if (std::isinf(source[i])) EXPECT_TRUE(std::isinf(scans[1].msg.ranges[i])) << i;
    else EXPECT_NEAR(scans[1].msg.ranges[i], source[i], 1e-5f) << i;
  }

  // Images: bit-exact, in the optical frame, with their calibration.
  const auto rgb = readTopic<sensor_msgs::Image>(path, "/camera/rgb/image_rect_color");
  const auto depth = readTopic<sensor_msgs::Image>(path, "/camera/depth_registered/image_raw");
  const auto info = readTopic<sensor_msgs::CameraInfo>(path, "/camera/rgb/camera_info");
  ASSERT_EQ(rgb.size(), 2u);
  EXPECT_EQ(rgb[0].msg.header.frame_id, "camera_rgb_optical_frame");
  EXPECT_EQ(depth[0].msg.encoding, "16UC1");
  EXPECT_TRUE(sameBits(*imageFromMsg(rgb[0].msg), randomImage(48, 64, CV_8UC3, 1)));
  EXPECT_TRUE(sameBits(*imageFromMsg(depth[1].msg), randomImage(48, 64, CV_16UC1, 52)));
  EXPECT_EQ(info[0].msg.header.frame_id, "camera_rgb_optical_frame");
  EXPECT_EQ(info[0].msg.P[0], 50.0);
  EXPECT_EQ(info[0].msg.width, 64u);

  const auto imu = readTopic<sensor_msgs::Imu>(path, "/imu/data");
  ASSERT_EQ(imu.size(), 3u);
  EXPECT_EQ(imu[0].time, ros::Time(1.0));
  EXPECT_EQ(imu[2].msg.header.frame_id, "imu_link");
  EXPECT_DOUBLE_EQ(imu[2].msg.angular_velocity.z, 0.03);
  EXPECT_EQ(imu[2].msg.orientation_covariance[0], -1.0);
}

TEST_F(DatasetBagTest, StereoAndVelodyneLayout) {
  std::vector<DatasetRecord> records;
  for (int i = 0; i < 3; ++i) {
    DatasetRecord r;
    r.stamp = 1400000000.0 + 0.1 * i;  // a real clock: no offset
    const rtabmap::StereoCameraModel stereo(60.0, 60.0, 32.0, 24.0, 0.12, kCamera, cv::Size(64, 48));
    r.data = SensorData(randomImage(48, 64, CV_8UC1, unsigned(i)), randomImage(48, 64, CV_8UC1, unsigned(i) + 9), stereo,
                        i + 1, r.stamp);
    r.data.setLaserScan(LaserScan(randomImage(1, 100, CV_32FC4), 120, 1.0, 120.0, LaserScan::kXYZI,
                                  Transform(0, 0, 1.7, 0, 0, 0)));
    records.push_back(r);
  }
  ScriptedReader reader(records);
  const BagSummary summary = convertDatasetToBag(reader, path);
  EXPECT_EQ(summary.timeOffset, 0.0);
  const std::map<std::string, size_t> expected = {
      {"/tf_static", 1}, {"/velodyne_points", 3}, {"/stereo_camera/left/image_rect", 3},
      {"/stereo_camera/right/image_rect", 3}, {"/stereo_camera/left/camera_info", 3},
      {"/stereo_camera/right/camera_info", 3}};
  EXPECT_EQ(topicCounts(path), expected);

  const auto left = readTopic<sensor_msgs::Image>(path, "/stereo_camera/left/image_rect");
  const auto right = readTopic<sensor_msgs::Image>(path, "/stereo_camera/right/image_rect");
  const auto rightInfo = readTopic<sensor_msgs::CameraInfo>(path, "/stereo_camera/right/camera_info");
  EXPECT_EQ(left[2].msg.header.frame_id, "camera_left_optical_frame");
  EXPECT_EQ(right[2].msg.header.frame_id, "camera_right_optical_frame");
  EXPECT_EQ(right[2].time, ros::Time(1400000000.2));
  EXPECT_TRUE(sameBits(*imageFromMsg(right[2].msg), randomImage(48, 64, CV_8UC1, 11)));
  EXPECT_DOUBLE_EQ(rightInfo[0].msg.P[3], -60.0 * 0.12);

  const tf2_msgs::TFMessage st = readTopic<tf2_msgs::TFMessage>(path, "/tf_static")[0].msg;
  EXPECT_TRUE(staticChain(st, "camera_left_optical_frame").toEigen().isApprox(kCamera.toEigen(), 1e-9));
  const Transform rightInLeft =
      staticChain(st, "camera_left_optical_frame").inverse() * staticChain(st, "camera_right_optical_frame");
  EXPECT_TRUE(rightInLeft.toEigen().isApprox(Transform(0.12, 0, 0, 0, 0, 0).toEigen(), 1e-9));
  EXPECT_NEAR(staticChain(st, "velodyne").z(), 1.7, 1e-12);

  const auto clouds = readTopic<sensor_msgs::PointCloud2>(path, "/velodyne_points");
  EXPECT_EQ(clouds[0].msg.header.frame_id, "velodyne");
  EXPECT_EQ(clouds[0].msg.width, 100u);
}

TEST_F(DatasetBagTest, ChangedMountingRewritesTfStaticAndOffsetsAreHonoured) {
  DatasetRecord a = rgbdLaserFrame(5.0, 1);
  DatasetRecord b = rgbdLaserFrame(5.1, 2);
  const Transform moved(0.3, 0.0, 0.3, 0.0, 0.0, 0.0);
  LaserScan scan = b.data.laserScanRaw();
  scan.setLocalTransform(moved);
  b.data.setLaserScan(scan);
  ScriptedReader reader({a, b});
  BagWriterOptions options;
  options.timeOffset = 100.0;
  options.compression = "lz4";
  const BagSummary summary = convertDatasetToBag(reader, path, options);
  EXPECT_EQ(summary.timeOffset, 100.0);
  const auto statics = readTopic<tf2_msgs::TFMessage>(path, "/tf_static");
  ASSERT_EQ(statics.size(), 2u);
  EXPECT_EQ(statics[1].time, ros::Time(105.1) - ros::Duration(0, 1000));
  // The second message is complete (camera too): late subscribers of the latched topic get all.
  EXPECT_TRUE(staticChain(statics[1].msg, "laser").toEigen().isApprox(moved.toEigen(), 1e-12));
  EXPECT_FALSE(staticChain(statics[1].msg, "camera_rgb_optical_frame").isNull());
  EXPECT_EQ(readTopic<sensor_msgs::LaserScan>(path, "/scan")[0].msg.header.stamp, ros::Time(105.0));
}

TEST_F(DatasetBagTest, SensorsStartingJustAfterTheFirstFrameAreInTheFirstTfStatic) {
  // The IMU starts 5 ms after the first image (as the simulator's does): still one /tf_static.
  std::vector<DatasetRecord> records = {rgbdLaserFrame(10.0, 1), imuRecord(10.005)};
  for (int i = 1; i <= 15; ++i) records.push_back(rgbdLaserFrame(10.0 + 0.1 * i, i + 1));
  ScriptedReader early(records);
  convertDatasetToBag(early, path);
  auto statics = readTopic<tf2_msgs::TFMessage>(path, "/tf_static");
  ASSERT_EQ(statics.size(), 1u);
  EXPECT_FALSE(staticChain(statics[0].msg, "imu_link").isNull());
  EXPECT_FALSE(staticChain(statics[0].msg, "laser").isNull());

  // A sensor that first speaks after the first second: a second, complete /tf_static then.
  records.push_back(imuRecord(12.0));
  ScriptedReader late(std::vector<DatasetRecord>(records.begin() + 2, records.end()));
  convertDatasetToBag(late, path);
  statics = readTopic<tf2_msgs::TFMessage>(path, "/tf_static");
  ASSERT_EQ(statics.size(), 2u);
  EXPECT_TRUE(staticChain(statics[0].msg, "imu_link").isNull());
  EXPECT_FALSE(staticChain(statics[1].msg, "imu_link").isNull());
  EXPECT_FALSE(staticChain(statics[1].msg, "camera_rgb_optical_frame").isNull());
  EXPECT_EQ(statics[1].time, ros::Time(12.0) - ros::Duration(0, 1000));
}

TEST_F(DatasetBagTest, AScanWithoutReturnsIsStillPublishedWithItsMounting) {
  DatasetRecord open;
  open.stamp = 20.0;
  open.data = SensorData(LaserScan::fromRanges(std::vector<float>(181, std::numeric_limits<float>::infinity()),
                                               -M_PI / 2, M_PI / 180, 0.1, 20.0, kLaser));
  ScriptedReader reader({open});
  convertDatasetToBag(reader, path);
  const auto scans = readTopic<sensor_msgs::LaserScan>(path, "/scan");
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_EQ(scans[0].msg.ranges, std::vector<float>(181, std::numeric_limits<float>::infinity()));
  const auto statics = readTopic<tf2_msgs::TFMessage>(path, "/tf_static");
  ASSERT_EQ(statics.size(), 1u);
  EXPECT_TRUE(staticChain(statics[0].msg, "laser").toEigen().isApprox(kLaser.toEigen(), 1e-12));
}

TEST_F(DatasetBagTest, OutOfOrderRecordsAreCountedAndBagPlaysThemInOrder) {
  ScriptedReader reader({odomRecord(10.0, 0.0), odomRecord(10.2, 2.0), odomRecord(10.1, 1.0), rgbdLaserFrame(10.3, 1)});
  const BagSummary summary = convertDatasetToBag(reader, path);
  EXPECT_EQ(summary.outOfOrder, 1u);
  const auto odom = readTopic<nav_msgs::Odometry>(path, "/odom");
  ASSERT_EQ(odom.size(), 4u);
  for (size_t i = 1; i < odom.size(); ++i) EXPECT_LT(odom[i - 1].time, odom[i].time);
}

TEST_F(DatasetBagTest, RecordsWithoutAFrameStillEndUpInTheBag) {
  ScriptedReader reader({imuRecord(2.0), imuRecord(2.005)});
  const BagSummary summary = convertDatasetToBag(reader, path);
  EXPECT_EQ(summary.messagesPerTopic.at("/imu/data"), 2u);
  EXPECT_EQ(summary.messagesPerTopic.at("/tf_static"), 1u);
}

TEST_F(DatasetBagTest, BadInputsAreErrors) {
  BagWriterOptions badCompression;
  badCompression.compression = "zip";
  EXPECT_THROW(DatasetBagWriter(path, badCompression), rtabmap::Error);
  EXPECT_THROW(DatasetBagWriter(dir.file("missing/dir/out.bag")), rtabmap::Error);

  DatasetRecord twoCameras;
  twoCameras.stamp = 3.0;
  twoCameras.data = SensorData(randomImage(48, 128, CV_8UC3), cv::Mat(),
                               std::vector<CameraModel>{CameraModel(50, 50, 32, 24), CameraModel(50, 50, 32, 24)});
  DatasetBagWriter writer(path);
  EXPECT_THROW(writer.add(twoCameras), rtabmap::FormatError);
  // The bag layout has one stereo pair of topics: two stereo cameras are refused, not cut to one.
  DatasetRecord twoStereo;
  twoStereo.stamp = 3.0;
  const rtabmap::StereoCameraModel stereo(50, 50, 32, 24, 0.1, CameraModel::opticalRotation(), cv::Size(64, 48));
  twoStereo.data = SensorData(randomImage(48, 128, CV_8UC1), randomImage(48, 128, CV_8UC1),
                              std::vector<rtabmap::StereoCameraModel>{stereo, stereo});
  try {
    writer.add(twoStereo);
    ADD_FAILURE() << "two stereo cameras were written to the bag";
  } catch (const rtabmap::FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("2 stereo cameras"), std::string::npos) << e.what();
  }

  DatasetRecord nanStamp = rgbdLaserFrame(3.0, 1);
  nanStamp.stamp = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(writer.add(nanStamp), rtabmap::FormatError);
  writer.close();
}
