#include "rtabmap_slam_node/LandmarkBuffer.h"

#include <map>
#include <sstream>

namespace rtabmap_slam_node {

namespace {
constexpr double kAfterFrame = 0.1;  // s: detections stamped with the frame's image, or just after

// The covariance of a pose seen from a frame rotated by R: both 3x3 blocks turn with it.
Eigen::Matrix<double, 6, 6> rotated(const Eigen::Matrix<double, 6, 6>& c, const Eigen::Matrix3d& R) {
  Eigen::Matrix<double, 6, 6> J = Eigen::Matrix<double, 6, 6>::Zero();
  J.topLeftCorner<3, 3>() = R;
  J.bottomRightCorner<3, 3>() = R;
  return J * c * J.transpose();
}
}  // namespace

void LandmarkBuffer::add(const PendingLandmark& detection) {
  std::lock_guard<std::mutex> lock(mutex_);
  pending_.push_back(detection);
}

rtabmap::Landmarks LandmarkBuffer::take(double frameStamp, const LandmarkFramePose& poseOf,
                                        const Eigen::Matrix<double, 6, 6>& defaultCovariance,
                                        std::vector<std::string>* problems) {
  std::vector<PendingLandmark> now;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<PendingLandmark> later;
    for (PendingLandmark& p : pending_) {
      if (p.stamp > frameStamp + kAfterFrame) {
        later.push_back(std::move(p));
      } else if (p.stamp < frameStamp - maxAge_) {
        if (problems) {
          std::ostringstream s;
          s << "landmark " << p.landmark.id << " detected at " << p.stamp << " is " << frameStamp - p.stamp
            << " s older than the frame (more than " << maxAge_ << " s): dropped";
          problems->push_back(s.str());
        }
      } else {
        now.push_back(std::move(p));
      }
    }
    pending_.swap(later);
  }
  rtabmap::Landmarks out;
  std::map<int, double> stampOf;
  for (const PendingLandmark& p : now) {
    auto seen = stampOf.find(p.landmark.id);
    if (seen != stampOf.end() && seen->second > p.stamp) continue;  // a newer sighting of it is kept
    std::string why;
    const rtabmap::Transform local = poseOf(p.frameId, p.stamp, &why);
    if (local.isNull()) {
      if (problems) problems->push_back("landmark " + std::to_string(p.landmark.id) + " in " + p.frameId + ": " + why);
      continue;
    }
    rtabmap::Landmark l = p.landmark;
    l.pose = local * p.landmark.pose;
    l.covariance = rotated(p.defaultCovariance ? defaultCovariance : p.landmark.covariance, local.rotationMatrix());
    out[l.id] = l;
    stampOf[l.id] = p.stamp;
  }
  return out;
}

void LandmarkBuffer::clear() {
  std::lock_guard<std::mutex> lock(mutex_);
  pending_.clear();
}

size_t LandmarkBuffer::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return pending_.size();
}

}  // namespace rtabmap_slam_node
