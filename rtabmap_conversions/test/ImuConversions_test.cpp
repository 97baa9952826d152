#include "rtabmap_conversions/ImuConversions.h"

#include <gtest/gtest.h>

#include <limits>

using namespace rtabmap_conversions;

namespace {

rtabmap::IMU sampleImu(bool withOrientation) {
  rtabmap::IMU imu;
  if (withOrientation) {
    imu.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 0.1, 1.0).normalized()));
    imu.orientationCovariance = Eigen::Matrix3d::Identity() * 0.01;
  }
  imu.angularVelocity = Eigen::Vector3d(0.01, -0.02, 0.5);
  imu.angularVelocityCovariance = Eigen::Matrix3d::Identity() * 1e-4;
  imu.angularVelocityCovariance(0, 2) = 2e-5;
  imu.linearAcceleration = Eigen::Vector3d(0.1, 0.2, 9.81);
  imu.linearAccelerationCovariance = Eigen::Matrix3d::Identity() * 1e-3;
  return imu;
}

std_msgs::Header imuHeader() {
  std_msgs::Header h;
  h.frame_id = "imu_link";
  h.stamp = ros::Time(3, 0);
  return h;
}

}  // namespace

TEST(ImuConversions, RoundTripWithOrientation) {
  const rtabmap::IMU imu = sampleImu(true);
  const sensor_msgs::Imu msg = imuToMsg(imu, imuHeader());
  EXPECT_EQ(msg.header.frame_id, "imu_link");
  EXPECT_EQ(msg.angular_velocity_covariance[2], 2e-5);  // row-major (0, 2)
  const rtabmap::Transform local(0.1, 0, 0.2, 0, 0, 0);
  std::string error;
  const std::optional<rtabmap::IMU> back = imuFromMsg(msg, local, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_TRUE(back->hasOrientation());
  EXPECT_TRUE(back->orientation.isApprox(imu.orientation, 1e-12));
  EXPECT_EQ(back->orientationCovariance, imu.orientationCovariance);
  EXPECT_EQ(back->angularVelocity, imu.angularVelocity);
  EXPECT_EQ(back->angularVelocityCovariance, imu.angularVelocityCovariance);
  EXPECT_EQ(back->linearAcceleration, imu.linearAcceleration);
  EXPECT_EQ(back->linearAccelerationCovariance, imu.linearAccelerationCovariance);
  EXPECT_EQ(back->localTransform, local);
}

TEST(ImuConversions, NoOrientationTravelsAsMinusOneCovariance) {
  const sensor_msgs::Imu msg = imuToMsg(sampleImu(false), imuHeader());
  EXPECT_EQ(msg.orientation_covariance[0], -1.0);
  std::optional<rtabmap::IMU> back = imuFromMsg(msg);
  ASSERT_TRUE(back);
  EXPECT_FALSE(back->hasOrientation());
  EXPECT_EQ(back->angularVelocity, sampleImu(false).angularVelocity);

  sensor_msgs::Imu garbage = msg;  // with the -1 marker the quaternion is ignored, even NaN
  garbage.orientation.x = std::numeric_limits<double>::quiet_NaN();
  back = imuFromMsg(garbage);
  ASSERT_TRUE(back);
  EXPECT_FALSE(back->hasOrientation());

  sensor_msgs::Imu zero = msg;  // drivers that forget the marker
  zero.orientation_covariance[0] = 0.0;
  back = imuFromMsg(zero);
  ASSERT_TRUE(back);
  EXPECT_FALSE(back->hasOrientation());
}

TEST(ImuConversions, DenormalisedQuaternionIsNormalisedAndNaNIsAnError) {
  sensor_msgs::Imu msg = imuToMsg(sampleImu(true), imuHeader());
  msg.orientation.x *= 2.0;
  msg.orientation.y *= 2.0;
  msg.orientation.z *= 2.0;
  msg.orientation.w *= 2.0;
  std::optional<rtabmap::IMU> back = imuFromMsg(msg);
  ASSERT_TRUE(back);
  EXPECT_NEAR(back->orientation.norm(), 1.0, 1e-12);

  std::string error;
  sensor_msgs::Imu nan = imuToMsg(sampleImu(true), imuHeader());
  nan.linear_acceleration.z = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(imuFromMsg(nan, rtabmap::Transform::Identity(), &error));
  EXPECT_NE(error.find("'imu_link'"), std::string::npos) << error;
  nan = imuToMsg(sampleImu(true), imuHeader());
  nan.orientation.w = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(imuFromMsg(nan, rtabmap::Transform::Identity(), &error));
  EXPECT_NE(error.find("orientation"), std::string::npos) << error;
}
