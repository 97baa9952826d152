// The gyroscope's rotation between two frames (src/odometry/GyroIntegration.h) and odometry's
// guess from it (Odometry::addImu).
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>

#include "../../src/odometry/GyroIntegration.h"

namespace rtabmap {
namespace {

using odometry_detail::GyroIntegration;

IMU gyro(const Eigen::Vector3d& w, const Transform& mount = Transform::Identity()) {
  IMU imu;
  imu.angularVelocity = w;
  imu.localTransform = mount;
  return imu;
}

double angleBetween(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

// A base yawing at a rate that ramps up (0.5 rad/s more each second) and pitching at a constant
// 0.2 rad/s, sampled at 200 Hz by an IMU mounted upside down and turned: the integral between two
// frame stamps (between samples) is the base's true rotation over that time.
TEST(GyroIntegration, IntegratesTheBaseRotationBetweenTwoStamps) {
  const Transform mount(0.1, 0.0, 0.2, M_PI, 0.0, M_PI_2);
  const Eigen::Matrix3d baseImu = mount.rotationMatrix();
  auto rateAt = [](double t) { return Eigen::Vector3d(0.0, 0.2, 0.5 * t); };  // base frame
  GyroIntegration g;
  for (int i = 0; i <= 400; ++i) {
    const double t = 10.0 + i * 0.005;
    ASSERT_TRUE(g.add(t, gyro(baseImu.transpose() * rateAt(t - 10.0), mount)));
  }
  // The truth: the same rates integrated finely (body-frame rates: right-multiplied).
  auto truth = [&](double t0, double t1) {
    Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
    const int n = 20000;
    for (int k = 0; k < n; ++k) {
      const double t = t0 + (k + 0.5) * (t1 - t0) / n;
      const Eigen::Vector3d w = rateAt(t - 10.0) * (t1 - t0) / n;
      r = r * Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
    }
    return r;
  };
  for (const auto& [t0, t1] : {std::pair<double, double>{10.0123, 10.1123}, {10.5, 11.3}, {11.001, 11.999}}) {
    const std::optional<Eigen::Matrix3d> r = g.rotationBetween(t0, t1);
    ASSERT_TRUE(r);
    const Eigen::Matrix3d want = truth(t0, t1);
    EXPECT_GT(Eigen::AngleAxisd(want).angle(), 0.02);
    EXPECT_LT(angleBetween(*r, want), 1e-5) << t0 << " -> " << t1;
  }
  // Outside what the samples cover, or over a hole: none.
  EXPECT_FALSE(g.rotationBetween(9.0, 10.1));
  EXPECT_FALSE(g.rotationBetween(11.5, 12.5));
  EXPECT_FALSE(g.rotationBetween(10.2, 10.1));
  GyroIntegration holed;
  ASSERT_TRUE(holed.add(1.0, gyro({0, 0, 1})));
  ASSERT_TRUE(holed.add(1.01, gyro({0, 0, 1})));
  ASSERT_TRUE(holed.add(1.2, gyro({0, 0, 1})));
  EXPECT_TRUE(holed.rotationBetween(1.0, 1.01));
  EXPECT_FALSE(holed.rotationBetween(1.0, 1.2)) << "0.19 s without a sample";
  // Ends within maxGap of a sample inside are covered, holes before or after included.
  const std::optional<Eigen::Matrix3d> end = holed.rotationBetween(1.17, 1.25);
  ASSERT_TRUE(end);
  EXPECT_NEAR(Eigen::AngleAxisd(*end).angle(), 0.08, 1e-9);
  EXPECT_TRUE(holed.rotationBetween(0.97, 1.005));
  EXPECT_FALSE(holed.rotationBetween(1.1, 1.19)) << "inside the hole";

  // Forgetting the past keeps what the next integration needs.
  g.dropBefore(11.0);
  EXPECT_TRUE(g.rotationBetween(11.0, 11.5));
  EXPECT_FALSE(g.rotationBetween(10.5, 11.5));
}

// Odometry lost for minutes adds samples without a pose to drop them at: the history stays bounded.
TEST(GyroIntegration, HistoryIsBounded) {
  GyroIntegration g(0.05, 10.0);
  for (int i = 0; i < 200 * 60; ++i) ASSERT_TRUE(g.add(i * 0.005, gyro({0, 0, 0.1})));
  EXPECT_LE(g.size(), 2002u);
  EXPECT_TRUE(g.rotationBetween(55.0, 59.0));
  EXPECT_FALSE(g.rotationBetween(40.0, 59.0)) << "forgotten";
}

TEST(GyroIntegration, UnusableSamplesAreRefused) {
  GyroIntegration g;
  EXPECT_FALSE(g.add(1.0, gyro({0, 0, 0}))) << "no angular velocity (an orientation-only message)";
  EXPECT_FALSE(g.add(1.0, gyro({std::nan(""), 0, 0})));
  EXPECT_FALSE(g.add(std::nan(""), gyro({0, 0, 1})));
  EXPECT_TRUE(g.add(1.0, gyro({0, 0, 1})));
  EXPECT_FALSE(g.add(1.0, gyro({0, 0, 1}))) << "not after the previous sample";
  EXPECT_FALSE(g.add(0.5, gyro({0, 0, 1})));
  EXPECT_EQ(g.size(), 1u);
}

}  // namespace
}  // namespace rtabmap
