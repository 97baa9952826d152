#include "ScanMap.h"

#include <pcl/common/transforms.h>

#include <cmath>

namespace rtabmap::scanodom {

ScanMapOptions ScanMapOptions::fromParameters(const ParametersMap& p) {
  ScanMapOptions o;
  o.maxSize = Parameters::getInt(p, Parameters::kOdomF2MScanMaxSize());
  o.subtractRadius = Parameters::getFloat(p, Parameters::kOdomF2MScanSubtractRadius());
  o.subtractAngle = Parameters::getFloat(p, Parameters::kOdomF2MScanSubtractAngle()) * static_cast<float>(M_PI / 180.0);
  o.range = Parameters::getFloat(p, Parameters::kOdomF2MScanRange());
  o.indexDistance = Parameters::getFloat(p, Parameters::kIcpMaxCorrespondenceDistance());
  return o;
}

void ScanMap::clear() {
  map_.cloud->clear();
  map_.index.clear();
  map_.hasNormals = false;
  map_.normalMoment.setZero();
  map_.normalCount = 0;
  map_.expectedPoints = 0;
  keyFrameOf_.clear();
  nextKeyFrame_ = 0;
}

int ScanMap::keyFrames() const {
  // Ids only grow along the cloud (points are appended, removals keep the order).
  int count = 0;
  for (size_t i = 0; i < keyFrameOf_.size(); ++i) {
    if (i == 0 || keyFrameOf_[i] != keyFrameOf_[i - 1]) ++count;
  }
  return count;
}

bool ScanMap::alreadyMapped(const icp::Point& p, const icp::ScanIndex& index) const {
  index.within(p.getVector3fMap(), options_.subtractRadius, &neighbours_);
  if (neighbours_.empty()) return false;
  if (options_.subtractAngle <= 0.0f || !map_.hasNormals) return true;
  // Same place but another surface (the far side of a thin wall, a corner): keep it.
  const float cosMax = std::cos(options_.subtractAngle);
  for (const auto& [i, d2] : neighbours_) {
    if ((*map_.cloud)[i].getNormalVector3fMap().dot(p.getNormalVector3fMap()) >= cosMax) return true;
  }
  return false;
}

int ScanMap::addKeyFrame(const icp::IcpCloud& scan, const Transform& pose) {
  icp::Cloud moved;
  pcl::transformPointCloudWithNormals(*scan.cloud, moved, pose.toEigen().matrix().cast<float>());
  if (scan.is2d) {
    for (auto& p : moved) p.z = p.normal_z = 0.0f;
  }
  if (map_.empty()) {
    clear();
    map_.is2d = scan.is2d;
    map_.hasNormals = scan.hasNormals;
    map_.index.build(icp::Cloud(), options_.indexDistance, map_.is2d);
  }
  // The map's own index answers radius queries up to the ICP's correspondence distance; a
  // larger subtraction radius needs an index of its own.
  icp::ScanIndex wider;
  const icp::ScanIndex* index = &map_.index;
  if (options_.subtractRadius > map_.index.maxDistance() && !map_.empty()) {
    wider.build(*map_.cloud, options_.subtractRadius, map_.is2d);
    index = &wider;
  }
  const bool subtract = options_.subtractRadius > 0.0f && !map_.empty();
  icp::Cloud added;
  added.reserve(moved.size());
  for (const auto& p : moved) {
    if (!subtract || !alreadyMapped(p, *index)) added.push_back(p);
  }

  const int keyFrame = nextKeyFrame_++;
  map_.cloud->insert(map_.cloud->end(), added.begin(), added.end());
  keyFrameOf_.resize(map_.cloud->size(), keyFrame);
  if (map_.hasNormals) addMoment(added, +1.0);
  if (map_.is2d) map_.index.append(added);
  const bool rebuilt = cap(pose);
  // The 3D tree cannot grow or shrink: one rebuild for both changes.
  if (!map_.is2d || rebuilt) map_.index.build(*map_.cloud, options_.indexDistance, map_.is2d);
  map_.expectedPoints = map_.size();
  return static_cast<int>(added.size());
}

void ScanMap::addMoment(const icp::Cloud& points, double sign) {
  int count = 0;
  map_.normalMoment += sign * icp::normalMomentSum(points, map_.is2d, &count);
  map_.normalCount += static_cast<int>(sign) * count;
}

bool ScanMap::cap(const Transform& pose) {
  icp::Cloud& cloud = *map_.cloud;
  if (options_.range > 0.0f) {
    // Points anywhere in the map may leave the range: filter, then rebuild the index.
    const Eigen::Vector3f center = pose.translation().cast<float>();
    const float range2 = options_.range * options_.range;
    size_t kept = 0;
    for (size_t i = 0; i < cloud.size(); ++i) {
      Eigen::Vector3f d = cloud[i].getVector3fMap() - center;
      if (map_.is2d) d.z() = 0.0f;
      if (d.squaredNorm() <= range2) {
        cloud[kept] = cloud[i];
        keyFrameOf_[kept] = keyFrameOf_[i];
        ++kept;
      }
    }
    if (kept == cloud.size()) return false;
    cloud.resize(kept);
    keyFrameOf_.resize(kept);
    if (map_.hasNormals) map_.normalMoment = icp::normalMomentSum(cloud, map_.is2d, &map_.normalCount);
    return true;
  }
  if (options_.maxSize > 0 && static_cast<int>(cloud.size()) > options_.maxSize) {
    // The oldest points are first.
    const int drop = static_cast<int>(cloud.size()) - options_.maxSize;
    if (map_.hasNormals) {
      icp::Cloud dropped;
      dropped.insert(dropped.end(), cloud.begin(), cloud.begin() + drop);
      addMoment(dropped, -1.0);
    }
    cloud.erase(cloud.begin(), cloud.begin() + drop);
    keyFrameOf_.erase(keyFrameOf_.begin(), keyFrameOf_.begin() + drop);
    if (map_.is2d) map_.index.removeOldest(drop);
  }
  return false;
}

}  // namespace rtabmap::scanodom
