// The scan a new node keeps (Mem/LaserScan*): thinned, voxelised, with normals, still in its
// sensor's frame; and a SLAM node made with the filters keeps that scan.
#include "rtabmap_core/registration/ScanFilter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "common/TestData.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/slam/Rtabmap.h"

namespace rtabmap {
namespace {

// A wall 1 m in front of a 3D sensor: a 1 m x 1 m square of points 1 cm apart, in the sensor
// frame (x forward), sensor mounted 0.5 m up and turned by 0.3 rad on the robot.
const Transform kMount(0.1, 0.0, 0.5, 0.0, 0.0, 0.3);

LaserScan wall3D() {
  std::vector<cv::Vec3f> points;
  for (int i = 0; i < 100; ++i) {
    for (int j = 0; j < 100; ++j) points.emplace_back(1.0f, -0.5f + 0.01f * i, -0.5f + 0.01f * j);
  }
  points.emplace_back(NAN, 0.0f, 0.0f);
  cv::Mat data(1, static_cast<int>(points.size()), CV_32FC3, points.data());
  return LaserScan(data.clone(), static_cast<int>(points.size()), 0.1, 30.0, LaserScan::kXYZ, kMount);
}

// A planar scan of a square room 4 m wide around the sensor, 0.25 degree beams.
LaserScan room2D(const Transform& mount) {
  std::vector<float> ranges;
  const double increment = M_PI / 720.0;
  for (int i = 0; i < 1440; ++i) {
    const double a = -M_PI + i * increment;
    ranges.push_back(static_cast<float>(2.0 / std::max(std::fabs(std::cos(a)), std::fabs(std::sin(a)))));
  }
  return LaserScan::fromRanges(ranges, -M_PI, increment, 0.1, 30.0, mount);
}

Eigen::Vector3f point(const LaserScan& scan, int i) {
  const float* v = scan.data().ptr<float>(0) + static_cast<size_t>(i) * LaserScan::channels(scan.format());
  return Eigen::Vector3f(v[0], v[1], scan.is2d() ? 0.0f : v[2]);
}

Eigen::Vector3f normal(const LaserScan& scan, int i) {
  const int cn = LaserScan::channels(scan.format());
  const float* v = scan.data().ptr<float>(0) + static_cast<size_t>(i) * cn + cn - 3;
  return Eigen::Vector3f(v[0], v[1], v[2]);
}

TEST(ScanFilter, VoxelGridAndNormalsKeepTheSensorFrameAndItsMount) {
  const LaserScan scan = wall3D();
  ScanFilterOptions o;
  o.voxelSize = 0.1f;
  o.normalK = 10;
  std::string why;
  const LaserScan out = filterScan(scan, o, &why);
  ASSERT_FALSE(out.empty()) << why;
  EXPECT_EQ(out.format(), LaserScan::kXYZNormal);
  EXPECT_TRUE(out.localTransform().toEigen().isApprox(kMount.toEigen()));
  EXPECT_DOUBLE_EQ(out.rangeMin(), 0.1);
  EXPECT_DOUBLE_EQ(out.rangeMax(), 30.0);
  // 10 x 10 voxels of the 1 m square, a few more: the voxels are aligned with the robot's
  // frame, where the wall is turned by the mount's yaw (128 here).
  EXPECT_GE(out.size(), 100);
  EXPECT_LE(out.size(), 160);
  // maxPoints scaled by what the filter kept, for ICP's correspondence ratio.
  EXPECT_NEAR(out.maxPoints(), scan.maxPoints() * out.size() / 10000.0, 2.0);
  for (int i = 0; i < out.size(); ++i) {
    const Eigen::Vector3f p = point(out, i);
    EXPECT_NEAR(p.x(), 1.0f, 1e-4) << i;  // still on the wall, in the sensor frame
    EXPECT_LE(std::fabs(p.y()), 0.5f);
    EXPECT_NEAR(std::fabs(normal(out, i).x()), 1.0f, 1e-3) << "normal of the wall, sensor frame";
    EXPECT_LT(normal(out, i).x(), 0.0f) << "towards the sensor";
  }
}

TEST(ScanFilter, APlanarScanStaysPlanarInItsSensorFrame) {
  const Transform mount(0.2, 0.0, 0.3, 0.0, 0.0, 0.0);
  const LaserScan scan = room2D(mount);
  ScanFilterOptions o;
  o.downsampleStep = 2;
  o.voxelSize = 0.05f;
  o.normalK = 5;
  std::string why;
  const LaserScan out = filterScan(scan, o, &why);
  ASSERT_FALSE(out.empty()) << why;
  EXPECT_EQ(out.format(), LaserScan::kXYNormal);
  EXPECT_TRUE(out.localTransform().toEigen().isApprox(mount.toEigen()));
  EXPECT_LT(out.size(), scan.size() / 2);
  EXPECT_GT(out.size(), 200);  // 16 m of wall at 5 cm voxels: ~320
  for (int i = 0; i < out.size(); ++i) {
    const Eigen::Vector3f p = point(out, i);
    // On the room's walls, 2 m from the sensor along x or y.
    EXPECT_NEAR(std::max(std::fabs(p.x()), std::fabs(p.y())), 2.0f, 0.03f) << i;
    const Eigen::Vector3f n = normal(out, i);
    EXPECT_NEAR(n.z(), 0.0f, 1e-6);
    EXPECT_NEAR(n.norm(), 1.0f, 1e-3);
  }
}

TEST(ScanFilter, NothingLeftSaysWhyAndInactiveOptionsAreNotApplied) {
  std::string why;
  EXPECT_TRUE(filterScan(LaserScan(), ScanFilterOptions{1, 0.1f, 0, 0.0f}, &why).empty());
  EXPECT_NE(why.find("empty"), std::string::npos) << why;
  std::vector<cv::Vec3f> nans(5, cv::Vec3f(NAN, NAN, NAN));
  const LaserScan allNan(cv::Mat(1, 5, CV_32FC3, nans.data()).clone(), 5, 0, 0, LaserScan::kXYZ);
  EXPECT_TRUE(filterScan(allNan, ScanFilterOptions{1, 0.1f, 0, 0.0f}, &why).empty());
  EXPECT_NE(why.find("finite"), std::string::npos) << why;
  EXPECT_FALSE(ScanFilterOptions().active());
  EXPECT_TRUE((ScanFilterOptions{2, 0.0f, 0, 0.0f}.active()));
  EXPECT_TRUE((ScanFilterOptions{1, 0.0f, 0, 0.2f}.active()));
  EXPECT_THROW(ScanFilterOptions::fromParameters({{"Mem/LaserScanDownsampleStepSize", "0"}}), ParameterError);
  const ScanFilterOptions read = ScanFilterOptions::fromParameters(
      {{"Mem/LaserScanVoxelSize", "0.1"}, {"Mem/LaserScanNormalK", "20"}});
  EXPECT_FLOAT_EQ(read.voxelSize, 0.1f);
  EXPECT_EQ(read.normalK, 20);
}

TEST(ScanFilter, ANodeKeepsTheFilteredScan) {
  test::TempDir dir("rtabmap_scan_filter");
  const ParametersMap p = {{"Rtabmap/DetectionRate", "0"},   {"Kp/MaxFeatures", "-1"},
                           {"Mem/LaserScanVoxelSize", "0.1"}, {"Mem/LaserScanNormalK", "10"},
                           {"RGBD/ProximityBySpace", "false"}};
  Rtabmap slam;
  slam.init(p, dir.file("rtabmap.db"));
  ASSERT_TRUE(slam.process(SensorData(wall3D(), 1, 1.0), Transform::Identity()));
  const int id = slam.statistics().refImageId;
  ASSERT_GT(id, 0);
  NodeDataParts parts;
  parts.scan = true;
  const std::optional<Signature> node = slam.node(id, parts);
  ASSERT_TRUE(node.has_value());
  SensorData data = node->sensorData();
  if (data.laserScanRaw().empty()) data.uncompress(false, false, true, false);
  const LaserScan& kept = data.laserScanRaw();
  EXPECT_EQ(kept.format(), LaserScan::kXYZNormal);
  EXPECT_LE(kept.size(), 160);
  EXPECT_TRUE(kept.localTransform().toEigen().isApprox(kMount.toEigen()));
}

}  // namespace
}  // namespace rtabmap
