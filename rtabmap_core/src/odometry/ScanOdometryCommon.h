#pragma once
// Private: what scan-to-map and scan-to-scan odometry share: taking the scan out of a frame,
// the ICP with its coarse retry, key-frame thresholds, and the motion of frames that were lost.
#include <string>

#include "../registration/IcpCloud.h"
#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/params/Parameters.h"
#include "rtabmap_core/registration/IcpRegistration.h"

namespace rtabmap::scanodom {

// Icp/* options for odometry, validated (ParameterError naming the key otherwise).
IcpOptions icpOptions(const ParametersMap& parameters);

// The frame's scan (uncompressed if the frame only carries the compressed one), prepared for
// ICP. False with a reason a user understands ("the frame has no laser scan", "scan 'new'
// has 1 point ...") when it cannot be used.
bool prepareFrameScan(SensorData& data, const IcpOptions& options, icp::IcpCloud* scan, std::string* why);

// The ICP of odometry: `scan` (its base frame) against `target` from `poseGuess` (pose of the
// scan in the target's frame). `unguided`: this frame has no motion prediction at all (none yet,
// the one given failed, or the last frames were lost), so poseGuess is only the last pose and
// the scan may be off by a whole frame's motion: at 10 m, 5 degrees of turn move a wall half a
// metre, and no pair within Icp/MaxCorrespondenceDistance is left to pull it back. Then, when
// the regular ICP fails, once more from the same pose with correspondences kCoarseFactor times
// farther (a coarse alignment, still bounded by Icp/MaxTranslation and Icp/MaxRotation), and
// the regular ICP from there, which alone decides acceptance. Not with a prediction: a wheel
// guess that ICP cannot confirm is better trusted (the frame is lost and its motion kept) than
// replaced by a coarse alignment that may have slid along a corridor.
constexpr float kCoarseFactor = 5.0f;
Transform registerScan(const icp::IcpCloud& target, const icp::IcpCloud& scan, const Transform& poseGuess,
                       bool unguided, const IcpOptions& options, RegistrationInfo* info);

// Odom/ScanKeyFrameThr: a new key frame when the correspondence ratio falls under it; 0 makes
// every frame a key frame (as the parameter's description says).
inline bool belowKeyFrameThreshold(double ratio, double threshold) {
  return threshold <= 0.0 || ratio < threshold;
}

// The motion guesses of frames that were lost (wheel odometry keeps coming while the lidar
// fails): the next registration must start from the last good pose moved by all of them, not
// only by the guess of the frame at hand. The base class runs computeTransform at most twice
// per frame (with and without the guess) and counts frames after each one, so a change of
// framesProcessed() marks a new frame.
class LostMotion {
 public:
  // Call at the start of every computeTransform; returns the motion since the last good pose
  // to put before this frame's guess.
  const Transform& beginAttempt(int frame, const Transform& guess) {
    if (frame != frame_) {
      if (frame_ >= 0 && !succeeded_ && !frameGuess_.isNull()) pending_ = pending_ * frameGuess_;
      frame_ = frame;
      succeeded_ = false;
      frameGuess_ = guess;  // the first attempt carries the frame's guess
    }
    return pending_;
  }
  void succeeded() {
    succeeded_ = true;
    pending_ = Transform::Identity();
  }
  void reset() {
    frame_ = -1;
    succeeded_ = false;
    frameGuess_ = Transform();
    pending_ = Transform::Identity();
  }

 private:
  int frame_ = -1;
  bool succeeded_ = false;
  Transform frameGuess_;
  Transform pending_ = Transform::Identity();
};

}  // namespace rtabmap::scanodom
