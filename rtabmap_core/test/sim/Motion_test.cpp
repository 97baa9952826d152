// The planned path, the robot that tracks it, its wheel odometry and its IMU.
#include <gtest/gtest.h>

#include <cmath>

#include "SimTestUtil.h"
#include "rtabmap_core/sim/ImuModel.h"
#include "rtabmap_core/sim/Motion.h"
#include "rtabmap_core/sim/WheelOdometry.h"

using namespace rtabmap::sim;

namespace {

double yawError(double a, double b) { return std::fabs(Pose2::normalizeAngle(a - b)); }

// The loop scenario's route in the cached building.
std::vector<Eigen::Vector2d> loopRoute() {
  const Building& b = test::loopBuilding();
  return planRoutes(scenarioSpec("loop"), b, rtabmap::test::drawSeed(7), MotionLimits()).front().waypoints;
}

}  // namespace

TEST(SimMotion, PlanRespectsTheLimitsAndRestsAtBothEnds) {
  MotionLimits lim;
  const ReferencePath path({{0, 0}, {6, 0}, {6, 4}, {2, 4}}, lim);
  // 6 + 4 + 4 m, minus what each of the two rounded corners cuts: 2r of straight for r pi/2 of arc.
  EXPECT_NEAR(path.length(), 14.0 - 2.0 * lim.cornerRadius * (2.0 - M_PI / 2.0), 1e-3);
  double prevYaw = path.at(0).yaw;
  for (double t = 0.0; t <= path.duration(); t += 0.01) {
    const ReferenceState r = path.at(t);
    ASSERT_LE(r.v, lim.maxSpeed + 1e-9);
    ASSERT_GE(r.v, 0.0);
    ASSERT_LE(std::fabs(r.omega), lim.maxYawRate + 1e-9);
    ASSERT_LE(std::fabs(r.yaw - prevYaw), 0.05);  // continuous
    prevYaw = r.yaw;
  }
  EXPECT_EQ(path.at(0.5 * lim.dwell).v, 0.0);
  EXPECT_EQ(path.at(path.duration() - 0.5 * lim.dwell).v, 0.0);
  const ReferenceState end = path.at(path.duration());
  EXPECT_NEAR(end.x, 2.0, 1e-9);
  EXPECT_NEAR(end.y, 4.0, 1e-9);
  EXPECT_NEAR(end.yaw, M_PI, 1e-9);  // two left turns
  EXPECT_GT(path.duration(), path.length() / lim.maxSpeed + 2 * lim.dwell);
}

TEST(SimMotion, SharpCornersTurnInPlace) {
  const ReferencePath path({{0, 0}, {3, 0}, {0, 0.01}}, MotionLimits());  // a U-turn
  bool sawTurn = false;
  for (double t = 0.0; t <= path.duration(); t += 0.01) {
    const ReferenceState r = path.at(t);
    if (std::fabs(r.omega) > 0.1) {
      sawTurn = true;
      EXPECT_NEAR(r.x, 3.0, 1e-9);  // turning on the spot
      EXPECT_EQ(r.v, 0.0);
    }
  }
  EXPECT_TRUE(sawTurn);
  EXPECT_NEAR(yawError(path.at(path.duration()).yaw, M_PI), 0.0, 0.01);
  EXPECT_THROW(ReferencePath({{1, 1}, {1, 1.001}}, MotionLimits()), std::invalid_argument);
}

TEST(SimMotion, OppositeCornersKeepAStraightBetweenThemAndTheRobotFollows) {
  // A 0.5 m jog: left then right at once. Rounded back to back, the plan would reverse its yaw
  // rate in one step, which the robot's yaw acceleration follows only after decimetres (6 cm
  // off the plan here, 13 cm in some generated buildings).
  const MotionLimits lim;
  const ReferencePath path({{0, 0}, {3, 0}, {3, 0.5}, {6, 0.5}}, lim);
  double straight = 0.0, previousOmega = 0.0;
  bool betweenArcs = false;
  const double dt = 0.001;
  for (double t = 0.0; t <= path.duration(); t += dt) {
    const ReferenceState r = path.at(t);
    if (previousOmega > 1e-6 && std::fabs(r.omega) < 1e-9) betweenArcs = true;  // the left arc ended
    if (betweenArcs && r.omega < -1e-6) break;                                  // the right arc began
    if (betweenArcs) straight += r.v * dt;
    previousOmega = r.omega;
  }
  EXPECT_GT(straight, 0.1) << "no straight between the two arcs";
  RobotSimulator robot(path);
  double worst = 0.0;
  while (!robot.finished()) {
    const RobotState& s = robot.step();
    const ReferenceState r = path.at(s.t);
    worst = std::max(worst, std::hypot(r.x - s.pose.x, r.y - s.pose.y));
  }
  EXPECT_LT(worst, 0.05);
}

TEST(SimMotion, RobotTracksThePlanWithinCentimetresAndNeverTouchesAWall) {
  const Building& b = test::loopBuilding();
  const ReferencePath path(loopRoute(), MotionLimits());
  RobotSimulator robot(path);
  double worstTracking = 0.0, worstClearance = 1e9, worstAcceleration = 0.0;
  double previousV = 0.0;
  long long steps = 0;
  while (!robot.finished()) {
    const RobotState& s = robot.step();
    worstAcceleration = std::max(worstAcceleration, std::fabs(s.v - previousV) / robot.stepSeconds());
    previousV = s.v;
    if (++steps % 100) continue;
    const ReferenceState r = path.at(s.t);
    worstTracking = std::max(worstTracking, std::hypot(r.x - s.pose.x, r.y - s.pose.y));
    worstClearance = std::min(worstClearance, b.world->clearance({s.pose.x, s.pose.y}, 0.05f));
  }
  EXPECT_LT(worstTracking, 0.05);
  EXPECT_GT(worstClearance, 0.3);  // a 0.25 m robot radius with room to spare
  EXPECT_LE(worstAcceleration, path.limits().robotAcceleration + 1e-6);
  EXPECT_GT(path.length(), 50.0);
}

TEST(SimOdometry, WithoutNoiseOdometryIsTheTrueMotion) {
  const ReferencePath path(loopRoute(), MotionLimits());
  RobotSimulator robot(path);
  WheelOdometry odom(OdometryNoise::none(), 1);
  const Pose2 start = robot.state().pose;
  odom.reset(start);
  long long steps = 0;
  double worst = 0.0;
  while (!robot.finished()) {
    const RobotState& s = robot.step();
    odom.update(s.pose);
    if (++steps % 500) continue;
    const Pose2 expected = start.inverse() * s.pose;
    worst = std::max({worst, std::hypot(odom.pose().x - expected.x, odom.pose().y - expected.y),
                      yawError(odom.pose().yaw, expected.yaw)});
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_EQ(odom.take(0).covariance.norm(), 0.0);
}

// Odometry error (position, against the true motion) after about 10 m and about 60 m of the same
// route, averaged over seeds: it grows with the distance, as wheel odometry drifts.
TEST(SimOdometry, WithNoiseTheErrorGrowsWithDistance) {
  const ReferencePath path(loopRoute(), MotionLimits());
  double at10 = 0.0, at60 = 0.0, covariance10 = 0.0, covariance60 = 0.0;
  const int seeds = 6;
  for (int seed = 0; seed < seeds; ++seed) {
    RobotSimulator robot(path);
    WheelOdometry odom(OdometryNoise(), rtabmap::test::drawSeed(static_cast<unsigned>(seed)));
    const Pose2 start = robot.state().pose;
    odom.reset(start);
    double travelled = 0.0;
    bool passed10 = false;
    while (!robot.finished() && travelled < 60.0) {
      const RobotState& s = robot.step();
      odom.update(s.pose);
      travelled += std::fabs(s.v) * robot.stepSeconds();
      const Pose2 truth = start.inverse() * s.pose;
      const double error = std::hypot(odom.pose().x - truth.x, odom.pose().y - truth.y);
      if (!passed10 && travelled >= 10.0) {
        passed10 = true;
        at10 += error / seeds;
        covariance10 += odom.take(0).covariance.trace() / seeds;
      }
      if (travelled >= 60.0) {
        at60 += error / seeds;
        covariance60 += odom.take(1).covariance.trace() / seeds;
      }
    }
    ASSERT_GE(travelled, 60.0);
  }
  EXPECT_GT(at10, 0.001);
  EXPECT_GT(at60, 2.0 * at10);
  EXPECT_GT(covariance60, 3.0 * covariance10);  // consumer 1 accumulated 60 m, consumer 0 10 m
}

TEST(SimImu, AtRestItReadsGravityAndItsGyroIntegratesToTheYawChange) {
  const ReferencePath path(loopRoute(), MotionLimits());
  RobotSimulator robot(path);
  ImuModel exact(ImuNoise::none(), 200.0, 1);
  ImuModel noisy(ImuNoise(), 200.0, rtabmap::test::drawSeed(1));
  double integrated = 0.0, noisyIntegrated = 0.0, trueYaw = 0.0, noisyWindowTruth = 0.0;
  long long steps = 0;
  int restSamples = 0;
  Eigen::Vector3d noisyRest = Eigen::Vector3d::Zero();
  while (!robot.finished()) {
    const RobotState& s = robot.step();
    trueYaw += s.omega * robot.stepSeconds();
    exact.accumulate(robot.stepSeconds(), s.v, s.omega, s.acceleration);
    noisy.accumulate(robot.stepSeconds(), s.v, s.omega, s.acceleration);
    if (++steps % 5) continue;  // 200 Hz
    const ImuSample a = exact.sample(s.t);
    const ImuSample b = noisy.sample(s.t);
    integrated += a.angularVelocity.z() * 0.005;
    if (s.t <= 10.0) {
      noisyIntegrated += b.angularVelocity.z() * 0.005;
      noisyWindowTruth = trueYaw;
    }
    if (s.t < path.limits().dwell - 0.01) {  // the robot has not moved yet
      EXPECT_EQ(a.linearAcceleration, Eigen::Vector3d(0, 0, kGravity));
      EXPECT_EQ(a.angularVelocity, Eigen::Vector3d::Zero());
      noisyRest += b.linearAcceleration;
      ++restSamples;
    }
  }
  // The steps after the last 200 Hz sample: the robot may still be settling its heading there
  // (1.8e-7 rad left out on another building's route).
  if (steps % 5) integrated += exact.sample(robot.state().t).angularVelocity.z() * (steps % 5) * robot.stepSeconds();
  ASSERT_GT(restSamples, 150);
  EXPECT_NEAR(integrated, trueYaw, 1e-7);  // the same sum, added up in another order
  EXPECT_GT(std::fabs(trueYaw), 2.0 * M_PI - 0.5);  // at least a lap
  // With the noise model: the turn-on bias (2e-3 rad/s, 1 sigma) is all that accumulates.
  EXPECT_NEAR(noisyIntegrated, noisyWindowTruth, 0.1);
  noisyRest /= restSamples;
  EXPECT_NEAR(noisyRest.z(), kGravity, 0.15);
  EXPECT_NEAR(noisyRest.head<2>().norm(), 0.0, 0.15);
}
