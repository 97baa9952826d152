#include "rtabmap_conversions/ImuOrientationBuffer.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "rtabmap_conversions/ImuConversions.h"

namespace rtabmap_conversions {

ImuOrientationBuffer::ImuOrientationBuffer(double keepSeconds, double maxGapSeconds)
    : keep_(keepSeconds), maxGap_(maxGapSeconds) {}

bool ImuOrientationBuffer::add(const ImuOrientation& sample, std::string* why) {
  auto fail = [why](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  const Eigen::Vector4d q = sample.orientation.coeffs();
  if (!std::isfinite(sample.stamp) || !q.allFinite()) return fail("not a finite stamp and orientation");
  if (q.squaredNorm() < 1e-12) return fail("no orientation (null quaternion)");
  std::lock_guard<std::mutex> lock(mutex_);
  // Older than all the history kept: ROS time went back (a restarted bag), not a late sample.
  if (!samples_.empty() && sample.stamp < samples_.back().stamp - keep_) samples_.clear();
  if (!samples_.empty() && sample.stamp <= samples_.back().stamp) {
    return fail("stamp " + std::to_string(sample.stamp) + " is not after the previous sample's " +
                std::to_string(samples_.back().stamp));
  }
  ImuOrientation s = sample;
  s.orientation.normalize();
  samples_.push_back(std::move(s));
  while (samples_.front().stamp < samples_.back().stamp - keep_) samples_.pop_front();
  return true;
}

std::optional<ImuOrientation> ImuOrientationBuffer::at(double stamp) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (samples_.empty() || !std::isfinite(stamp)) return std::nullopt;
  const auto after = std::lower_bound(samples_.begin(), samples_.end(), stamp,
                                      [](const ImuOrientation& s, double t) { return s.stamp < t; });
  if (after == samples_.end()) {
    // Past the newest sample (the frame came first): held if recent enough.
    const ImuOrientation& newest = samples_.back();
    if (stamp - newest.stamp > maxGap_) return std::nullopt;
    ImuOrientation out = newest;
    out.stamp = stamp;
    return out;
  }
  if (after->stamp == stamp) return *after;
  if (after == samples_.begin()) return std::nullopt;  // older than what is kept
  const ImuOrientation& before = *std::prev(after);
  if (after->stamp - before.stamp > maxGap_ || before.frameId != after->frameId) return std::nullopt;
  const double ratio = (stamp - before.stamp) / (after->stamp - before.stamp);
  ImuOrientation out = before;
  out.stamp = stamp;
  out.orientation = before.orientation.slerp(ratio, after->orientation);
  return out;
}

ImuOrientationBuffer::Intake ImuOrientationBuffer::add(const sensor_msgs::Imu& msg, std::string* why,
                                                       rtabmap::IMU* converted) {
  const std::optional<rtabmap::IMU> imu = imuFromMsg(msg, rtabmap::Transform::Identity(), why);
  if (!imu) return Intake::kRefused;
  if (converted) *converted = *imu;
  if (!imu->hasOrientation()) {
    if (why) *why = "the message has no orientation (a raw IMU: put a filter such as imu_filter_madgwick before it)";
    return Intake::kNoOrientation;
  }
  return add({msg.header.stamp.toSec(), imu->orientation, msg.header.frame_id}, why) ? Intake::kKept : Intake::kRefused;
}

rtabmap::Transform ImuOrientationBuffer::mountOf(const std::string& frameId, const LocalPoseOf& localOf,
                                                 std::string* why) const {
  const auto now = std::chrono::steady_clock::now();
  {
    std::lock_guard<std::mutex> lock(mountMutex_);
    auto known = mounts_.find(frameId);
    if (known != mounts_.end()) return known->second;
    auto failed = mountFailures_.find(frameId);
    if (failed != mountFailures_.end() && now - failed->second < std::chrono::seconds(1)) {
      if (why) *why = "no pose on the robot for the imu frame \"" + frameId + "\" yet (tf asked again each second)";
      return rtabmap::Transform();
    }
  }
  const rtabmap::Transform local = localOf(frameId, why);
  std::lock_guard<std::mutex> lock(mountMutex_);
  if (local.isNull()) {
    mountFailures_[frameId] = now;
  } else {
    mountFailures_.erase(frameId);
    mounts_.emplace(frameId, local);
  }
  return local;
}

std::optional<rtabmap::IMU> ImuOrientationBuffer::imuAt(double stamp, const LocalPoseOf& localOf,
                                                        std::string* why) const {
  const std::optional<ImuOrientation> sample = at(stamp);
  if (!sample) {
    if (why) {
      std::ostringstream m;
      m << "no imu orientation within " << maxGap_ << " s of the frame";
      *why = m.str();
    }
    return std::nullopt;
  }
  // The IMU's pose on the robot: the orientation is the IMU frame's, not the base's.
  const rtabmap::Transform local = mountOf(sample->frameId, localOf, why);
  if (local.isNull()) return std::nullopt;
  rtabmap::IMU imu;
  imu.orientation = sample->orientation;
  imu.localTransform = local;
  return imu;
}

bool ImuOrientationBuffer::empty() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return samples_.empty();
}

void ImuOrientationBuffer::clear() {
  std::lock_guard<std::mutex> lock(mutex_);
  samples_.clear();
}

}  // namespace rtabmap_conversions
