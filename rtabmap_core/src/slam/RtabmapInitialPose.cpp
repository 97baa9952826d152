// Where the robot starts in the map: the user's initial pose (rviz's "2D Pose Estimate", the
// node's initial_pose parameter), the default start of localization (the last session's last
// pose, or the origin with RGBD/StartAtOrigin), and the map a new session continues.
#include "RtabmapImpl.h"
#include "rtabmap_core/common/Log.h"

namespace rtabmap {

bool Rtabmap::setInitialPose(const Transform& pose, std::string* why) {
  Impl& m = *impl_;
  const auto refuse = [why](const std::string& reason) {
    if (why) *why = reason;
    RTABMAP_WARN("initial pose refused: " << reason);
    return false;
  };
  if (!m.initialized) return refuse("no map: init() was not called");
  if (pose.isNull() || pose.isInvalid()) return refuse("the pose is null or not finite");
  if (!m.options.metric) return refuse("the map has no metric poses (" + std::string(Parameters::kRGBDEnabled()) + " false)");
  if (m.options.incremental && m.lastNodeId != 0 && !m.newMapPending) {
    // The nodes already there were placed by odometry and loop closures: moving the robot now
    // would tear the map apart.
    return refuse("mapping mode: map " + std::to_string(m.mapId) + " already has nodes (the last is " +
                  std::to_string(m.lastNodeId) +
                  "); an initial pose places a map before its first node only (trigger a new map, or use localization mode)");
  }
  const Transform start = m.options.force3DoF ? pose.to3DoF() : pose;
  // Localization: a guess, not a localisation; the next confirmed one (two agreeing links,
  // OdometryCache.h) is applied wherever it puts the robot, and until then the robot moves with
  // its odometry from `start`. The links cached so far were found around the old belief, which
  // the user says was wrong: they go.
  m.localized = false;
  m.odometryCache.clear();
  if (!m.lastOdom.isNull() && !m.newMapPending) {
    // The robot is at `start` now, where the last odometry pose received put it: map -> odom
    // (and the tf of the ROS node) moves at once.
    m.mapCorrection = start * m.lastOdom.inverse();
    m.currentPose = start;
  } else {
    // No odometry yet, or a new map starts at the next update (which resets map -> odom).
    m.initialPose = start;
  }
  if (why) why->clear();
  RTABMAP_INFO("initial pose " << start.prettyPrint() << " ("
                               << (m.options.incremental ? "where map " + std::to_string(m.mapId) + " starts"
                                                         : "localization starts from there")
                               << ")");
  return true;
}

void Rtabmap::Impl::applyStartPose(const Transform& odom) {
  if (!options.metric) return;
  if (!initialPose.isNull()) {
    mapCorrection = initialPose * odom.inverse();
    currentPose = initialPose;
    initialPose = Transform();
    return;
  }
  if (!options.incremental && currentPose.isNull() && !localized) {
    // First update of a localization session without a user pose: the robot is assumed where
    // the last session ended (or at the origin with RGBD/StartAtOrigin).
    const bool origin = options.startAtOrigin || initialLocalizationPose.isNull();
    mapCorrection = (origin ? Transform::Identity() : initialLocalizationPose) * odom.inverse();
  }
}

int Rtabmap::Impl::newestMapId() const {
  // Node ids grow across sessions: the largest is the newest.
  const std::map<int, Transform> all = graph.poses();
  return all.empty() ? -1 : graph.mapOf(all.rbegin()->first);
}

}  // namespace rtabmap
