#include "rtabmap_slam_node/LandmarkBuffer.h"

#include <gtest/gtest.h>

#include <cmath>

using rtabmap::Transform;
using namespace rtabmap_slam_node;

namespace {

PendingLandmark seen(int id, double stamp, double x, bool noCovariance = false) {
  PendingLandmark p;
  p.stamp = stamp;
  p.frameId = "camera";
  p.landmark.id = id;
  p.landmark.pose = Transform(x, 0, 1, 0, 0, 0);
  p.landmark.covariance.setZero();
  p.landmark.covariance.diagonal() << 0.01, 0.02, 0.03, 0.1, 0.2, 0.3;
  p.defaultCovariance = noCovariance;
  return p;
}

Eigen::Matrix<double, 6, 6> markers() {
  Eigen::Matrix<double, 6, 6> c = Eigen::Matrix<double, 6, 6>::Zero();
  c.diagonal() << 0.001, 0.001, 0.001, 0.01, 0.01, 0.01;
  return c;
}

// The camera turned a quarter about z on the robot, 0.5 m ahead of it.
Transform cameraOnRobot(const std::string&, double, std::string*) { return Transform(0.5, 0, 0, 0, 0, M_PI / 2); }

TEST(LandmarkBuffer, DetectionsUpToTheFrameInTheBaseFrameTheNewestPerId) {
  LandmarkBuffer buffer(1.0);
  buffer.add(seen(3, 9.5, 0.1));
  buffer.add(seen(3, 9.9, 0.2));  // newer sighting of the same landmark
  buffer.add(seen(5, 10.05, 0.3));  // stamped with the frame's image, arrived a little later
  buffer.add(seen(7, 10.5, 0.4));   // after the frame: the next frame's
  buffer.add(seen(9, 8.5, 0.5));    // too old
  std::vector<std::string> problems;
  const rtabmap::Landmarks out = buffer.take(10.0, cameraOnRobot, markers(), &problems);
  ASSERT_EQ(out.size(), 2u);
  ASSERT_TRUE(out.count(3));
  // (0.2, 0, 1) in the camera: turned a quarter and 0.5 m ahead on the robot.
  EXPECT_NEAR(out.at(3).pose.x(), 0.5, 1e-9);
  EXPECT_NEAR(out.at(3).pose.y(), 0.2, 1e-9);
  EXPECT_NEAR(out.at(3).pose.z(), 1.0, 1e-9);
  // The covariance turned with it: x and y swap.
  EXPECT_NEAR(out.at(3).covariance(0, 0), 0.02, 1e-12);
  EXPECT_NEAR(out.at(3).covariance(1, 1), 0.01, 1e-12);
  EXPECT_NEAR(out.at(3).covariance(3, 3), 0.2, 1e-12);
  EXPECT_TRUE(out.count(5));
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("landmark 9"), std::string::npos) << problems[0];
  EXPECT_EQ(buffer.size(), 1u) << "the next frame's detection waits";
  const rtabmap::Landmarks next = buffer.take(10.6, cameraOnRobot, markers(), &problems);
  EXPECT_TRUE(next.count(7));
  EXPECT_EQ(buffer.size(), 0u);
}

TEST(LandmarkBuffer, WithoutCovarianceTheDefaultAndWithoutTfDropped) {
  LandmarkBuffer buffer;
  buffer.add(seen(2, 1.0, 0.0, true));
  rtabmap::Landmarks out = buffer.take(1.0, cameraOnRobot, markers(), nullptr);
  ASSERT_TRUE(out.count(2));
  EXPECT_NEAR(out.at(2).covariance(0, 0), 0.001, 1e-12);
  EXPECT_NEAR(out.at(2).covariance(5, 5), 0.01, 1e-12);

  buffer.add(seen(4, 2.0, 0.0));
  std::vector<std::string> problems;
  const auto noTf = [](const std::string&, double, std::string* why) {
    *why = "no transform from camera";
    return Transform();
  };
  out = buffer.take(2.0, noTf, markers(), &problems);
  EXPECT_TRUE(out.empty());
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("no transform"), std::string::npos);
  buffer.add(seen(6, 3.0, 0.0));
  buffer.clear();
  EXPECT_EQ(buffer.size(), 0u);
}

}  // namespace
