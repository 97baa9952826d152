#pragma once
// The feature map of frame-to-map visual odometry (JFR 2019, 3.1.1, F2M): 3D features of past
// key frames in the odometry frame, each with its descriptor, when it was last matched and how
// often, plus the key frames that observed them (pose, camera, 2D observations) for local
// bundle adjustment.
#include <opencv2/core/mat.hpp>

#include <deque>
#include <map>
#include <unordered_set>

#include "rtabmap_core/registration/BundleAdjustment.h"
#include "rtabmap_core/registration/RegistrationVis.h"

namespace rtabmap::odometry_detail {

class VisualLocalMap {
 public:
  struct Point {
    cv::Point3f position;  // odometry frame
    cv::Mat descriptor;    // one row
    int lastSeen = 0;      // frame counter of its last inlier match (or its creation)
    int observations = 1;  // times it was an inlier, creation included
  };
  struct Observation {
    cv::Point2f uv;
    float depth = 0.0f;  // m along the optical axis, 0 = unknown
  };
  struct KeyFrame {
    int id = 0;
    Transform pose;     // base frame in the odometry frame
    CameraModel model;  // local transform base -> optical
    double baseline = 0.0;
    int features = 0;   // features the frame had (for Odom/KeyFrameThr)
    std::map<int, Observation> observations;  // point id -> where the frame saw it
  };

  void clear();
  size_t size() const { return points_.size(); }
  bool empty() const { return points_.empty(); }
  const std::map<int, Point>& points() const { return points_; }
  const std::deque<KeyFrame>& keyFrames() const { return keyFrames_; }

  // The map as the reference side of a registration (points, descriptors, ids; no keypoints).
  const VisualFrame& asFrame() const;

  int addPoint(const cv::Point3f& position, const cv::Mat& descriptor, int frame);
  // An inlier match of point `id` in frame `frame`: refreshes its age and, for the next
  // matches, its descriptor (the latest view resembles the next one best).
  void observe(int id, int frame, const cv::Mat& descriptor);
  // Keeps at most `maxFrames` key frames (0 = all those still observing a map point).
  void addKeyFrame(KeyFrame keyFrame, int maxFrames);

  // Removes points until at most maxSize remain (0 = no limit): those outside `keep` first,
  // then those not seen for the longest, the least observed among equally old. Key frames left
  // observing no point are dropped.
  void trim(size_t maxSize, const std::unordered_set<int>& keep);

  // Local bundle adjustment over the last `maxFrames` key frames (0 = all), the oldest fixed:
  // refines their poses and the points they observe; drops observations it finds wrong.
  // Returns the summary (success false when there is nothing to adjust).
  BundleAdjustmentSummary adjust(int maxFrames, const BundleAdjustmentOptions& options);

 private:
  std::map<int, Point> points_;  // ids increase with time: iteration is oldest first
  std::deque<KeyFrame> keyFrames_;
  int nextId_ = 1;
  int nextKeyFrameId_ = 1;
  mutable VisualFrame frame_;
  mutable bool dirty_ = true;
};

}  // namespace rtabmap::odometry_detail
