// The odometry base: motion model, external guess, lost / recovery / reset (JFR 2019, 3.1).
#include "rtabmap_core/odometry/Odometry.h"

#include <opencv2/core.hpp>

#include <Eigen/Geometry>

#include <chrono>
#include <cmath>
#include <exception>
#include <optional>

#include "GroundAlignment.h"
#include "GyroIntegration.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"
#include "rtabmap_core/geometry/IMU.h"
#include "rtabmap_core/geometry/ImageRectification.h"

namespace rtabmap {
namespace {

using Twist = Eigen::Matrix<double, 6, 1>;

// Covariance reported when lost: the ROS convention for "no information".
constexpr double kLostVariance = 9999.0;

// Motion as a twist (translation, rotation vector), and back: scaling a twist scales the
// motion along its screw, which Euler angles would not do.
Twist toTwist(const Transform& t) {
  const Eigen::AngleAxisd aa(t.rotationMatrix());
  Twist v;
  v.head<3>() = t.translation();
  v.tail<3>() = aa.axis() * aa.angle();
  return v;
}

Transform fromTwist(const Twist& v) {
  Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
  const double angle = v.tail<3>().norm();
  if (angle > 1e-12) iso.linear() = Eigen::AngleAxisd(angle, v.tail<3>() / angle).toRotationMatrix();
  iso.translation() = v.head<3>();
  return Transform(iso);
}

}  // namespace

Transform Odometry::withImuRotation(const Transform& guess, const Eigen::Matrix3d& imuRotation) const {
  Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
  iso.linear() = imuRotation;
  if (!guess.isNull()) iso.translation() = guess.translation();  // else: turning on the spot
  const Transform t(iso);
  return force3DoF_ ? t.to3DoF() : t;
}

Odometry::~Odometry() = default;

bool Odometry::addImu(double stamp, const IMU& imu) { return gyro_->add(stamp, imu); }

std::optional<Eigen::Matrix3d> Odometry::imuRotationBetween(double t0, double t1) const {
  return gyro_->rotationBetween(t0, t1);
}

Odometry::Odometry(const ParametersMap& parameters)
    : parameters_(parameters), gyro_(std::make_unique<odometry_detail::GyroIntegration>()) {
  Parameters::validate(parameters_);
  resetCountdown_ = Parameters::getInt(parameters_, Parameters::kOdomResetCountdown());
  guessMotion_ = Parameters::getBool(parameters_, Parameters::kOdomGuessMotion());
  guessSmoothingDelay_ = Parameters::getDouble(parameters_, Parameters::kOdomGuessSmoothingDelay());
  force3DoF_ = Parameters::getBool(parameters_, Parameters::kRegForce3DoF());
  holonomic_ = Parameters::getBool(parameters_, Parameters::kOdomHolonomic());
  imagesAlreadyRectified_ = Parameters::getBool(parameters_, Parameters::kRtabmapImagesAlreadyRectified());
  alignWithGround_ = Parameters::getBool(parameters_, Parameters::kOdomAlignWithGround());
}

Transform Odometry::process(SensorData& data, OdometryInfo* info) { return process(data, Transform(), info); }

Transform Odometry::predictMotion(double dt) const {
  if (dt <= 0.0) return lastMotion_;
  if (velocityTransform_.isNull()) return Transform();
  return fromTwist(toTwist(velocityTransform_) * dt);
}

void Odometry::updateVelocity(const Transform& motion, double dt, double stamp) {
  lastMotion_ = motion;
  if (dt <= 0.0) {
    velocityTransform_ = Transform();
    velocityHistory_.clear();
    return;
  }
  const Twist v = toTwist(motion) / dt;
  if (guessSmoothingDelay_ <= 0.0) {
    velocityTransform_ = fromTwist(v);
    return;
  }
  // Average of the velocities of the last Odom/GuessSmoothingDelay seconds: a noisy single
  // motion does not throw the next prediction off.
  velocityHistory_.emplace_back(stamp, v);
  while (!velocityHistory_.empty() && velocityHistory_.front().first < stamp - guessSmoothingDelay_) {
    velocityHistory_.pop_front();
  }
  Twist mean = Twist::Zero();
  for (const auto& [s, w] : velocityHistory_) mean += w;
  mean /= static_cast<double>(velocityHistory_.size());
  velocityTransform_ = fromTwist(mean);
}

Transform Odometry::reportLost(SensorData& data, OdometryInfo& info) {
  ++lostCount_;
  info.lost = true;
  if (info.lostReason.empty()) info.lostReason = "no transform found";
  info.transform = Transform();
  info.covariance = Eigen::Matrix<double, 6, 6>::Identity() * kLostVariance;
  // The motion model is no longer trustworthy: the next frame registers without its prediction.
  // The IMU's measure of the turn since the last pose (pose_ has not moved) still holds, and
  // guides the next frame (turning on the spot).
  velocityTransform_ = Transform();
  lastMotion_ = Transform();
  velocityHistory_.clear();
  data.setOdom(Transform(), info.covariance);
  if (resetCountdown_ > 0 && lostCount_ >= resetCountdown_) {
    RTABMAP_WARN("odometry lost for " << lostCount_ << " frames (Odom/ResetCountdown " << resetCountdown_
                                      << "): reset at the last pose " << pose_.prettyPrint());
    const Transform last = pose_;
    reset(last);
    info.autoReset = true;
  }
  return Transform();
}

Transform Odometry::process(SensorData& data, const Transform& externalGuess, OdometryInfo* infoOut) {
  const auto start = std::chrono::steady_clock::now();
  OdometryInfo localInfo;
  OdometryInfo& info = infoOut ? *infoOut : localInfo;
  info = OdometryInfo();
  info.stamp = data.stamp();
  const double dt = (previousStamp_ > 0.0 && data.stamp() > 0.0) ? data.stamp() - previousStamp_ : 0.0;
  info.interval = dt;
  auto finish = [&](const Transform& result) {
    info.timeTotalMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (data.stamp() > 0.0) previousStamp_ = data.stamp();
    ++framesProcessed_;
    return result;
  };
  // Rtabmap/ImagesAlreadyRectified false: the frame goes on (to SLAM too) rectified, with
  // rectified models, so nothing downstream rectifies it again.
  if (!imagesAlreadyRectified_ && needsRectification(data)) {
    try {
      data = rectifyImages(data);
    } catch (const std::exception& e) {
      info.lostReason = std::string("the images cannot be rectified (Rtabmap/ImagesAlreadyRectified false): ") + e.what();
      return finish(reportLost(data, info));
    }
  }

  // Odom/AlignWithGround: the first frame from the origin (not from a pose a reset asked for)
  // starts level with the floor it sees.
  if (alignWithGround_ && framesProcessed_ == 0 && pose_.isIdentity()) {
    std::string why;
    const Transform level = odometry_detail::groundAlignedPose(data, &why);
    if (level.isNull()) {
      RTABMAP_WARN("Odom/AlignWithGround: " << why << "; odometry starts at the origin, not levelled");
    } else {
      RTABMAP_INFO("Odom/AlignWithGround: odometry starts at " << level.prettyPrint() << " (level with the floor)");
      reset(level);
    }
  }

  // A frame with an IMU orientation (a filter's, e.g. the odometry node's imu topic): the base's
  // orientation in the IMU's gravity-aligned frame.
  const Transform imuOrientation = baseOrientationFromImu(data.imu());
  if (!imuOrientation.isNull() && framesProcessed_ == 0 && pose_.isIdentity() && !force3DoF_) {
    // The odometry frame's z axis up, as the original's odometry nodes do with an IMU: the
    // first pose takes the IMU's roll and pitch (its heading means nothing to the map).
    double roll, pitch, yaw;
    imuOrientation.getEulerAngles(roll, pitch, yaw);
    const Transform level(0.0, 0.0, 0.0, roll, pitch, 0.0);
    RTABMAP_INFO("odometry starts at " << level.prettyPrint() << " (levelled by the IMU)");
    reset(level);
  }

  const bool initialising = needsInitialisation();
  Transform guess;
  if (!initialising) {
    if (!externalGuess.isNull()) {
      guess = externalGuess;
    } else if (guessMotion_) {
      guess = predictMotion(dt);
      // The IMU measures the turn since the last pose, where the constant-velocity model only
      // extrapolates the previous one (a robot starting or stopping a turn): from orientations
      // when the frames carry them, else from the raw gyroscope samples given (addImu).
      std::optional<Eigen::Matrix3d> turn;
      if (!imuOrientation.isNull() && !imuAtPose_.isNull()) {
        turn = (imuAtPose_.inverse() * imuOrientation).rotationMatrix();
      } else if (!gyro_->empty() && stampAtPose_ > 0.0 && data.stamp() > stampAtPose_) {
        turn = gyro_->rotationBetween(stampAtPose_, data.stamp());
      }
      if (turn) {
        guess = withImuRotation(guess, *turn);
        info.guessFromImu = true;
      }
    }
  }
  info.guess = guess;

  // Bad sensor data must never escape as an exception: it is a lost frame with its reason.
  auto attempt = [&](const Transform& g) {
    try {
      return computeTransform(data, g, &info);
    } catch (const Error& e) {
      info.lostReason = e.what();
    } catch (const cv::Exception& e) {
      info.lostReason = std::string("OpenCV error: ") + e.what();
    } catch (const std::exception& e) {
      info.lostReason = e.what();
    }
    return Transform();
  };
  const auto t0 = std::chrono::steady_clock::now();
  Transform motion = attempt(guess);
  if (motion.isNull() && !guess.isNull() && !initialising) {
    // A wrong prediction (sudden stop, jerk) can put the search windows in the wrong place:
    // try once more matching over the whole image.
    const std::string guided = info.lostReason;
    info.lostReason.clear();
    info.reg = RegistrationInfo();
    info.retriedWithoutGuess = true;
    motion = attempt(Transform());
    if (motion.isNull()) {
      info.lostReason += " (also tried with the motion prediction: " + guided + ")";
    }
  }
  info.timeEstimationMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (motion.isNull() || motion.isInvalid()) {
    if (!motion.isNull()) info.lostReason = "the transform found is not finite";
    return finish(reportLost(data, info));
  }

  if (force3DoF_) motion = motion.to3DoF();
  if (!holonomic_) {
    // A non-holonomic base cannot slide sideways: its lateral displacement follows from the
    // forward one and the heading change.
    double x, y, z, roll, pitch, yaw;
    motion.getTranslationAndEulerAngles(x, y, z, roll, pitch, yaw);
    motion = Transform(x, x * std::tan(yaw), z, roll, pitch, yaw);
  }
  lostCount_ = 0;
  pose_ = (pose_ * motion).normalized();
  imuAtPose_ = imuOrientation;  // null without one: the next frame's turn is not measured
  if (data.stamp() > 0.0) {
    stampAtPose_ = data.stamp();
    gyro_->dropBefore(stampAtPose_);
  }
  distanceTravelled_ += motion.getNorm();
  updateVelocity(motion, dt, data.stamp());
  info.lost = false;
  info.lostReason.clear();
  info.transform = motion;
  info.distanceTravelled = distanceTravelled_;
  if (info.covariance.isIdentity() && info.reg.success) info.covariance = info.reg.covariance;
  data.setOdom(pose_, info.covariance);
  return finish(pose_);
}

void Odometry::reset(const Transform& initialPose) {
  pose_ = initialPose.isNull() ? Transform::Identity() : initialPose;
  velocityTransform_ = Transform();
  lastMotion_ = Transform();
  imuAtPose_ = Transform();
  stampAtPose_ = 0.0;
  gyro_->clear();  // a reset may follow ROS time jumping back: older samples come again
  velocityHistory_.clear();
  previousStamp_ = 0.0;
  framesProcessed_ = 0;
  lostCount_ = 0;
  distanceTravelled_ = 0.0;
  resetMap(pose_);
}

}  // namespace rtabmap
