// findGroundPlane (Odom/AlignWithGround): the floor under a tilted base, not a wall nor a
// ceiling, the same plane every time.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include <cmath>

#include "rtabmap_core/maps/GroundPlane.h"

namespace rtabmap {
namespace {

// Points of a grid on the plane n . p + d = 0 (n unit), spread `size` metres around the foot of
// the origin's perpendicular, with small noise.
void addPlane(Cloud& cloud, const Eigen::Vector3d& n, double d, double size, cv::RNG& rng) {
  const Eigen::Vector3d foot = -d * n;
  const Eigen::Vector3d a = n.unitOrthogonal(), b = n.cross(a);
  for (double i = -size / 2; i < size / 2; i += 0.05) {
    for (double j = -size / 2; j < size / 2; j += 0.05) {
      const Eigen::Vector3d p = foot + i * a + j * b + n * rng.gaussian(0.003);
      cloud.push_back(cv::Point3f(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())));
    }
  }
}

// The floor 1.2 m below a base pitched down by 0.4 rad and rolled by 0.1: its normal in the
// base frame is the world's z seen from the base.
Eigen::Vector3d floorNormalInBase() {
  const Eigen::Matrix3d worldFromBase = (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY()) *
                                         Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX())).toRotationMatrix();
  return worldFromBase.transpose() * Eigen::Vector3d::UnitZ();
}

TEST(GroundPlane, TheFloorUnderATiltedBaseAmongAWall) {
  cv::RNG rng(1);
  Cloud cloud;
  const Eigen::Vector3d n = floorNormalInBase();
  addPlane(cloud, n, 1.2, 4.0, rng);                             // floor: n . p + 1.2 = 0
  addPlane(cloud, Eigen::Vector3d::UnitX(), -3.0, 3.0, rng);     // a wall 3 m ahead
  const std::optional<GroundPlane> floor = findGroundPlane(cloud);
  ASSERT_TRUE(floor.has_value());
  EXPECT_NEAR(floor->height, 1.2, 0.01);
  EXPECT_LT(std::acos(std::min(1.0, floor->normal.dot(n))), 0.01) << floor->normal.transpose();
  EXPECT_GT(floor->inliers, 5000);
  // Deterministic: the same cloud, the same plane.
  const std::optional<GroundPlane> again = findGroundPlane(cloud);
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(again->inliers, floor->inliers);
  EXPECT_EQ(again->height, floor->height);
}

TEST(GroundPlane, AWallOrACeilingIsNoFloor) {
  cv::RNG rng(2);
  Cloud wall, ceiling;
  addPlane(wall, Eigen::Vector3d::UnitX(), -2.0, 3.0, rng);
  addPlane(ceiling, -Eigen::Vector3d::UnitZ(), 1.0, 3.0, rng);  // z = 1: above the base
  EXPECT_FALSE(findGroundPlane(wall).has_value());
  EXPECT_FALSE(findGroundPlane(ceiling).has_value());
  EXPECT_FALSE(findGroundPlane(Cloud()).has_value());
}

}  // namespace
}  // namespace rtabmap
