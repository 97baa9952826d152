#include "rtabmap_core/geometry/SensorData.h"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>

#include "common/TestData.h"
#include "rtabmap_core/common/Error.h"

using rtabmap::Bytes;
using rtabmap::CameraModel;
using rtabmap::FormatError;
using rtabmap::LaserScan;
using rtabmap::SensorData;
using rtabmap::StereoCameraModel;
using rtabmap::Transform;

namespace {

cv::Mat colourImage(int rows = 480, int cols = 640) {
  cv::Mat m(rows, cols, CV_8UC3);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      m.at<cv::Vec3b>(r, c) = cv::Vec3b(cv::saturate_cast<uchar>(128 + 100 * std::sin(0.03 * c)),
                                        cv::saturate_cast<uchar>(128 + 100 * std::cos(0.04 * r)),
                                        cv::saturate_cast<uchar>((r + c) / 5));
  return m;
}

cv::Mat depthMm(int rows = 480, int cols = 640) {
  cv::Mat m(rows, cols, CV_16UC1);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) m.at<uint16_t>(r, c) = static_cast<uint16_t>(500 + 7 * r + 3 * c);
  m(cv::Rect(0, 0, 10, 10)).setTo(0);
  m(cv::Rect(20, 20, 5, 5)).setTo(65535);
  return m;
}

LaserScan makeScan() {
  cv::Mat data(1, 360, CV_32FC(4));
  cv::Mat flat = data.reshape(1);
  cv::randu(flat, cv::Scalar(-20), cv::Scalar(20));
  return LaserScan(data, 720, 0.5, 30.0, LaserScan::kXYZI, Transform(0.1, 0.0, 0.4, 0, 0, 0.2));
}

bool identical(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != b.type()) return false;
  if (a.empty()) return true;
  for (int r = 0; r < a.rows; ++r)
    if (std::memcmp(a.ptr(r), b.ptr(r), a.cols * a.elemSize()) != 0) return false;
  return true;
}

const CameraModel kCamera(525, 525, 319.5, 239.5, CameraModel::opticalRotation(), 0, cv::Size(640, 480));

}  // namespace

TEST(SensorData, Constructors) {
  const SensorData empty;
  EXPECT_EQ(empty.id(), 0);
  EXPECT_TRUE(empty.imageRaw().empty());
  EXPECT_TRUE(empty.odomPose().isNull());
  EXPECT_TRUE(empty.groundTruth().isNull());
  EXPECT_FALSE(empty.isStereo());
  EXPECT_TRUE(empty.laserScanRaw().empty());
  EXPECT_TRUE(empty.imu().empty());

  const cv::Mat rgb = colourImage(), depth = depthMm();
  const SensorData rgbd(rgb, depth, kCamera, 7, 12.5);
  EXPECT_EQ(rgbd.id(), 7);
  EXPECT_DOUBLE_EQ(rgbd.stamp(), 12.5);
  EXPECT_EQ(rgbd.imageRaw().data, rgb.data);
  EXPECT_EQ(rgbd.depthOrRightRaw().data, depth.data);
  ASSERT_EQ(rgbd.cameraModels().size(), 1u);
  EXPECT_DOUBLE_EQ(rgbd.cameraModels()[0].fx(), 525);
  EXPECT_FALSE(rgbd.isStereo());

  const SensorData multi(cv::Mat(480, 1280, CV_8UC3), cv::Mat(480, 1280, CV_16UC1),
                         std::vector<CameraModel>{kCamera, kCamera}, 1, 2.0);
  EXPECT_EQ(multi.cameraModels().size(), 2u);
  EXPECT_THROW(SensorData(cv::Mat(480, 1281, CV_8UC3), cv::Mat(480, 1281, CV_16UC1),
                          std::vector<CameraModel>{kCamera, kCamera}),
               FormatError);
  EXPECT_THROW(SensorData(rgb, cv::Mat(480, 640, CV_8UC1), kCamera), FormatError);

  const StereoCameraModel stereo(435, 435, 367, 252, 0.11, CameraModel::opticalRotation(), cv::Size(752, 480));
  const cv::Mat left(480, 752, CV_8UC1, cv::Scalar(10)), right(480, 752, CV_8UC1, cv::Scalar(20));
  const SensorData s(left, right, stereo, 3, 4.0);
  EXPECT_TRUE(s.isStereo());
  EXPECT_TRUE(s.cameraModels().empty());
  ASSERT_EQ(s.stereoCameraModels().size(), 1u);
  EXPECT_NEAR(s.stereoCameraModels()[0].baseline(), 0.11, 1e-12);
  EXPECT_THROW(SensorData(left, cv::Mat(480, 752, CV_16UC1), stereo), FormatError);

  // Several stereo cameras: left images side by side, right images the same way.
  const cv::Mat lefts(480, 1504, CV_8UC3, cv::Scalar(10)), rights(480, 1504, CV_8UC1, cv::Scalar(20));
  const SensorData two(lefts, rights, std::vector<StereoCameraModel>{stereo, stereo}, 3, 4.0);
  EXPECT_TRUE(two.isStereo());
  EXPECT_EQ(two.stereoCameraModels().size(), 2u);
  EXPECT_TRUE(two.cameraModels().empty());
  EXPECT_THROW(SensorData(cv::Mat(480, 1505, CV_8UC1), cv::Mat(480, 1505, CV_8UC1),
                          std::vector<StereoCameraModel>{stereo, stereo}),
               FormatError);
  EXPECT_THROW(SensorData(lefts, right, std::vector<StereoCameraModel>{stereo, stereo}), FormatError);
  // Models alone (a node loaded without its images), or the left images alone, are fine.
  SensorData modelsOnly;
  modelsOnly.setStereoImage(cv::Mat(), cv::Mat(), std::vector<StereoCameraModel>{stereo, stereo});
  EXPECT_EQ(modelsOnly.stereoCameraModels().size(), 2u);
  modelsOnly.setStereoImage(lefts, cv::Mat(), std::vector<StereoCameraModel>{stereo, stereo});
  EXPECT_EQ(modelsOnly.imageRaw().cols, 1504);

  const LaserScan scan = makeScan();
  const SensorData l(scan, 5, 6.0);
  EXPECT_EQ(l.laserScanRaw().size(), 360);
  EXPECT_TRUE(l.imageRaw().empty());
  const SensorData lr(scan, rgb, depth, kCamera, 8, 9.0);
  EXPECT_EQ(lr.laserScanRaw().size(), 360);
  EXPECT_EQ(lr.cameraModels().size(), 1u);
}

TEST(SensorData, Setters) {
  SensorData d;
  Eigen::Matrix<double, 6, 6> cov = Eigen::Matrix<double, 6, 6>::Identity() * 0.01;
  d.setOdom(Transform(1, 2, 0.3), cov);
  EXPECT_DOUBLE_EQ(d.odomPose().x(), 1);
  EXPECT_EQ(d.odomCovariance()(0, 0), 0.01);
  d.setGroundTruth(Transform(3, 4, 0));
  EXPECT_DOUBLE_EQ(d.groundTruth().y(), 4);
  rtabmap::GPS gps;
  gps.stamp = 1;
  gps.latitude = 45.5;
  d.setGPS(gps);
  EXPECT_DOUBLE_EQ(d.gps().latitude, 45.5);
  rtabmap::IMU imu;
  imu.angularVelocity = Eigen::Vector3d(0, 0, 0.1);
  d.setIMU(imu);
  EXPECT_FALSE(d.imu().empty());
  std::vector<cv::KeyPoint> kps(3, cv::KeyPoint(1, 2, 3));
  d.setFeatures(kps, std::vector<cv::Point3f>(3), cv::Mat(3, 32, CV_8UC1, cv::Scalar(1)));
  EXPECT_EQ(d.keypoints().size(), 3u);
  EXPECT_THROW(d.setFeatures(kps, std::vector<cv::Point3f>(2), cv::Mat()), FormatError);
  EXPECT_THROW(d.setFeatures(kps, {}, cv::Mat(2, 32, CV_8UC1)), FormatError);
  rtabmap::LocalGrid grid;
  grid.obstacles = cv::Mat(1, 10, CV_32FC2, cv::Scalar(1, 2));
  grid.cellSize = 0.05f;
  d.setLocalGrid(grid);
  EXPECT_FALSE(d.localGrid().isEmpty());
}

TEST(SensorData, CompressUncompressRgbd) {
  const cv::Mat rgb = colourImage(), depth = depthMm();
  SensorData d(rgb, depth, kCamera, 1, 1.0);
  d.compress();  // jpg colour, png depth
  ASSERT_FALSE(d.imageCompressed().empty());
  ASSERT_FALSE(d.depthOrRightCompressed().empty());
  EXPECT_LT(d.imageCompressed().size(), rgb.total() * 3 / 4);
  // Raw kept after compress.
  EXPECT_EQ(d.imageRaw().data, rgb.data);
  d.clearRaw();
  EXPECT_TRUE(d.imageRaw().empty());
  EXPECT_TRUE(d.depthOrRightRaw().empty());
  d.uncompress();
  ASSERT_EQ(d.imageRaw().type(), CV_8UC3);
  ASSERT_EQ(d.imageRaw().size(), rgb.size());
  cv::Mat diff;
  cv::absdiff(d.imageRaw(), rgb, diff);
  EXPECT_LT(cv::mean(diff)[0], 2.0);
  EXPECT_TRUE(identical(d.depthOrRightRaw(), depth));

  // Float depth: bit-exact, NaN included.
  cv::Mat metres;
  depth.convertTo(metres, CV_32F, 0.001);
  metres.at<float>(5, 5) = std::numeric_limits<float>::quiet_NaN();
  SensorData f(rgb, metres, kCamera);
  f.compress(".png");
  f.clearRaw();
  f.uncompress();
  EXPECT_TRUE(identical(f.imageRaw(), rgb));  // png colour is lossless
  EXPECT_TRUE(identical(f.depthOrRightRaw(), metres));
}

TEST(SensorData, UncompressOnlyWhatIsAsked) {
  SensorData d(colourImage(), depthMm(), kCamera);
  d.setLaserScan(makeScan());
  d.setUserData(cv::Mat(1, 10, CV_8UC1, cv::Scalar(3)));
  d.compress();
  d.clearRaw();
  d.uncompress(false, true, false, false);
  EXPECT_TRUE(d.imageRaw().empty());
  EXPECT_FALSE(d.depthOrRightRaw().empty());
  EXPECT_TRUE(d.laserScanRaw().empty());
  EXPECT_TRUE(d.userDataRaw().empty());
  d.uncompress();
  EXPECT_FALSE(d.imageRaw().empty());
  EXPECT_FALSE(d.laserScanRaw().empty());
  EXPECT_FALSE(d.userDataRaw().empty());
}

TEST(SensorData, CompressStereoRightIsLossless) {
  const StereoCameraModel stereo(435, 435, 367, 252, 0.11, CameraModel::opticalRotation(), cv::Size(752, 480));
  cv::Mat left(480, 752, CV_8UC1), right(480, 752, CV_8UC1);
  cv::randu(left, 0, 255);
  cv::randu(right, 0, 255);
  SensorData d(left, right, stereo);
  d.compress(".jpg");
  d.clearRaw();
  d.uncompress();
  ASSERT_EQ(d.imageRaw().type(), CV_8UC1);
  EXPECT_EQ(d.imageRaw().size(), left.size());
  EXPECT_TRUE(identical(d.depthOrRightRaw(), right));
}

TEST(SensorData, CompressScanAndUserDataBitExact) {
  const LaserScan scan = makeScan();
  SensorData d(scan, 1, 2.0);
  cv::Mat user(3, 7, CV_64FC2);
  cv::randu(user, -1e6, 1e6);
  d.setUserData(user);
  d.compress();
  ASSERT_FALSE(d.laserScanCompressed().empty());
  ASSERT_FALSE(d.userDataCompressed().empty());
  const SensorData::ScanInfo info = d.laserScanInfo();
  EXPECT_EQ(info.format, LaserScan::kXYZI);
  EXPECT_EQ(info.maxPoints, 720);
  EXPECT_DOUBLE_EQ(info.rangeMin, 0.5);
  EXPECT_DOUBLE_EQ(info.rangeMax, 30.0);
  EXPECT_EQ(info.localTransform, scan.localTransform());
  d.clearRaw();
  EXPECT_TRUE(d.laserScanRaw().empty());
  EXPECT_EQ(d.laserScanInfo().format, LaserScan::kXYZI);  // kept for the compressed scan
  d.uncompress();
  EXPECT_TRUE(identical(d.laserScanRaw().data(), scan.data()));
  EXPECT_EQ(d.laserScanRaw().format(), scan.format());
  EXPECT_EQ(d.laserScanRaw().maxPoints(), 720);
  EXPECT_DOUBLE_EQ(d.laserScanRaw().rangeMin(), 0.5);
  EXPECT_DOUBLE_EQ(d.laserScanRaw().rangeMax(), 30.0);
  EXPECT_EQ(d.laserScanRaw().localTransform(), scan.localTransform());
  EXPECT_TRUE(identical(d.userDataRaw(), user));
}

TEST(SensorData, SetCompressedAsFromDatabase) {
  // What the database does: bytes and scan metadata stored separately, raw rebuilt on demand.
  SensorData src(makeScan(), colourImage(), depthMm(), kCamera);
  src.compress();
  SensorData loaded;
  loaded.setCompressed(src.imageCompressed(), src.depthOrRightCompressed(), src.laserScanCompressed(),
                       src.userDataCompressed());
  loaded.setLaserScanInfo(src.laserScanInfo());
  EXPECT_EQ(loaded.laserScanInfo().maxPoints, 720);
  loaded.uncompress();
  EXPECT_TRUE(identical(loaded.depthOrRightRaw(), src.depthOrRightRaw()));
  EXPECT_TRUE(identical(loaded.laserScanRaw().data(), src.laserScanRaw().data()));
  EXPECT_EQ(loaded.laserScanRaw().localTransform(), src.laserScanRaw().localTransform());
  loaded.clearCompressed();
  EXPECT_TRUE(loaded.imageCompressed().empty());
  EXPECT_TRUE(loaded.laserScanCompressed().empty());
  EXPECT_FALSE(loaded.imageRaw().empty());
}

TEST(SensorData, UncompressCorruptBytesThrows) {
  SensorData src(makeScan(), colourImage(), depthMm(), kCamera);
  src.setUserData(cv::Mat(4, 4, CV_32FC1, cv::Scalar(2)));
  src.compress();
  const Bytes garbage{1, 2, 3, 4, 5, 6, 7, 8, 9};
  auto truncated = [](const Bytes& b) { return Bytes(b.begin(), b.begin() + b.size() / 2); };
  {
    SensorData d;
    d.setCompressed(garbage, {}, {}, {});
    EXPECT_THROW(d.uncompress(), FormatError);
  }
  {
    SensorData d;
    d.setCompressed(truncated(src.imageCompressed()), {}, {}, {});
    EXPECT_THROW(d.uncompress(), FormatError);
  }
  {
    SensorData d;
    d.setCompressed({}, truncated(src.depthOrRightCompressed()), {}, {});
    EXPECT_THROW(d.uncompress(), FormatError);
  }
  {
    SensorData d;
    d.setCompressed({}, garbage, {}, {});
    EXPECT_THROW(d.uncompress(), FormatError);
  }
  {
    SensorData d;
    d.setCompressed({}, {}, truncated(src.laserScanCompressed()), {});
    d.setLaserScanInfo(src.laserScanInfo());
    EXPECT_THROW(d.uncompress(), FormatError);
  }
  {
    // Scan bytes with metadata of another format: the channel count disagrees.
    SensorData d;
    d.setCompressed({}, {}, src.laserScanCompressed(), {});
    SensorData::ScanInfo info = src.laserScanInfo();
    info.format = LaserScan::kXY;
    d.setLaserScanInfo(info);
    EXPECT_THROW(d.uncompress(), FormatError);
  }
  {
    SensorData d;
    d.setCompressed({}, {}, {}, truncated(src.userDataCompressed()));
    EXPECT_THROW(d.uncompress(), FormatError);
  }
}

TEST(SensorData, DepthAt) {
  cv::Mat mm(2, 3, CV_16UC1);
  mm.at<uint16_t>(0, 0) = 1234;
  mm.at<uint16_t>(0, 1) = 0;
  mm.at<uint16_t>(0, 2) = 65535;  // 7-Scenes "invalid"
  mm.at<uint16_t>(1, 0) = 65534;
  EXPECT_FLOAT_EQ(SensorData::depthAt(mm, 0, 0), 1.234f);
  EXPECT_EQ(SensorData::depthAt(mm, 1, 0), 0.0f);
  EXPECT_EQ(SensorData::depthAt(mm, 2, 0), 0.0f);
  EXPECT_FLOAT_EQ(SensorData::depthAt(mm, 0, 1), 65.534f);
  EXPECT_EQ(SensorData::depthAt(mm, -1, 0), 0.0f);
  EXPECT_EQ(SensorData::depthAt(mm, 3, 0), 0.0f);
  EXPECT_EQ(SensorData::depthAt(mm, 0, 2), 0.0f);
  EXPECT_EQ(SensorData::depthAt(cv::Mat(), 0, 0), 0.0f);

  cv::Mat m(1, 5, CV_32FC1);
  m.at<float>(0, 0) = 2.5f;
  m.at<float>(0, 1) = std::numeric_limits<float>::quiet_NaN();
  m.at<float>(0, 2) = 0.0f;
  m.at<float>(0, 3) = -1.0f;
  m.at<float>(0, 4) = std::numeric_limits<float>::infinity();
  EXPECT_EQ(SensorData::depthAt(m, 0, 0), 2.5f);
  for (int u = 1; u < 5; ++u) EXPECT_EQ(SensorData::depthAt(m, u, 0), 0.0f) << u;
  EXPECT_THROW(SensorData::depthAt(cv::Mat(2, 2, CV_8UC1, cv::Scalar(1)), 0, 0), FormatError);
}

TEST(SensorData, Real7ScenesDepthAt) {
  RTABMAP_REQUIRE_DATA(path, "rgbd_7scenes/frame-000000.depth.png");
  std::ifstream f(path, std::ios::binary);
  const Bytes bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const cv::Mat depth = rtabmap::codec::uncompressDepth(bytes);
  int valid = 0, invalid = 0;
  for (int v = 0; v < depth.rows; v += 4) {
    for (int u = 0; u < depth.cols; u += 4) {
      const float d = SensorData::depthAt(depth, u, v);
      if (d > 0) {
        ++valid;
        EXPECT_LT(d, 10.0f) << "a Kinect does not see " << d << " m";
      } else {
        ++invalid;
      }
    }
  }
  EXPECT_GT(valid, invalid);
}

TEST(SensorData, MemoryUsed) {
  SensorData d(colourImage(), depthMm(), kCamera);
  const size_t raw = d.memoryUsed();
  EXPECT_GE(raw, 640u * 480u * 3u + 640u * 480u * 2u);
  d.compress();
  const size_t both = d.memoryUsed();
  EXPECT_GT(both, raw);
  d.clearRaw();
  const size_t compressed = d.memoryUsed();
  EXPECT_LT(compressed, raw);
  EXPECT_GE(compressed, d.imageCompressed().size() + d.depthOrRightCompressed().size());
  EXPECT_LT(SensorData().memoryUsed(), 10000u);
}

TEST(SensorData, SetImagesClearsStaleCompressed) {
  SensorData d(colourImage(), depthMm(), kCamera);
  d.compress();
  ASSERT_FALSE(d.imageCompressed().empty());
  d.setRGBDImage(colourImage(240, 320), depthMm(240, 320), {kCamera.scaled(0.5)});
  EXPECT_TRUE(d.imageCompressed().empty());
  EXPECT_TRUE(d.depthOrRightCompressed().empty());
}
