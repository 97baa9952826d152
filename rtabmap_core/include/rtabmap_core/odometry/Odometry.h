#pragma once
// Odometry: the pose of each new frame in the odometry frame, from the frame alone (visual or
// lidar registration against a local map or the last key frame) and optionally a motion guess
// (wheel odometry). The concrete approaches (JFR 2019, section 3):
//   OdometryF2M  visual frame-to-map    (Odom/Strategy 0, images)
//   OdometryF2F  visual frame-to-frame  (Odom/Strategy 1, images)
//   OdometryS2M  lidar scan-to-map      (Odom/Strategy 0, Reg/Strategy 1)
//   OdometryS2S  lidar scan-to-scan     (Odom/Strategy 1, Reg/Strategy 1)
// This base class owns what they share: the constant-velocity motion model, the external
// guess, lost / recovery / reset countdown, the covariance convention, timing.
//
// An IMU: frames carrying its orientation (SensorData::imu(), e.g. a Madgwick filter's through
// the odometry node's imu topic) give the first pose the IMU's roll and pitch, so the odometry
// frame's z axis is up (not with Reg/Force3DoF, nor after a reset to a given pose), and the
// constant-velocity guess the rotation the IMU measured since the last pose. Without
// orientations, the raw gyroscope samples given to addImu() measure that rotation (integrated
// between the frames' stamps). An external guess is left as given.
#include <Eigen/Core>

#include <deque>
#include <memory>
#include <optional>
#include <string>

#include "rtabmap_core/geometry/IMU.h"
#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/params/Parameters.h"
#include "rtabmap_core/registration/RegistrationInfo.h"

namespace rtabmap {

namespace odometry_detail {
class GyroIntegration;
}

// What one odometry update did (published as rtabmap_ros/OdomInfo).
struct OdometryInfo {
  bool lost = false;
  std::string lostReason;          // why no transform was found this frame (empty if found)
  RegistrationInfo reg;            // details of the registration of this frame
  int features = 0;                // features extracted from the frame
  int localMapSize = 0;            // F2M: 3D features in the map
  int localScanMapSize = 0;        // S2M: points in the scan map
  int localKeyFrames = 0;          // key frames contributing to the local map
  bool keyFrameAdded = false;
  bool autoReset = false;          // Odom/ResetCountdown reached: the map was reset this frame
  bool retriedWithoutGuess = false;  // the guided registration failed and was run again unguided
  double timeEstimationMs = 0.0;   // registration
  double timeTotalMs = 0.0;        // whole process()
  double stamp = 0.0;
  double interval = 0.0;           // s since the previous frame
  double distanceTravelled = 0.0;  // m, sum of |translation| since reset
  Transform transform;             // incremental motion found this frame (null if lost)
  Transform guess;                 // motion guess used (null if none)
  bool guessFromImu = false;       // its rotation is the IMU's since the last pose
  // Covariance of the incremental motion (x y z roll pitch yaw); lost => 9999 on the diagonal.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Identity();
};

class Odometry {
 public:
  enum class Type { kF2M, kF2F, kS2M, kS2S };

  // Picks the approach from Odom/Strategy and Reg/Strategy (1 = ICP only => lidar), validates
  // every parameter (ParameterError naming the key otherwise).
  static std::unique_ptr<Odometry> create(const ParametersMap& parameters = {});
  // A given approach, whatever Odom/Strategy and Reg/Strategy say (other parameters apply).
  static std::unique_ptr<Odometry> create(Type type, const ParametersMap& parameters = {});
  // "F2M", "F2F", "S2M", "S2S"; typeFromName accepts them in any case and throws
  // ParameterError naming the accepted names otherwise.
  static std::string typeName(Type type);
  static Type typeFromName(const std::string& name);

  virtual ~Odometry();
  virtual Type type() const = 0;

  // Processes one frame and returns its pose in the odometry frame, or a null Transform when
  // lost (info->lost, info->lostReason say why). Never throws on bad sensor data: bad input
  // is a lost frame with its reason. `data` may be enriched (features, odometry pose).
  Transform process(SensorData& data, OdometryInfo* info = nullptr);
  // Same with an external motion guess: the motion since the previous frame given by another
  // source (wheel odometry), used instead of the constant-velocity prediction.
  Transform process(SensorData& data, const Transform& guess, OdometryInfo* info);

  // A raw IMU sample (angular velocity; IMU::localTransform its pose on the base), in stamp
  // order, before the frames it comes before. False when it is not used (no angular velocity,
  // not finite, not after the previous one).
  bool addImu(double stamp, const IMU& imu);
  // The base's rotation from t0 to t1 (expressed at t0) the gyroscope samples given measured
  // (e.g. over a lidar sweep, for deskewing); none when they do not cover [t0, t1]. Samples
  // before the last pose's frame are forgotten.
  std::optional<Eigen::Matrix3d> imuRotationBetween(double t0, double t1) const;

  // Restarts from `initialPose` (identity by default) with an empty map.
  void reset(const Transform& initialPose = Transform::Identity());
  const Transform& getPose() const { return pose_; }
  // Frames processed since reset, and consecutive lost frames.
  int framesProcessed() const { return framesProcessed_; }
  int lostCount() const { return lostCount_; }

 protected:
  explicit Odometry(const ParametersMap& parameters);
  // The approach's registration of `data` against its map / key frame. `guess` is the
  // predicted motion since the previous frame (null if none). Returns the motion since the
  // previous frame (not the pose), or null with info->lostReason set.
  virtual Transform computeTransform(SensorData& data, const Transform& guess, OdometryInfo* info) = 0;
  // Drops the approach's map / key frame (called by reset()).
  virtual void resetMap(const Transform& initialPose) = 0;
  // True until the approach has a map / key frame (the first frame initialises it).
  virtual bool needsInitialisation() const = 0;

  const ParametersMap& parameters() const { return parameters_; }

 private:
  // Motion expected over dt seconds (dt <= 0: stamps unknown, one frame's motion), null if
  // the model has no velocity yet.
  Transform predictMotion(double dt) const;
  // The guess with its rotation replaced by the one the IMU measured (translation zero when
  // there is no guess), planar with Reg/Force3DoF.
  Transform withImuRotation(const Transform& guess, const Eigen::Matrix3d& imuRotation) const;
  // Feeds the constant-velocity model with the motion found over dt seconds.
  void updateVelocity(const Transform& motion, double dt, double stamp);
  // The frame is lost: null pose, 9999 covariance, reset countdown.
  Transform reportLost(SensorData& data, OdometryInfo& info);

  ParametersMap parameters_;
  Transform pose_ = Transform::Identity();
  Transform velocityTransform_;  // last motion per second (constant-velocity model), null if none
  Transform lastMotion_;         // last motion per frame, for data without stamps
  Transform imuAtPose_;          // the base's IMU orientation at pose_ (null if none)
  double stampAtPose_ = 0.0;     // the stamp of the frame at pose_ (0: none)
  std::unique_ptr<odometry_detail::GyroIntegration> gyro_;  // addImu()'s samples
  // (stamp, velocity as twist vx vy vz wx wy wz) of recent frames, for Odom/GuessSmoothingDelay.
  std::deque<std::pair<double, Eigen::Matrix<double, 6, 1>>> velocityHistory_;
  double guessSmoothingDelay_ = 0.0;
  double previousStamp_ = 0.0;
  int framesProcessed_ = 0;
  int lostCount_ = 0;
  double distanceTravelled_ = 0.0;
  int resetCountdown_ = 0;  // Odom/ResetCountdown
  bool guessMotion_ = true; // Odom/GuessMotion
  bool force3DoF_ = false;  // Reg/Force3DoF
  bool holonomic_ = true;   // Odom/Holonomic
  bool imagesAlreadyRectified_ = true;  // Rtabmap/ImagesAlreadyRectified
  bool alignWithGround_ = false;        // Odom/AlignWithGround
};

}  // namespace rtabmap
