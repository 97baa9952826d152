#pragma once
// The rtabmap node's landmark_detection(s) topics: landmarks another node detected (an AprilTag
// or ArUco detector relayed to rtabmap_ros/LandmarkDetection), waiting for the next frame the
// node maps. Each is brought to the robot's base frame at that frame's stamp by the caller's
// `poseOf` (tf: the camera on the base at the detection's stamp, moved by the odometry since),
// its covariance rotated with it. Thread-safe: the detection callbacks and the data callback may
// run at once.
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/Landmark.h"

namespace rtabmap_slam_node {

struct PendingLandmark {
  double stamp = 0.0;
  std::string frameId;        // the frame of landmark.pose (the camera's)
  rtabmap::Landmark landmark;  // pose in frameId
  // The detector gave no covariance: the frame's caller gives one (the node's Marker/Variance*).
  bool defaultCovariance = false;
};

// The pose of `frameId` at `stamp` in the base frame at the frame's stamp; null (with why) when
// tf cannot say.
using LandmarkFramePose = std::function<rtabmap::Transform(const std::string& frameId, double stamp, std::string* why)>;

class LandmarkBuffer {
 public:
  // maxAgeSeconds: a detection this much older than the frame is dropped (the robot moved on;
  // odometry over a long gap is not worth a landmark).
  explicit LandmarkBuffer(double maxAgeSeconds = 1.0) : maxAge_(maxAgeSeconds) {}

  void add(const PendingLandmark& detection);
  // The landmarks for a frame at `frameStamp`: every detection up to 0.1 s after it (a detector
  // stamps with the image the frame may share) and not older than maxAge, in the base frame,
  // the newest per id; those taken, and those too old, leave the buffer (later ones stay for
  // the next frame). `problems` gets one line per detection dropped.
  // `defaultCovariance` (in the camera's frame) replaces the covariance of detections that had none.
  rtabmap::Landmarks take(double frameStamp, const LandmarkFramePose& poseOf,
                          const Eigen::Matrix<double, 6, 6>& defaultCovariance, std::vector<std::string>* problems);
  void clear();  // ROS time jumped back
  size_t size() const;

 private:
  double maxAge_;
  mutable std::mutex mutex_;
  std::vector<PendingLandmark> pending_;
};

}  // namespace rtabmap_slam_node
