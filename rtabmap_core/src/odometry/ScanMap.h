#pragma once
// Private: the local point-cloud map of scan-to-map odometry, in the odometry frame.
//
// Points are kept in the order they were added (oldest first), each tagged with its key frame,
// so capping the map drops the oldest surfaces first: the robot has moved away from them.
// A new key frame only brings what the map lacks: its points within OdomF2M/ScanSubtractRadius
// of a map point (with a normal within OdomF2M/ScanSubtractAngle, when both have normals) are
// skipped, so standing still does not pile up copies of the same wall.
#include <vector>

#include "../registration/IcpCloud.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap::scanodom {

struct ScanMapOptions {
  int maxSize = 2000;            // OdomF2M/ScanMaxSize (0 = no limit)
  float subtractRadius = 0.05f;  // OdomF2M/ScanSubtractRadius (m, 0 = add every point)
  float subtractAngle = 0.785f;  // OdomF2M/ScanSubtractAngle, here in radians (0 = any angle)
  float range = 0.0f;            // OdomF2M/ScanRange (m, 0 = cap by size instead)
  float indexDistance = 0.05f;   // Icp/MaxCorrespondenceDistance: the index's query range

  static ScanMapOptions fromParameters(const ParametersMap& parameters);
};

class ScanMap {
 public:
  explicit ScanMap(const ScanMapOptions& options) : options_(options) {}

  void clear();
  bool empty() const { return map_.empty(); }
  int size() const { return map_.size(); }
  bool is2d() const { return map_.is2d; }
  // Key frames that still have points in the map.
  int keyFrames() const;
  // The map, indexed for ICP.
  const icp::IcpCloud& cloud() const { return map_; }

  // Adds key frame `scan` (points in its base frame) seen at `pose` (odometry frame), then
  // caps the map around `pose`, updating the index (in place in 2D) and the normals' moment.
  // Returns the points added.
  int addKeyFrame(const icp::IcpCloud& scan, const Transform& pose);

 private:
  bool alreadyMapped(const icp::Point& p, const icp::ScanIndex& index) const;

  mutable std::vector<std::pair<int, float>> neighbours_;  // scratch of alreadyMapped
  // Drops the points beyond the size or range limit. True when the index must be rebuilt
  // (the range limit removes points anywhere; the size limit only the oldest, in place).
  bool cap(const Transform& pose);
  void addMoment(const icp::Cloud& points, double sign);

  ScanMapOptions options_;
  icp::IcpCloud map_;
  std::vector<int> keyFrameOf_;  // key frame number of each map point, parallel to the cloud
  int nextKeyFrame_ = 0;
};

}  // namespace rtabmap::scanodom
