// Gravity links through the SLAM pipeline (Mem/UseOdomGravity, Optimizer/GravitySigma): a loop
// closure whose rotation is tilted must not tilt a map whose odometry knows where down is.
#include <gtest/gtest.h>

#include <cmath>

#include "common/TestData.h"
#include "rtabmap_core/slam/Rtabmap.h"

namespace rtabmap {
namespace {

using Cov = Eigen::Matrix<double, 6, 6>;

// A node with a small planar scan (no camera needed) and, with `imu`, the orientation an IMU
// filter gives: level, the IMU mounted upside down under the base.
SensorData frame(int id, double stamp, bool imu) {
  cv::Mat points(1, 3, CV_32FC2);
  for (int i = 0; i < 3; ++i) points.at<cv::Vec2f>(0, i) = cv::Vec2f(1.0f + i, 0.5f * id);
  SensorData data(LaserScan(points, 3, 0.1, 10.0, LaserScan::kXY), id, stamp);
  if (imu) {
    IMU reading;
    reading.localTransform = Transform(0, 0, -0.1, M_PI, 0, 0);
    reading.orientation = reading.localTransform.quaternion();  // the base is level
    data.setIMU(reading);
  }
  return data;
}

// Largest tilt (angle between the node's up axis and the world's) of the optimised map.
double largestTilt(const std::map<int, Transform>& poses) {
  double worst = 0.0;
  for (const auto& [id, p] : poses) {
    (void)id;
    const Eigen::Vector3d up = p.rotationMatrix() * Eigen::Vector3d::UnitZ();
    worst = std::max(worst, std::acos(std::min(1.0, up.z())));
  }
  return worst;
}

// Level odometry along x, 11 nodes 0.5 m apart (1 cm, 0.01 rad per motion), then a loop
// closure from node 1 to node 11 that is 5 m long, as odometry says, but pitched by 0.05 rad
// (a visual registration's rotation error) and confident about it.
std::map<int, Transform> mapWithTiltedClosure(const ParametersMap& extra, bool* accepted, int* gravityLinks,
                                              bool imu = false) {
  ParametersMap p = {{"Rtabmap/DetectionRate", "0"}, {"Mem/UseOdomGravity", "true"}};
  for (const auto& [k, v] : extra) p[k] = v;
  Rtabmap slam;
  slam.init(p, "");
  for (int i = 0; i <= 10; ++i) {
    EXPECT_TRUE(slam.process(frame(i + 1, i + 1.0, imu), Transform(0.5 * i, 0, 0, 0, 0, 0), Cov::Identity() * 1e-4));
  }
  *gravityLinks = 0;
  for (const auto& [from, link] : slam.localLinks()) *gravityLinks += link.type() == Link::kGravity && link.to() == from;
  const Link tilted(1, 11, Link::kUserClosure, Transform(5.0, 0, 0, 0, 0.05, 0), Link::InfMatrix::Identity() * 1e4);
  *accepted = slam.addLink(tilted);
  return slam.optimizedPoses();
}

TEST(Gravity, GravityLinksKeepTheMapLevelAgainstATiltedLoopClosure) {
  bool accepted = false;
  int gravityLinks = 0;
  const ParametersMap noCheck = {{"RGBD/OptimizeMaxError", "0"}};

  const std::map<int, Transform> free = mapWithTiltedClosure(noCheck, &accepted, &gravityLinks);
  ASSERT_TRUE(accepted);
  EXPECT_EQ(gravityLinks, 11) << "one gravity link per node";
  const double tiltFree = largestTilt(free);
  EXPECT_GT(tiltFree, 0.02) << "without gravity the closure's pitch bends the odometry chain";

  // 0.002 (0.1 degree): what a visual-inertial odometry's tilt is good to, 25 times the
  // closure's confidence in its rotation (and every node has one).
  ParametersMap withGravity = noCheck;
  withGravity["Optimizer/GravitySigma"] = "0.002";
  const std::map<int, Transform> level = mapWithTiltedClosure(withGravity, &accepted, &gravityLinks);
  ASSERT_TRUE(accepted);
  const double tiltLevel = largestTilt(level);
  EXPECT_LT(tiltLevel, 0.25 * tiltFree) << "gravity links should hold the nodes' up axis";
  EXPECT_NEAR(level.at(11).x(), 5.0, 0.01) << "gravity constrains the orientation, not the position";

  // The same from the frames' IMU orientation instead of the odometry's.
  ParametersMap fromImu = withGravity;
  fromImu["Mem/UseOdomGravity"] = "false";
  const std::map<int, Transform> imuLevel = mapWithTiltedClosure(fromImu, &accepted, &gravityLinks, true);
  ASSERT_TRUE(accepted);
  EXPECT_EQ(gravityLinks, 11);
  EXPECT_LT(largestTilt(imuLevel), 0.25 * tiltFree);

  // In 3DoF the gravity links have nothing to constrain: ignored, the map is planar anyway.
  ParametersMap planar = withGravity;
  planar["Reg/Force3DoF"] = "true";
  const std::map<int, Transform> flat = mapWithTiltedClosure(planar, &accepted, &gravityLinks);
  EXPECT_LT(largestTilt(flat), 1e-9);
}

TEST(Gravity, TiltedLoopClosureIsRefusedWhenGravityDisagrees) {
  // With RGBD/OptimizeMaxError (default 3 sigma) the graph decides: odometry alone can bend
  // enough to hold the closure, but not against gravity links that know where down is.
  bool accepted = false;
  int gravityLinks = 0;
  mapWithTiltedClosure({}, &accepted, &gravityLinks);
  EXPECT_TRUE(accepted) << "without gravity the closure is within what the odometry can absorb";
  mapWithTiltedClosure({{"Optimizer/GravitySigma", "0.002"}}, &accepted, &gravityLinks);
  EXPECT_FALSE(accepted) << "the closure's pitch, 0.05 rad at 0.01 rad, is about 5 sigma off once gravity holds the nodes";
}

TEST(Gravity, NoGravityLinkWithoutTheOption) {
  bool accepted = false;
  int gravityLinks = 0;
  mapWithTiltedClosure({{"Mem/UseOdomGravity", "false"}, {"Optimizer/GravitySigma", "0.002"}}, &accepted, &gravityLinks);
  EXPECT_EQ(gravityLinks, 0) << "the frames carry no IMU orientation";
}

}  // namespace
}  // namespace rtabmap
