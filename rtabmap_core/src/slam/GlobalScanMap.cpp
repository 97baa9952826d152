#include "GlobalScanMap.h"

#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "LinkRegistration.h"
#include "ScanMerge.h"
#include "rtabmap_core/memory/Memory.h"
#include "rtabmap_core/optimizer/Graph.h"
#include "rtabmap_core/registration/RegistrationInfo.h"
#include "rtabmap_core/registration/ScanFilter.h"

namespace rtabmap {
namespace {

// Cells of the index: a crop of a 10-30 m radius visits tens to hundreds of them, each holding
// a few hundred points of a 5 cm 2D map.
constexpr float kCellSize = 2.0f;

// Both cell coordinates in one key, through unsigned arithmetic (a negative value shifted left
// is undefined before C++20: UBSan's report in make test-asan).
uint64_t cellKey(int32_t cx, int32_t cy) {
  return (static_cast<uint64_t>(static_cast<uint32_t>(cx)) << 32) | static_cast<uint32_t>(cy);
}

LaserScan voxelFiltered(const LaserScan& scan, float voxelSize) {
  if (voxelSize <= 0.0f || scan.empty()) return scan;
  ScanFilterOptions f;
  f.voxelSize = voxelSize;
  std::string why;
  const LaserScan out = filterScan(scan, f, &why);
  return out.empty() ? scan : out;
}

LaserScan concatenated(const LaserScan& a, const LaserScan& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  cv::Mat data;
  cv::hconcat(a.data(), b.data(), data);
  return LaserScan(data, data.cols, 0.0, 0.0, a.format());
}

}  // namespace

GlobalScanMap::GlobalScanMap(float voxelSize) : voxelSize_(std::max(0.0f, voxelSize)), cellSize_(kCellSize) {}

void GlobalScanMap::add(const std::vector<std::pair<LaserScan, Transform>>& parts) {
  std::vector<std::pair<LaserScan, Transform>> kept;
  kept.reserve(parts.size());
  for (const auto& part : parts) {
    if (part.first.empty() || part.second.isNull()) continue;
    // The first scan ever added decides the map's format.
    const LaserScan& first = kept.empty() ? part.first : kept.front().first;
    const LaserScan::Format format = points_.empty() ? first.format() : points_.format();
    if (part.first.format() != format) {
      ++skipped_;
      continue;
    }
    kept.push_back(part);
  }
  if (kept.empty()) return;
  cells_.clear();  // indexed again by finish()
  points_ = concatenated(points_, voxelFiltered(mergeScans(kept), voxelSize_));
}

uint64_t GlobalScanMap::cellOf(float x, float y) const {
  return cellKey(static_cast<int32_t>(std::floor(x / cellSize_)), static_cast<int32_t>(std::floor(y / cellSize_)));
}

void GlobalScanMap::finish() {
  cells_.clear();
  if (points_.empty()) return;
  points_ = voxelFiltered(points_, voxelSize_);
  const int n = points_.size();
  std::vector<uint64_t> keys(n);
  for (int i = 0; i < n; ++i) {
    const float* p = points_.data().ptr<float>(0, i);
    keys[i] = cellOf(p[0], p[1]);
  }
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&keys](int a, int b) { return keys[a] < keys[b]; });
  cv::Mat sorted(1, n, points_.data().type());
  const size_t bytes = points_.data().elemSize();
  for (int i = 0; i < n; ++i) {
    std::copy_n(points_.data().ptr<uchar>(0, order[i]), bytes, sorted.ptr<uchar>(0, i));
  }
  points_ = LaserScan(sorted, n, 0.0, 0.0, points_.format());
  for (int i = 0; i < n;) {
    const uint64_t key = keys[order[i]];
    int j = i;
    while (j < n && keys[order[j]] == key) ++j;
    cells_.emplace(key, std::make_pair(i, j));
    i = j;
  }
}

LaserScan GlobalScanMap::around(const Transform& center, float radius) const {
  if (points_.empty() || cells_.empty() || !(radius > 0.0f)) return LaserScan();
  const float cx = center.x(), cy = center.y();
  const int32_t x0 = static_cast<int32_t>(std::floor((cx - radius) / cellSize_));
  const int32_t x1 = static_cast<int32_t>(std::floor((cx + radius) / cellSize_));
  const int32_t y0 = static_cast<int32_t>(std::floor((cy - radius) / cellSize_));
  const int32_t y1 = static_cast<int32_t>(std::floor((cy + radius) / cellSize_));
  const float r2 = radius * radius;
  const int channels = LaserScan::channels(points_.format());
  const bool is2d = points_.is2d(), normals = points_.hasNormals();
  const Transform toCenter = center.inverse();
  const Eigen::Matrix3f r = toCenter.rotationMatrix().cast<float>();
  const Eigen::Vector3f t = toCenter.translation().cast<float>();
  std::vector<float> out;
  for (int32_t x = x0; x <= x1; ++x) {
    for (int32_t y = y0; y <= y1; ++y) {
      const auto cell = cells_.find(cellKey(x, y));
      if (cell == cells_.end()) continue;
      for (int i = cell->second.first; i < cell->second.second; ++i) {
        const float* p = points_.data().ptr<float>(0, i);
        const float dx = p[0] - cx, dy = p[1] - cy;
        if (dx * dx + dy * dy > r2) continue;
        const size_t k = out.size();
        out.insert(out.end(), p, p + channels);
        const Eigen::Vector3f q = r * Eigen::Vector3f(p[0], p[1], is2d ? 0.0f : p[2]) + t;
        out[k] = q.x();
        out[k + 1] = q.y();
        if (!is2d) out[k + 2] = q.z();
        if (normals) {
          const int n0 = channels - 3;
          const Eigen::Vector3f n = r * Eigen::Vector3f(p[n0], p[n0 + 1], p[n0 + 2]);
          out[k + n0] = n.x();
          out[k + n0 + 1] = n.y();
          out[k + n0 + 2] = n.z();
        }
      }
    }
  }
  if (out.empty()) return LaserScan();
  const int count = static_cast<int>(out.size()) / channels;
  const cv::Mat data = cv::Mat(1, count, CV_32FC(channels), out.data()).clone();
  return LaserScan(data, count, 0.0, 0.0, points_.format());
}

ProximityResult localizeOnGlobalScanMap(memory::Memory& memory, int currentId, const Transform& estimate,
                                        const GlobalScanMap& map, const RtabmapOptions& o,
                                        const LinkRegistration& registration, bool covOffDiagIgnored) {
  ProximityResult result;
  Signature* current = memory.mutableSignature(currentId);
  if (!current || map.empty() || estimate.isNull()) return result;
  const std::string name = "global scan map " + std::to_string(currentId);
  double distance = 0.0;
  if (graph::findNearestNode(map.nodes(), estimate, &distance, o.force3DoF) == 0 || distance > o.localRadius) {
    result.rejections.push_back(name + ": no node of the map within " + Parameters::kRGBDLocalRadius() +
                                " of the assumed pose");
    return result;
  }
  // The new scan against the local map, as for local paths: the map within RGBD/LocalRadius of
  // the robot. Against everything the scan could reach (80 m for a SICK), ICP paired far points
  // with walls they may never have seen and the robot was pulled along corridors (ACES, second
  // half localised on a map of the first: relation error 0.17 m, 0.066 m with the local map).
  // The scan stays whole: its points beyond the local map count as unexplained, as against a
  // path's merged scans (cropped too, 4x more matches passed the ratio test and the error rose
  // to 0.11 m).
  const LaserScan& scan = scanOf(*current);
  if (scan.empty()) return result;
  const float window = o.proximityCorrelativeWindow;
  const LaserScan target = map.around(estimate, o.localRadius + std::max(window, registration.icpReach()));
  if (target.empty()) {
    result.rejections.push_back(name + ": the map has no point around the assumed pose");
    return result;
  }
  ++result.scanChecked;
  Transform guess = Transform::Identity();  // the new scan in the estimate's frame
  if (window > 0.0f && target.is2d() && scan.is2d()) {
    std::string why;
    guess = correlativeProximityGuess(target, scan, guess, o, window, &why);
    if (guess.isNull()) {
      result.rejections.push_back(name + ": " + why);
      return result;
    }
  }
  RegistrationInfo info;
  const Transform t = registration.icp(target, scan, guess, &info);
  if (t.isNull()) {
    result.rejections.push_back(name + ": " + info.rejectedMsg);
    return result;
  }
  // The map holds every surface the mapping saw: where the robot really is, nearly all of the
  // scan finds it; a look-alike place explains only part of it (an ICP that converged on
  // someone else's walls).
  if (info.icpInliersRatio < o.proximityGlobalScanMapMinRatio) {
    result.rejections.push_back(name + ": " + std::to_string(info.icpInliersRatio) +
                                " of the scan found in the map < " + Parameters::kRGBDProximityGlobalScanMapMinRatio());
    return result;
  }
  // As for merged scans of a path: a corridor only echoes the assumed pose back along it.
  if (info.icpStructuralComplexity < registration.minComplexity()) {
    result.rejections.push_back(name + ": structural complexity " + std::to_string(info.icpStructuralComplexity) +
                                " under Icp/PointToPlaneMinComplexity");
    return result;
  }
  const Transform corrected = estimate * t;
  const int nearest = graph::findNearestNode(map.nodes(), corrected, nullptr, o.force3DoF);
  const Link link(currentId, nearest, Link::kLocalSpaceClosure, corrected.inverse() * map.nodes().at(nearest),
                  informationOf(info.covariance * o.proximityMergedScanCovFactor, covOffDiagIgnored));
  result.links.push_back(link);
  ++result.addedByScans;
  return result;
}

}  // namespace rtabmap
