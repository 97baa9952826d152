// ICP registration: known 2D and 3D transforms recovered, point-to-plane against point-to-point,
// the corridor (low structural complexity), acceptance, and bad scans.
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "registration/IcpTestScenes.h"
#include "common/TestData.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/registration/IcpRegistration.h"

namespace rtabmap {
namespace {

using test::castScan2D;
using test::castScan3D;
using test::rotationError;
using test::translationError;

constexpr double kDeg = M_PI / 180.0;

ParametersMap scanParams2D(bool pointToPlane) {
  return {{Parameters::kIcpVoxelSize(), "0.05"},
          {Parameters::kIcpMaxCorrespondenceDistance(), "0.5"},
          {Parameters::kIcpIterations(), "50"},
          {Parameters::kIcpMaxTranslation(), "1"},
          {Parameters::kIcpPointToPlane(), pointToPlane ? "true" : "false"},
          {Parameters::kIcpPointToPlaneK(), "5"}};
}

TEST(IcpRegistration, Recovers2DTransformPointToPointAndPointToPlane) {
  const auto world = test::officeWorld();
  const Transform a(4.0, 6.0, 0.3);
  const Transform b(4.25, 5.9, 0.3 + 4 * kDeg);
  const LaserScan from = castScan2D(world, a, {});
  const LaserScan to = castScan2D(world, b, {});
  const Transform truth = a.inverse() * b;
  for (bool plane : {false, true}) {
    SCOPED_TRACE(plane ? "point-to-plane" : "point-to-point");
    RegistrationInfo info;
    const Transform t = IcpRegistration(scanParams2D(plane)).computeTransform(from, to, Transform::Identity(), &info);
    ASSERT_FALSE(t.isNull()) << info.rejectedMsg;
    EXPECT_TRUE(info.success);
    EXPECT_LT(translationError(t, truth), 0.02);
    EXPECT_LT(rotationError(t, truth), 0.3 * kDeg);
    // A planar scan never leaves its plane.
    EXPECT_EQ(t.z(), 0.0);
    EXPECT_EQ(t.roll(), 0.0);
    EXPECT_EQ(t.pitch(), 0.0);
    EXPECT_GT(info.icpInliersRatio, 0.7);
    EXPECT_GT(info.icpCorrespondences, 100);
  }
}

TEST(IcpRegistration, PlanarGuessWithTiltIsFlattened) {
  const auto world = test::officeWorld();
  const Transform a(4.0, 6.0, 0.0);
  const Transform b(4.1, 6.0, 0.02);
  const LaserScan from = castScan2D(world, a, {});
  const LaserScan to = castScan2D(world, b, {});
  RegistrationInfo info;
  const Transform guess(0.1, 0.0, 0.4, 0.1, -0.1, 0.0);  // z, roll and pitch a 2D scan cannot see
  const Transform t = IcpRegistration(scanParams2D(true)).computeTransform(from, to, guess, &info);
  ASSERT_FALSE(t.isNull()) << info.rejectedMsg;
  EXPECT_EQ(t.z(), 0.0);
  EXPECT_EQ(t.roll(), 0.0);
  EXPECT_LT(translationError(t, a.inverse() * b), 0.01);
}

TEST(IcpRegistration, Recovers3DTransform) {
  const auto world = test::hallWorld();
  const Transform a(0.5, -0.5, 0.3, 0.0, 0.0, 0.2);
  const Transform b(1.1, -0.3, 0.35, 1.5 * kDeg, -1.0 * kDeg, 0.2 + 3 * kDeg);
  // 32 rings: with 16, the rings cut the floor in circles that move with the sensor, and
  // point-to-point pairs them with the other scan's circles (centimetres of bias).
  const LaserScan from = castScan3D(world, a, 32, 360);
  const LaserScan to = castScan3D(world, b, 32, 360);
  const Transform truth = a.inverse() * b;
  for (bool plane : {false, true}) {
    SCOPED_TRACE(plane ? "point-to-plane" : "point-to-point");
    ParametersMap p = {{Parameters::kIcpVoxelSize(), "0.1"},
                       {Parameters::kIcpMaxCorrespondenceDistance(), "1.0"},
                       {Parameters::kIcpIterations(), "60"},
                       {Parameters::kIcpMaxTranslation(), "2"},
                       {Parameters::kIcpPointToPlane(), plane ? "true" : "false"},
                       {Parameters::kIcpPointToPlaneK(), "10"}};
    RegistrationInfo info;
    const Transform t = IcpRegistration(p).computeTransform(from, to, Transform::Identity(), &info);
    ASSERT_FALSE(t.isNull()) << info.rejectedMsg;
    EXPECT_LT(translationError(t, truth), plane ? 0.01 : 0.05);
    EXPECT_LT(rotationError(t, truth), (plane ? 0.1 : 0.5) * kDeg);
    if (plane) {
      EXPECT_GT(info.icpStructuralComplexity, 0.1);
    }
  }
}

// Sparse beams sample the far walls every ~30 cm at different places in each scan: pairing
// points with points is off by up to half that spacing, pairing points with the wall is not.
TEST(IcpRegistration, PointToPlaneBeatsPointToPointOnPlanarScene) {
  test::World2D room;
  test::addPolygon(room, {0, 0, 12, 0, 12, 9, 0, 9});
  test::Lidar2D sparse;
  sparse.beams = 100;
  sparse.angleMax = M_PI - 2 * M_PI / 100;
  const Transform a(3.0, 3.0, 0.0);
  const Transform b(3.4, 3.3, 5 * kDeg);
  const LaserScan from = castScan2D(room, a, sparse);
  const LaserScan to = castScan2D(room, b, sparse);
  const Transform truth = a.inverse() * b;
  ParametersMap p = scanParams2D(false);
  p[Parameters::kIcpVoxelSize()] = "0";
  p[Parameters::kIcpIterations()] = "30";
  RegistrationInfo info;
  const Transform point = IcpRegistration(p).computeTransform(from, to, Transform::Identity(), &info);
  ASSERT_FALSE(point.isNull()) << info.rejectedMsg;
  p[Parameters::kIcpPointToPlane()] = "true";
  const Transform plane = IcpRegistration(p).computeTransform(from, to, Transform::Identity(), &info);
  ASSERT_FALSE(plane.isNull()) << info.rejectedMsg;
  const double errPoint = translationError(point, truth);
  const double errPlane = translationError(plane, truth);
  EXPECT_LT(errPlane, 0.005);
  EXPECT_LT(errPlane, 0.5 * errPoint) << "point-to-point " << errPoint << " m, point-to-plane " << errPlane << " m";
  EXPECT_LE(rotationError(plane, truth), rotationError(point, truth) + 1e-4);
}

// In a corridor the walls constrain y and yaw but nothing constrains x: ICP would keep x where
// the guess put it only by luck. With strategy 1 the x of the result must be the guess's.
TEST(IcpRegistration, CorridorKeepsPositionAlongItFromTheGuess) {
  const auto world = test::corridorWorld();
  test::Lidar2D lidar;
  lidar.rangeMax = 8.0;
  std::mt19937 rng(rtabmap::test::drawSeed(3));
  lidar.noise = 0.005;
  const Transform a(0.0, 0.1, 0.0);
  const Transform b(0.5, 0.0, 2 * kDeg);
  const LaserScan from = castScan2D(world, a, lidar, &rng);
  const LaserScan to = castScan2D(world, b, lidar, &rng);
  const Transform truth = a.inverse() * b;
  const Transform guess(0.3, 0.05, 0.0);  // 20 cm short along the corridor, 5 cm off across

  ParametersMap p = scanParams2D(true);
  RegistrationInfo info;
  const Transform t = IcpRegistration(p).computeTransform(from, to, guess, &info);
  ASSERT_FALSE(t.isNull()) << info.rejectedMsg;
  EXPECT_LT(info.icpStructuralComplexity, 0.02);
  EXPECT_NEAR(t.x(), guess.x(), 2e-3);          // along the corridor: the guess
  EXPECT_NEAR(t.y(), truth.y(), 0.01);          // across: the walls
  EXPECT_NEAR(t.theta(), truth.theta(), 0.2 * kDeg);
  // The covariance says so: nothing is known along the corridor.
  EXPECT_GT(info.covariance(0, 0), 100 * info.covariance(1, 1));

  p[Parameters::kIcpPointToPlaneLowComplexityStrategy()] = "0";
  const Transform rejected = IcpRegistration(p).computeTransform(from, to, guess, &info);
  EXPECT_TRUE(rejected.isNull());
  EXPECT_NE(info.rejectedMsg.find("structural complexity"), std::string::npos) << info.rejectedMsg;
  EXPECT_NE(info.rejectedMsg.find("Icp/PointToPlaneMinComplexity"), std::string::npos);
}

TEST(IcpRegistration, RejectsLowCorrespondenceRatioWithReason) {
  const auto world = test::officeWorld();
  const LaserScan from = castScan2D(world, Transform(3.0, 3.0, 0.0), {});
  const LaserScan to = castScan2D(world, Transform(16.0, 10.0, 1.0), {});  // another room
  ParametersMap p = scanParams2D(false);
  p[Parameters::kIcpCorrespondenceRatio()] = "0.5";
  RegistrationInfo info;
  const Transform t = IcpRegistration(p).computeTransform(from, to, Transform::Identity(), &info);
  EXPECT_TRUE(t.isNull());
  EXPECT_FALSE(info.success);
  EXPECT_TRUE(info.rejectedMsg.find("< Icp/CorrespondenceRatio 0.500") != std::string::npos ||
              info.rejectedMsg.find("do not overlap") != std::string::npos ||
              info.rejectedMsg.find("Icp/MaxTranslation") != std::string::npos)
      << info.rejectedMsg;
}

TEST(IcpRegistration, RejectsCorrectionBeyondMaxTranslation) {
  const auto world = test::officeWorld();
  const Transform a(4.0, 6.0, 0.0);
  const Transform b(4.4, 6.0, 0.0);
  const LaserScan from = castScan2D(world, a, {});
  const LaserScan to = castScan2D(world, b, {});
  ParametersMap p = scanParams2D(true);
  p[Parameters::kIcpMaxCorrespondenceDistance()] = "1.0";
  p[Parameters::kIcpMaxTranslation()] = "0.2";
  RegistrationInfo info;
  EXPECT_TRUE(IcpRegistration(p).computeTransform(from, to, Transform::Identity(), &info).isNull());
  EXPECT_NE(info.rejectedMsg.find("> Icp/MaxTranslation 0.200"), std::string::npos) << info.rejectedMsg;
  EXPECT_NEAR(info.icpTranslation, 0.4, 0.02);
  // The same with a guess close to the truth is a small correction.
  EXPECT_FALSE(IcpRegistration(p).computeTransform(from, to, Transform(0.35, 0.0, 0.0), &info).isNull())
      << info.rejectedMsg;
}

TEST(IcpRegistration, HonoursScanLocalTransform) {
  const auto world = test::officeWorld();
  // The lidar sits 0.3 m ahead of the base, turned 90 degrees.
  const Transform sensor(0.3, 0.0, 0.0, 0.0, 0.0, M_PI / 2);
  const Transform a(4.0, 6.0, 0.2);
  const Transform b(4.2, 6.1, 0.25);
  LaserScan from = castScan2D(world, a * sensor, {});
  LaserScan to = castScan2D(world, b * sensor, {});
  from.setLocalTransform(sensor);
  to.setLocalTransform(sensor);
  RegistrationInfo info;
  const Transform t = IcpRegistration(scanParams2D(true)).computeTransform(from, to, Transform::Identity(), &info);
  ASSERT_FALSE(t.isNull()) << info.rejectedMsg;
  EXPECT_LT(translationError(t, a.inverse() * b), 0.01);  // base to base
}

TEST(IcpRegistration, BadScansAreRejectedWithReasonNeverThrown) {
  const auto world = test::officeWorld();
  const LaserScan good = castScan2D(world, Transform(4.0, 6.0, 0.0), {});
  const IcpRegistration icp(scanParams2D(true));
  RegistrationInfo info;

  EXPECT_TRUE(icp.computeTransform(LaserScan(), good, Transform::Identity(), &info).isNull());
  EXPECT_EQ(info.rejectedMsg, "scan 'from' is empty");

  cv::Mat one(1, 1, CV_32FC2, cv::Scalar(1.0f, 2.0f));
  EXPECT_TRUE(icp.computeTransform(good, LaserScan(one, 360, 0, 30, LaserScan::kXY), Transform(), &info).isNull());
  EXPECT_NE(info.rejectedMsg.find("scan 'to' has 1 point"), std::string::npos) << info.rejectedMsg;

  const float nan = std::numeric_limits<float>::quiet_NaN();
  cv::Mat allNan(1, 50, CV_32FC2, cv::Scalar(nan, nan));
  EXPECT_TRUE(icp.computeTransform(good, LaserScan(allNan, 360, 0, 30, LaserScan::kXY), Transform(), &info).isNull());
  EXPECT_NE(info.rejectedMsg.find("no finite point"), std::string::npos) << info.rejectedMsg;

  // Some NaN points among good ones are dropped, not fatal.
  cv::Mat partly = good.data().clone();
  for (int i = 0; i < partly.cols; i += 7) partly.at<cv::Vec2f>(0, i) = cv::Vec2f(nan, nan);
  const Transform t = icp.computeTransform(good, LaserScan(partly, 360, 0, 30, LaserScan::kXY), Transform(), &info);
  EXPECT_FALSE(t.isNull()) << info.rejectedMsg;
  EXPECT_LT(t.getNorm(), 0.01);

  // A guess with NaN.
  EXPECT_TRUE(icp.computeTransform(good, good, Transform(nan, 0.0, 0.0), &info).isNull());
  EXPECT_NE(info.rejectedMsg.find("guess"), std::string::npos) << info.rejectedMsg;

  // A line of collinear points has no 2D normals: every point is dropped, with a reason.
  cv::Mat line(1, 20, CV_32FC2);
  for (int i = 0; i < 20; ++i) line.at<cv::Vec2f>(0, i) = cv::Vec2f(1.0f, 0.0f);
  EXPECT_TRUE(icp.computeTransform(good, LaserScan(line, 360, 0, 30, LaserScan::kXY), Transform(), &info).isNull());
  EXPECT_NE(info.rejectedMsg.find("scan 'to' has"), std::string::npos) << info.rejectedMsg;
}

TEST(IcpOptions, FromParametersAndValidity) {
  const IcpOptions defaults = IcpOptions::fromParameters({});
  EXPECT_FLOAT_EQ(defaults.maxCorrespondenceDistance, Parameters::defaultIcpMaxCorrespondenceDistance());
  EXPECT_EQ(defaults.iterations, Parameters::defaultIcpIterations());
  std::string why;
  EXPECT_TRUE(defaults.IsValid(&why)) << why;

  EXPECT_THROW(IcpOptions::fromParameters({{"Icp/VoxelSise", "0.1"}}), ParameterError);
  EXPECT_THROW(IcpOptions::fromParameters({{Parameters::kIcpIterations(), "0"}}), ParameterError);

  IcpOptions o;
  o.pointToPlane = true;
  o.pointToPlaneK = 0;
  o.pointToPlaneRadius = 0.0f;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("Icp/PointToPlaneK"), std::string::npos);
  EXPECT_THROW(IcpRegistration{o}, ParameterError);

  o = IcpOptions();
  o.rangeMin = 5.0f;
  o.rangeMax = 2.0f;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("Icp/RangeMin"), std::string::npos);
}

TEST(IcpRegistration, Force4DoFKeepsRollAndPitchOfTheGuess) {
  const auto world = test::hallWorld();
  const Transform a(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
  const Transform b(0.4, 0.2, 0.1, 0.0, 0.0, 3 * kDeg);
  const LaserScan from = castScan3D(world, a, 16, 180);
  const LaserScan to = castScan3D(world, b, 16, 180);
  ParametersMap p = {{Parameters::kIcpVoxelSize(), "0.1"},
                     {Parameters::kIcpMaxCorrespondenceDistance(), "1.0"},
                     {Parameters::kIcpIterations(), "60"},
                     {Parameters::kIcpPointToPlane(), "true"},
                     {Parameters::kIcpPointToPlaneK(), "10"},
                     {Parameters::kIcpMaxTranslation(), "2"},
                     {Parameters::kIcpForce4DoF(), "true"}};
  const Transform guess(0.0, 0.0, 0.0, 0.5 * kDeg, -0.5 * kDeg, 0.0);
  RegistrationInfo info;
  const Transform t = IcpRegistration(p).computeTransform(from, to, guess, &info);
  ASSERT_FALSE(t.isNull()) << info.rejectedMsg;
  EXPECT_NEAR(t.roll(), guess.roll(), 1e-4);
  EXPECT_NEAR(t.pitch(), guess.pitch(), 1e-4);
  EXPECT_NEAR(t.yaw(), b.yaw(), 0.2 * kDeg);
  EXPECT_NEAR(t.x(), 0.4, 0.05);
}

}  // namespace
}  // namespace rtabmap
