// The odometry base: factory, motion model, external guess, retry without prediction, lost
// convention, reset countdown (with a scripted approach), and parameter errors.
#include <gtest/gtest.h>

#include <cmath>
#include <deque>

#include <Eigen/Geometry>

#include "common/DistortedFrames.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/geometry/IMU.h"
#include "rtabmap_core/odometry/Odometry.h"

namespace rtabmap {
namespace {

// An approach whose registration answers from a script, and records what it was asked.
class ScriptedOdometry : public Odometry {
 public:
  explicit ScriptedOdometry(const ParametersMap& p = {}) : Odometry(p) {}
  Type type() const override { return Type::kF2F; }

  std::deque<Transform> answers;  // null = registration fails
  std::vector<Transform> guesses;
  std::vector<bool> rectifiedInput;  // per registration: did its frame come with rectified models
  int resets = 0;

 protected:
  Transform computeTransform(SensorData& data, const Transform& guess, OdometryInfo* info) override {
    guesses.push_back(guess);
    rectifiedInput.push_back(!data.cameraModels().empty() && data.cameraModels().front().isRectified());
    if (!initialised_) {
      initialised_ = true;
      return Transform::Identity();
    }
    Transform t = answers.empty() ? Transform() : answers.front();
    // A failed answer is consumed only when there is no guess, so a guided failure can be
    // retried unguided with the next answer.
    if (!answers.empty()) answers.pop_front();
    if (t.isNull()) info->lostReason = "scripted failure";
    return t;
  }
  void resetMap(const Transform&) override {
    initialised_ = false;
    ++resets;
  }
  bool needsInitialisation() const override { return !initialised_; }

 private:
  bool initialised_ = false;
};

SensorData frameAt(double stamp) {
  SensorData d;
  d.setStamp(stamp);
  return d;
}

TEST(Odometry, ConstantVelocityPrediction) {
  ScriptedOdometry odom;
  const Transform step(0.1, 0.0, 0.0, 0.0, 0.0, 0.05);
  odom.answers = {step, step};
  SensorData a = frameAt(1.0), b = frameAt(1.1), c = frameAt(1.3);
  OdometryInfo info;
  EXPECT_TRUE(odom.process(a, &info).isIdentity());
  EXPECT_TRUE(info.guess.isNull());  // first frame: nothing to predict from
  odom.process(b, &info);
  EXPECT_TRUE(info.guess.isNull());  // no velocity yet
  const Transform pose = odom.process(c, &info);
  // Twice the interval: twice the last motion.
  ASSERT_FALSE(info.guess.isNull());
  EXPECT_NEAR(info.guess.x(), 0.2, 1e-9);
  EXPECT_NEAR(info.guess.yaw(), 0.1, 1e-9);
  EXPECT_NEAR(info.interval, 0.2, 1e-12);
  EXPECT_LT(pose.getDistance(step * step), 1e-9);
  EXPECT_NEAR(info.distanceTravelled, 0.2, 1e-9);
  EXPECT_EQ(odom.framesProcessed(), 3);
}

TEST(Odometry, ExternalGuessReplacesThePrediction) {
  ScriptedOdometry odom;
  odom.answers = {Transform(0.1, 0, 0, 0, 0, 0), Transform(0.1, 0, 0, 0, 0, 0)};
  SensorData a = frameAt(1.0), b = frameAt(1.1), c = frameAt(1.2);
  odom.process(a);
  odom.process(b);
  const Transform wheel(0.3, 0.1, 0, 0, 0, 0.2);
  OdometryInfo info;
  odom.process(c, wheel, &info);
  EXPECT_EQ(info.guess, wheel);
  EXPECT_EQ(odom.guesses.back(), wheel);
}

TEST(Odometry, RetriesWithoutPredictionThenReportsLost) {
  ScriptedOdometry odom;
  odom.answers = {Transform(0.1, 0, 0, 0, 0, 0), Transform(), Transform(0.1, 0, 0, 0, 0, 0)};
  SensorData a = frameAt(1.0), b = frameAt(1.1), c = frameAt(1.2);
  odom.process(a);
  odom.process(b);
  OdometryInfo info;
  // Guided attempt fails, unguided one succeeds.
  EXPECT_FALSE(odom.process(c, &info).isNull());
  EXPECT_TRUE(info.retriedWithoutGuess);
  ASSERT_GE(odom.guesses.size(), 2u);
  EXPECT_FALSE(odom.guesses[odom.guesses.size() - 2].isNull());
  EXPECT_TRUE(odom.guesses.back().isNull());
  // Both fail: lost, null pose, 9999 covariance, the odometry of the frame cleared.
  odom.answers = {Transform(), Transform()};
  SensorData d = frameAt(1.3);
  EXPECT_TRUE(odom.process(d, &info).isNull());
  EXPECT_TRUE(info.lost);
  EXPECT_NE(info.lostReason.find("scripted failure"), std::string::npos) << info.lostReason;
  EXPECT_DOUBLE_EQ(info.covariance(0, 0), 9999.0);
  EXPECT_TRUE(d.odomPose().isNull());
  EXPECT_DOUBLE_EQ(d.odomCovariance()(3, 3), 9999.0);
  EXPECT_EQ(odom.lostCount(), 1);
  // Recovery: no prediction after a loss; the pose continues from the last one.
  odom.answers = {Transform(0.1, 0, 0, 0, 0, 0)};
  SensorData e = frameAt(1.4);
  const Transform pose = odom.process(e, &info);
  EXPECT_TRUE(info.guess.isNull());
  EXPECT_NEAR(pose.x(), 0.3, 1e-9);
  EXPECT_EQ(odom.lostCount(), 0);
  EXPECT_FALSE(e.odomPose().isNull());
}

TEST(Odometry, ResetCountdownAndManualReset) {
  ScriptedOdometry odom(ParametersMap{{"Odom/ResetCountdown", "3"}});
  odom.answers = {Transform(0.5, 0, 0, 0, 0, 0)};
  SensorData a = frameAt(1.0), b = frameAt(1.1);
  odom.process(a);
  odom.process(b);
  OdometryInfo info;
  for (int i = 0; i < 3; ++i) {
    SensorData d = frameAt(1.2 + 0.1 * i);
    odom.process(d, &info);
    EXPECT_TRUE(info.lost);
    EXPECT_EQ(info.autoReset, i == 2);
  }
  EXPECT_EQ(odom.resets, 1);
  EXPECT_NEAR(odom.getPose().x(), 0.5, 1e-9);  // reset at the last pose
  odom.reset(Transform(1, 2, 3, 0, 0, 0));
  EXPECT_EQ(odom.framesProcessed(), 0);
  EXPECT_NEAR(odom.getPose().y(), 2.0, 1e-12);
}

TEST(Odometry, Force3DoFAndNonHolonomic) {
  ScriptedOdometry flat(ParametersMap{{"Reg/Force3DoF", "true"}});
  flat.answers = {Transform(0.1, 0.05, 0.2, 0.1, 0.1, 0.2)};
  SensorData a = frameAt(1.0), b = frameAt(1.1);
  flat.process(a);
  const Transform p = flat.process(b);
  EXPECT_DOUBLE_EQ(p.z(), 0.0);
  EXPECT_NEAR(p.roll(), 0.0, 1e-12);
  ScriptedOdometry car(ParametersMap{{"Odom/Holonomic", "false"}});
  car.answers = {Transform(0.2, 0.5, 0, 0, 0, 0.1)};
  SensorData c = frameAt(1.0), d = frameAt(1.1);
  car.process(c);
  const Transform q = car.process(d);
  EXPECT_NEAR(q.y(), 0.2 * std::tan(0.1), 1e-9);
}

// Rtabmap/ImagesAlreadyRectified false: the registration gets the rectified frame, and so does
// the caller (SLAM then has nothing left to rectify); an image that does not fit its
// calibration is a lost frame with the reason.
TEST(Odometry, RawImagesAreRectifiedBeforeRegistrationWhenNotAlreadyRectified) {
  const CameraModel camera = test::distortedCamera();
  for (const bool already : {true, false}) {
    SCOPED_TRACE(already ? "default" : "Rtabmap/ImagesAlreadyRectified false");
    ScriptedOdometry odom(ParametersMap{{"Rtabmap/ImagesAlreadyRectified", already ? "true" : "false"}});
    SensorData frame(test::distort(test::blockTexture(), camera), test::rampDepth(), camera, 1, 1.0);
    ASSERT_FALSE(odom.process(frame).isNull());
    ASSERT_EQ(odom.rectifiedInput.size(), 1u);
    EXPECT_EQ(odom.rectifiedInput.back(), !already);
    EXPECT_EQ(frame.cameraModels().front().isRectified(), !already);
    if (!already) {
      EXPECT_EQ(cv::norm(frame.imageRaw(), camera.rectifyImage(test::distort(test::blockTexture(), camera)),
                         cv::NORM_INF),
                0.0);
      cv::Mat small;
      cv::resize(test::blockTexture(), small, cv::Size(160, 120));
      SensorData wrong(small, cv::Mat(), camera, 2, 2.0);
      OdometryInfo info;
      EXPECT_TRUE(odom.process(wrong, &info).isNull());
      EXPECT_NE(info.lostReason.find("cannot be rectified"), std::string::npos) << info.lostReason;
    }
  }
}

// A 160x120 RGB-D frame of a flat floor seen from a base 1.2 m above it, pitched down by
// `pitch` (rad): depth by intersecting each pixel's ray with the floor.
SensorData floorFrame(double pitch) {
  const CameraModel camera(120.0, 120.0, 79.5, 59.5, CameraModel::opticalRotation(), 0.0, cv::Size(160, 120));
  const Transform base(0.0, 0.0, 1.2, 0.0, pitch, 0.0);
  const Transform sensor = base * camera.localTransform();
  cv::Mat depth(120, 160, CV_32FC1, cv::Scalar(0.0f));
  for (int v = 0; v < depth.rows; ++v) {
    for (int u = 0; u < depth.cols; ++u) {
      const Eigen::Vector3d ray((u - camera.cx()) / camera.fx(), (v - camera.cy()) / camera.fy(), 1.0);
      const Eigen::Vector3d w = sensor.rotationMatrix() * ray;  // z of the ray in the optical frame is 1
      if (w.z() < -1e-3) depth.at<float>(v, u) = static_cast<float>(1.2 / -w.z());
    }
  }
  return SensorData(cv::Mat(120, 160, CV_8UC3, cv::Scalar(128, 128, 128)), depth, camera, 1, 1.0);
}

// Odom/AlignWithGround: the first pose is level with the floor, at the base's height above it.
TEST(Odometry, AlignWithGroundStartsLevelWithTheFloor) {
  for (const bool align : {false, true}) {
    SCOPED_TRACE(align ? "Odom/AlignWithGround" : "default");
    ScriptedOdometry odom(ParametersMap{{"Odom/AlignWithGround", align ? "true" : "false"}});
    SensorData frame = floorFrame(0.45);
    ASSERT_FALSE(odom.process(frame).isNull());
    if (!align) {
      EXPECT_TRUE(odom.getPose().isIdentity());
      continue;
    }
    double x, y, z, roll, pitch, yaw;
    odom.getPose().getTranslationAndEulerAngles(x, y, z, roll, pitch, yaw);
    EXPECT_NEAR(z, 1.2, 0.02);
    EXPECT_NEAR(pitch, 0.45, 0.01);
    EXPECT_NEAR(roll, 0.0, 0.01);
    EXPECT_NEAR(yaw, 0.0, 0.01);
    EXPECT_NEAR(std::hypot(x, y), 0.0, 1e-9);
  }
  // No floor in view (a frame without depth): the origin, and odometry goes on.
  ScriptedOdometry blind(ParametersMap{{"Odom/AlignWithGround", "true"}});
  SensorData frame = frameAt(1.0);
  EXPECT_FALSE(blind.process(frame).isNull());
  EXPECT_TRUE(blind.getPose().isIdentity());
}

// A frame whose IMU (mounted turned and upside down on the base) reports the base at `base`'s
// orientation in its gravity-aligned world.
SensorData imuFrameAt(double stamp, const Transform& base) {
  const Transform mount(0.05, 0.0, 0.1, M_PI, 0.0, M_PI_2);
  const Eigen::Quaterniond q = (base * mount).quaternion();
  IMU imu;
  imu.orientation = q;
  imu.localTransform = mount;
  SensorData d = frameAt(stamp);
  d.setIMU(imu);
  return d;
}

double angleBetween(const Transform& a, const Transform& b) {
  return Eigen::AngleAxisd(a.rotationMatrix().transpose() * b.rotationMatrix()).angle();
}

// An IMU orientation levels the first pose and gives the guess its rotation: the robot starts
// a turn the constant-velocity model cannot foresee.
TEST(Odometry, ImuLevelsTheStartAndGivesTheGuessItsRotation) {
  ScriptedOdometry odom;
  const Transform tilt(0, 0, 0, 0.1, -0.2, 0.7);  // on a ramp, heading 0.7 in the IMU's world
  const Transform step(0.1, 0.0, 0.0, 0.0, 0.0, 0.0);
  const Transform turn(0.1, 0.0, 0.0, 0.0, 0.0, 0.3);
  odom.answers = {step, turn};
  SensorData a = imuFrameAt(1.0, tilt), b = imuFrameAt(1.1, tilt * step), c = imuFrameAt(1.2, tilt * step * turn);
  OdometryInfo info;
  odom.process(a, &info);
  double x, y, z, roll, pitch, yaw;
  odom.getPose().getTranslationAndEulerAngles(x, y, z, roll, pitch, yaw);
  EXPECT_NEAR(roll, 0.1, 1e-9);
  EXPECT_NEAR(pitch, -0.2, 1e-9);
  EXPECT_NEAR(yaw, 0.0, 1e-9) << "the IMU's heading is not the map's";
  EXPECT_NEAR(Transform(x, y, z, 0, 0, 0).getNorm(), 0.0, 1e-12);
  // Second frame: no velocity yet, but the IMU says the robot did not turn.
  odom.process(b, &info);
  ASSERT_FALSE(info.guess.isNull());
  EXPECT_TRUE(info.guessFromImu);
  EXPECT_LT(angleBetween(info.guess, Transform::Identity()), 1e-9);
  EXPECT_NEAR(info.guess.translation().norm(), 0.0, 1e-12);
  // Third: the constant-velocity translation with the IMU's 0.3 rad turn.
  odom.process(c, &info);
  EXPECT_TRUE(info.guessFromImu);
  EXPECT_NEAR(info.guess.x(), 0.1, 1e-9);
  EXPECT_LT(angleBetween(info.guess, turn), 1e-9);
  EXPECT_EQ(odom.guesses.back(), info.guess);

  // An external guess (wheel odometry) is left as given; a frame without an IMU falls back to
  // the constant-velocity model, and the one after it to that too (no orientation at the pose).
  odom.answers = {step, step, step};
  SensorData d = imuFrameAt(1.3, tilt * step * turn * step);
  odom.process(d, step, &info);
  EXPECT_FALSE(info.guessFromImu);
  EXPECT_EQ(info.guess, step);
  SensorData e = frameAt(1.4);
  odom.process(e, &info);
  EXPECT_FALSE(info.guessFromImu);
  SensorData f = imuFrameAt(1.5, tilt * step * turn * step * step * step);
  odom.process(f, &info);
  EXPECT_FALSE(info.guessFromImu);
  EXPECT_LT(angleBetween(info.guess, step), 1e-9);
}

// Reg/Force3DoF keeps the odometry planar: no levelling, and a planar rotation in the guess.
// A reset to a given pose keeps it.
TEST(Odometry, ImuWithForce3DoFOrAGivenStartPose) {
  const Transform tilt(0, 0, 0, 0.1, -0.2, 0.7);
  ScriptedOdometry planar(ParametersMap{{"Reg/Force3DoF", "true"}});
  const Transform turn(0.1, 0.0, 0.0, 0.0, 0.0, 0.3);
  planar.answers = {turn};
  SensorData a = imuFrameAt(1.0, tilt), b = imuFrameAt(1.1, tilt * turn);
  OdometryInfo info;
  planar.process(a, &info);
  EXPECT_TRUE(planar.getPose().isIdentity());
  planar.process(b, &info);
  ASSERT_TRUE(info.guessFromImu);
  EXPECT_NEAR(info.guess.roll(), 0.0, 1e-12);
  EXPECT_NEAR(info.guess.pitch(), 0.0, 1e-12);
  EXPECT_NEAR(info.guess.yaw(), 0.3, 1e-9);

  ScriptedOdometry given;
  const Transform start(1, 2, 0, 0, 0, 0.5);
  given.reset(start);
  SensorData c = imuFrameAt(2.0, tilt);
  given.process(c, &info);
  EXPECT_EQ(given.getPose(), start);
}

// Raw gyroscope samples (no orientation in the frames): the guess turns as the IMU measured
// between the last pose's frame and this one; frames the samples do not cover keep the
// constant-velocity guess.
TEST(Odometry, GyroscopeSamplesGiveTheGuessItsRotation) {
  ScriptedOdometry odom;
  const Transform step(0.1, 0.0, 0.0, 0.0, 0.0, 0.0);
  odom.answers = {step, step, step};
  const Transform mount(0.0, 0.0, 0.15, M_PI, 0.0, 0.0);  // upside down: its z is the base's -z
  IMU imu;
  imu.localTransform = mount;
  auto yawRate = [&](double t0, double t1, double rate) {
    for (double t = t0; t <= t1 + 1e-9; t += 0.005) {
      imu.angularVelocity = Eigen::Vector3d(0, 0, -rate);
      odom.addImu(t, imu);
    }
  };
  OdometryInfo info;
  SensorData a = frameAt(1.0), b = frameAt(1.1), c = frameAt(1.2), d = frameAt(1.5);
  yawRate(0.9, 1.0, 0.0001);
  odom.process(a, &info);
  EXPECT_TRUE(odom.getPose().isIdentity()) << "no orientation: nothing to level with";
  yawRate(1.005, 1.1, 2.0);  // starting a turn at 2 rad/s
  odom.process(b, &info);
  ASSERT_TRUE(info.guessFromImu);
  // 0.19 rad at 2 rad/s from 1.005 to 1.1, and 0.005 over the sample period where the rate
  // rose (two samples' mean).
  EXPECT_NEAR(info.guess.yaw(), 0.195, 1e-4);
  EXPECT_NEAR(info.guess.translation().norm(), 0.0, 1e-12) << "no velocity yet";
  yawRate(1.105, 1.2, 1.0);
  odom.process(c, &info);
  ASSERT_TRUE(info.guessFromImu);
  EXPECT_NEAR(info.guess.yaw(), 0.0075 + 0.095, 1e-4);
  EXPECT_NEAR(info.guess.x(), 0.1, 1e-9);
  // 0.3 s later, without samples since 1.2: the constant-velocity model.
  odom.process(d, &info);
  EXPECT_FALSE(info.guessFromImu);
  EXPECT_NEAR(info.guess.x(), 0.3, 1e-9);

  // A lost frame drops the velocity, not the gyroscope's measure since the last pose: the frame
  // after it is guided by the turn alone.
  odom.answers = {Transform(), Transform(), step};
  yawRate(1.505, 1.6, 1.0);
  SensorData e = frameAt(1.6);
  EXPECT_TRUE(odom.process(e, &info).isNull());
  yawRate(1.605, 1.7, 1.0);
  SensorData f = frameAt(1.7);
  odom.process(f, &info);
  ASSERT_TRUE(info.guessFromImu);
  EXPECT_NEAR(info.guess.yaw(), 0.2, 1e-4) << "the turn since frame d, the last pose";
  EXPECT_NEAR(info.guess.translation().norm(), 0.0, 1e-12);
}

TEST(Odometry, FactoryAndNames) {
  EXPECT_EQ(Odometry::create()->type(), Odometry::Type::kF2M);
  EXPECT_EQ(Odometry::create({{"Odom/Strategy", "1"}})->type(), Odometry::Type::kF2F);
  EXPECT_EQ(Odometry::create(Odometry::Type::kF2F)->type(), Odometry::Type::kF2F);
  // Reg/Strategy 1 (ICP only) selects the lidar approaches.
  EXPECT_EQ(Odometry::create({{"Reg/Strategy", "1"}})->type(), Odometry::Type::kS2M);
  EXPECT_EQ(Odometry::create({{"Reg/Strategy", "1"}, {"Odom/Strategy", "1"}})->type(), Odometry::Type::kS2S);
  EXPECT_EQ(Odometry::create(Odometry::Type::kS2S)->type(), Odometry::Type::kS2S);
  EXPECT_EQ(Odometry::typeFromName("f2m"), Odometry::Type::kF2M);
  EXPECT_EQ(Odometry::typeFromName("S2S"), Odometry::Type::kS2S);
  EXPECT_EQ(Odometry::typeName(Odometry::Type::kS2M), "S2M");
  EXPECT_THROW(Odometry::typeFromName("icp"), ParameterError);
  EXPECT_THROW(Odometry::create({{"Odom/NoSuchKey", "1"}}), ParameterError);
  EXPECT_THROW(Odometry::create({{"Vis/MinDepth", "5"}, {"Vis/MaxDepth", "1"}}), ParameterError);
  EXPECT_THROW(Odometry::create({{"Odom/KeyFrameThr", "2"}}), ParameterError);
}

}  // namespace
}  // namespace rtabmap
