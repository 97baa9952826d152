// The fusion of a refined neighbour link with its odometry (RGBD/NeighborLinkRefiningPrior),
// against the closed form it implements.
#include "../../src/slam/OdometryPrior.h"

#include <gtest/gtest.h>

#include <cmath>

using rtabmap::fuseWithOdometryPrior;
using rtabmap::Transform;

namespace {

using Information = Eigen::Matrix<double, 6, 6>;

// Information of ICP in a corridor along x: across it and the turn well known (2 cm, 0.3 deg),
// along it nearly nothing (0.3 m). The unused 3D axes as strong as the turn, as the ICP code
// fills them.
Information corridor() {
  Information i = Information::Zero();
  i.diagonal() << 1.0 / (0.3 * 0.3), 1.0 / (0.02 * 0.02), 1e4, 1e4, 1e4, 1.0 / (0.005 * 0.005);
  return i;
}

}  // namespace

// Along the corridor the odometry wins, across it and in rotation the registration does: the
// weights are the closed form's L_reg / (L_reg + 1/s^2) per axis (diagonal information).
TEST(OdometryPrior, CorridorKeepsTheOdometryAlongAndTheRegistrationAcross) {
  const Transform odometry(0.16, 0.0, 0.0, 0.0, 0.0, 0.02);
  const Transform registered = odometry * Transform(-0.15, 0.03, 0.0, 0.0, 0.0, -0.01);  // slid back
  const double prior = 0.5;
  const Transform fused = fuseWithOdometryPrior(registered, corridor(), odometry, prior);
  ASSERT_FALSE(fused.isNull());
  const Transform correction = odometry.inverse() * fused;

  const double s = 0.01 + prior * odometry.getNorm();
  const double lo = 1.0 / (s * s);
  const Information i = corridor();
  EXPECT_NEAR(correction.x(), -0.15 * i(0, 0) / (i(0, 0) + lo), 1e-6);  // mostly the odometry's
  EXPECT_NEAR(correction.y(), 0.03 * i(1, 1) / (i(1, 1) + lo), 1e-6);   // mostly the registration's
  EXPECT_NEAR(correction.yaw(), -0.01, 1e-6);                          // the registration's
  EXPECT_LT(std::fabs(correction.x()), 0.03);
  EXPECT_GT(correction.y(), 0.025);
}

// Where the registration knows every axis far better than the prior, the fusion changes nothing
// that matters; with no prior it changes nothing at all.
TEST(OdometryPrior, StrongRegistrationOrNoPriorKeepsTheRegistration) {
  const Transform odometry(0.3, 0.05, 0.0, 0.0, 0.0, 0.1);
  const Transform registered = odometry * Transform(0.04, -0.02, 0.0, 0.0, 0.0, 0.01);
  Information strong = Information::Identity() * 1e6;
  const Transform fused = fuseWithOdometryPrior(registered, strong, odometry, 0.5);
  EXPECT_LT(fused.getDistance(registered), 1e-3);
  EXPECT_NEAR(fused.yaw(), registered.yaw(), 1e-6);

  for (double prior : {0.0, -1.0}) {
    const Transform same = fuseWithOdometryPrior(registered, corridor(), odometry, prior);
    EXPECT_LT((same.toEigen().matrix() - registered.toEigen().matrix()).norm(), 1e-12);
  }
}

// Cross terms count: with translation along x correlated to the turn in the registration's
// information, the closed form is the full solve, not per axis.
TEST(OdometryPrior, FullInformationIsSolvedNotPerAxis) {
  const Transform odometry(0.2, 0.0, 0.0, 0.0, 0.0, 0.0);
  const Transform registered = odometry * Transform(-0.1, 0.02, 0.0, 0.0, 0.0, 0.03);
  Information i = corridor();
  i(0, 5) = i(5, 0) = 0.5 * std::sqrt(i(0, 0) * i(5, 5));
  const double prior = 0.2;
  const double s = 0.01 + prior * odometry.getNorm();
  Information lo = Information::Zero();
  lo.topLeftCorner<3, 3>() = Eigen::Matrix3d::Identity() / (s * s);
  Eigen::Matrix<double, 6, 1> d;
  d << -0.1, 0.02, 0.0, 0.0, 0.0, 0.03;
  const Eigen::Matrix<double, 6, 1> expected = (i + lo).inverse() * i * d;

  const Transform correction = odometry.inverse() * fuseWithOdometryPrior(registered, i, odometry, prior);
  EXPECT_NEAR(correction.x(), expected(0), 1e-6);
  EXPECT_NEAR(correction.y(), expected(1), 1e-6);
  EXPECT_NEAR(correction.yaw(), expected(5), 1e-6);
  EXPECT_GT(std::fabs(correction.x() - (-0.1 * i(0, 0) / (i(0, 0) + lo(0, 0)))), 1e-4);  // coupling moved x
}

// Nothing to fuse: null transforms, non-finite information.
TEST(OdometryPrior, BadInputKeepsTheRegistration) {
  const Transform odometry(0.2, 0.0, 0.0);
  const Transform registered(0.1, 0.0, 0.0);
  EXPECT_TRUE(fuseWithOdometryPrior(Transform(), corridor(), odometry, 0.5).isNull());
  EXPECT_LT(fuseWithOdometryPrior(registered, corridor(), Transform(), 0.5).getDistance(registered), 1e-12);
  Information nan = corridor();
  nan(0, 0) = std::nan("");
  EXPECT_LT(fuseWithOdometryPrior(registered, nan, odometry, 0.5).getDistance(registered), 1e-12);
}
