// Stages on clouds that need PCL: voxel filter, normals-based ground segmentation, obstacle
// clustering, radius noise filter (see LocalGridStages.h), and the ground plane (GroundPlane.h).
// PCL headers are slow to compile: they live in this file only.
#include <pcl/features/normal_3d.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>
#include <pcl/segmentation/sac_segmentation.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "rtabmap_core/maps/GroundPlane.h"
#include "rtabmap_core/maps/LocalGridStages.h"

namespace rtabmap {

namespace {

pcl::PointCloud<pcl::PointXYZ>::Ptr toPcl(const Cloud& cloud) {
  auto out = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  out->resize(cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) {
    const cv::Point3f& p = cloud.points[i];
    (*out)[i] = pcl::PointXYZ(p.x, p.y, p.z);
  }
  return out;
}

Cloud subset(const Cloud& cloud, const std::vector<int>& indices) {
  Cloud out;
  const bool colours = cloud.hasColors();
  out.reserve(indices.size(), colours);
  for (int i : indices) {
    if (colours) out.push_back(cloud.points[i], cloud.colors[i]);
    else out.push_back(cloud.points[i]);
  }
  return out;
}

// Euclidean clusters of the points at `indices` (all points when empty and all = true).
std::vector<pcl::PointIndices> euclideanClusters(const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud,
                                                 const std::vector<int>& indices, float radius) {
  std::vector<pcl::PointIndices> clusters;
  if (indices.empty()) return clusters;
  auto tree = pcl::make_shared<pcl::search::KdTree<pcl::PointXYZ>>();
  auto idx = pcl::make_shared<pcl::Indices>(indices.begin(), indices.end());
  tree->setInputCloud(cloud, idx);
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
  ec.setClusterTolerance(radius);
  ec.setMinClusterSize(1);
  ec.setMaxClusterSize(std::numeric_limits<int>::max());
  ec.setSearchMethod(tree);
  ec.setInputCloud(cloud);
  ec.setIndices(idx);
  ec.extract(clusters);
  return clusters;
}

// PCL's voxel grid indexes voxels with 32-bit integers over the cloud's bounding box; a large
// map at a fine voxel size overflows it. Splitting the cloud into slabs along x whose borders lie
// on voxel boundaries gives the same voxels.
void voxelFilterSlab(const pcl::PointCloud<pcl::PointXYZRGB>::Ptr& in, float leaf,
                     pcl::PointCloud<pcl::PointXYZRGB>& out) {
  pcl::VoxelGrid<pcl::PointXYZRGB> grid;
  grid.setLeafSize(leaf, leaf, leaf);
  grid.setInputCloud(in);
  grid.setDownsampleAllData(true);
  pcl::PointCloud<pcl::PointXYZRGB> filtered;
  grid.filter(filtered);
  out += filtered;
}

}  // namespace

Cloud voxelFilter(const Cloud& cloud, float voxelSize) {
  if (cloud.empty() || !(voxelSize > 0.0f)) return cloud;
  const bool colours = cloud.hasColors();
  auto in = pcl::make_shared<pcl::PointCloud<pcl::PointXYZRGB>>();
  in->resize(cloud.size());
  float minX = std::numeric_limits<float>::max(), maxX = -minX;
  float minY = minX, maxY = -minX, minZ = minX, maxZ = -minX;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const cv::Point3f& p = cloud.points[i];
    pcl::PointXYZRGB& q = (*in)[i];
    q.x = p.x; q.y = p.y; q.z = p.z;
    if (colours) { q.r = cloud.colors[i][0]; q.g = cloud.colors[i][1]; q.b = cloud.colors[i][2]; }
    minX = std::min(minX, p.x); maxX = std::max(maxX, p.x);
    minY = std::min(minY, p.y); maxY = std::max(maxY, p.y);
    minZ = std::min(minZ, p.z); maxZ = std::max(maxZ, p.z);
  }
  const double ny = std::floor(maxY / voxelSize) - std::floor(minY / voxelSize) + 1;
  const double nz = std::floor(maxZ / voxelSize) - std::floor(minZ / voxelSize) + 1;
  const double nx = std::floor(maxX / voxelSize) - std::floor(minX / voxelSize) + 1;
  const double limit = static_cast<double>(std::numeric_limits<int32_t>::max()) / 2.0;
  pcl::PointCloud<pcl::PointXYZRGB> out;
  if (nx * ny * nz < limit) {
    voxelFilterSlab(in, voxelSize, out);
  } else {
    const int slabVoxels = std::max(1, static_cast<int>(limit / (ny * nz)));
    const double slab = slabVoxels * static_cast<double>(voxelSize);
    const double x0 = std::floor(minX / voxelSize) * voxelSize;
    const int slabs = static_cast<int>(std::ceil((maxX - x0 + voxelSize) / slab));
    std::vector<pcl::PointCloud<pcl::PointXYZRGB>::Ptr> parts(slabs);
    for (auto& part : parts) part = pcl::make_shared<pcl::PointCloud<pcl::PointXYZRGB>>();
    for (const auto& p : *in) {
      const int s = std::min(slabs - 1, std::max(0, static_cast<int>((p.x - x0) / slab)));
      parts[s]->push_back(p);
    }
    for (const auto& part : parts) {
      if (!part->empty()) voxelFilterSlab(part, voxelSize, out);
    }
  }
  Cloud result;
  result.reserve(out.size(), colours);
  for (const auto& q : out) {
    if (colours) result.push_back(cv::Point3f(q.x, q.y, q.z), cv::Vec3b(q.r, q.g, q.b));
    else result.push_back(cv::Point3f(q.x, q.y, q.z));
  }
  return result;
}

GroundObstacles segmentGroundByNormals(const Cloud& cloud, const Eigen::Vector3f& viewPoint,
                                       const LocalGridOptions& o) {
  GroundObstacles out;
  if (cloud.empty()) return out;
  const auto pc = toPcl(cloud);
  const int n = static_cast<int>(cloud.size());

  // Normals from the K nearest neighbours, oriented towards the sensor.
  pcl::PointCloud<pcl::Normal> normals;
  if (n >= 3) {
    pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
    ne.setInputCloud(pc);
    ne.setSearchMethod(pcl::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
    ne.setKSearch(std::max(3, std::min(o.normalK, n)));  // a plane needs 3 points
    ne.setViewPoint(viewPoint.x(), viewPoint.y(), viewPoint.z());
    ne.compute(normals);
  }
  const float cosMax = std::cos(o.maxGroundAngle * static_cast<float>(M_PI) / 180.0f);
  std::vector<int> flat, groundIdx, obstacleIdx;
  for (int i = 0; i < n; ++i) {
    const bool isFlat = n >= 3 && std::isfinite(normals[i].normal_z) &&
                        std::abs(normals[i].normal_z) >= cosMax;
    (isFlat ? flat : obstacleIdx).push_back(i);
  }

  if (o.maxGroundHeight != 0.0f) {
    // The floor is known to lie below MaxGroundHeight (base frame on the floor).
    for (int i : flat) {
      if (cloud.points[i].z <= o.maxGroundHeight || !o.flatObstacleDetected) groundIdx.push_back(i);
      else obstacleIdx.push_back(i);
    }
  } else {
    const std::vector<pcl::PointIndices> clusters = euclideanClusters(pc, flat, o.clusterRadius);
    out.flatClusters = static_cast<int>(clusters.size());
    size_t biggest = 0;
    for (const auto& c : clusters) biggest = std::max(biggest, c.indices.size());
    std::vector<float> meanZ(clusters.size(), 0.0f);
    int floor = -1;
    for (size_t k = 0; k < clusters.size(); ++k) {
      double sum = 0.0;
      for (int i : clusters[k].indices) sum += cloud.points[i].z;
      meanZ[k] = static_cast<float>(sum / clusters[k].indices.size());
      // The floor: the lowest of the large flat surfaces (a close table top may be bigger in the
      // image, but it is above the floor).
      if (clusters[k].indices.size() * 10 >= biggest && (floor < 0 || meanZ[k] < meanZ[floor])) {
        floor = static_cast<int>(k);
      }
    }
    if (floor >= 0) out.floorHeight = meanZ[floor];
    for (size_t k = 0; k < clusters.size(); ++k) {
      const bool atFloor = std::abs(meanZ[k] - meanZ[floor]) <= o.clusterRadius;
      const bool ground = atFloor || !o.flatObstacleDetected;
      if (!atFloor && o.flatObstacleDetected) ++out.flatObstacleClusters;
      auto& target = ground ? groundIdx : obstacleIdx;
      target.insert(target.end(), clusters[k].indices.begin(), clusters[k].indices.end());
    }
  }
  if (o.minGroundHeight != 0.0f) {
    groundIdx.erase(std::remove_if(groundIdx.begin(), groundIdx.end(),
                                   [&](int i) { return cloud.points[i].z < o.minGroundHeight; }),
                    groundIdx.end());
  }
  std::sort(groundIdx.begin(), groundIdx.end());
  std::sort(obstacleIdx.begin(), obstacleIdx.end());
  out.ground = subset(cloud, groundIdx);
  out.obstacles = subset(cloud, obstacleIdx);
  return out;
}

Cloud clusterObstacles(const Cloud& obstacles, float radius, int minClusterSize, ClusterStats* statsOut) {
  ClusterStats stats;
  if (obstacles.empty() || minClusterSize <= 1) {
    if (statsOut) *statsOut = stats;
    return obstacles;
  }
  const auto pc = toPcl(obstacles);
  std::vector<int> all(obstacles.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  std::vector<int> kept;
  for (const auto& c : euclideanClusters(pc, all, radius)) {
    if (static_cast<int>(c.indices.size()) >= minClusterSize) {
      ++stats.kept;
      kept.insert(kept.end(), c.indices.begin(), c.indices.end());
    } else {
      ++stats.dropped;
      stats.droppedPoints += static_cast<int>(c.indices.size());
    }
  }
  std::sort(kept.begin(), kept.end());
  if (statsOut) *statsOut = stats;
  return subset(obstacles, kept);
}

Cloud filterNoise(const Cloud& cloud, float radius, int minNeighbors, int* removedOut) {
  if (cloud.empty() || !(radius > 0.0f)) {
    if (removedOut) *removedOut = 0;
    return cloud;
  }
  const auto pc = toPcl(cloud);
  pcl::search::KdTree<pcl::PointXYZ> tree;
  tree.setInputCloud(pc);
  std::vector<int> kept;
  pcl::Indices found;
  std::vector<float> distances;
  for (int i = 0; i < static_cast<int>(cloud.size()); ++i) {
    // The point finds itself: it needs minNeighbors others.
    const int count = tree.radiusSearch((*pc)[i], radius, found, distances, minNeighbors + 1);
    if (count > minNeighbors) kept.push_back(i);
  }
  if (removedOut) *removedOut = static_cast<int>(cloud.size() - kept.size());
  return subset(cloud, kept);
}

std::optional<GroundPlane> findGroundPlane(const Cloud& cloud, const GroundPlaneOptions& options) {
  const int needed = std::max(options.minInliers, static_cast<int>(options.minInlierRatio * cloud.size()));
  if (static_cast<int>(cloud.size()) < needed || cloud.size() < 3) return std::nullopt;
  // A plane perpendicular to the base's z axis, within maxTilt: walls never qualify.
  pcl::SACSegmentation<pcl::PointXYZ> ransac;  // not random: a fixed seed
  ransac.setModelType(pcl::SACMODEL_PERPENDICULAR_PLANE);
  ransac.setMethodType(pcl::SAC_RANSAC);
  ransac.setAxis(Eigen::Vector3f::UnitZ());
  ransac.setEpsAngle(options.maxTilt);
  ransac.setDistanceThreshold(options.distance);
  ransac.setMaxIterations(500);
  ransac.setInputCloud(toPcl(cloud));
  pcl::PointIndices inliers;
  pcl::ModelCoefficients plane;
  ransac.segment(inliers, plane);
  if (static_cast<int>(inliers.indices.size()) < needed || plane.values.size() != 4) return std::nullopt;
  Eigen::Vector3d n(plane.values[0], plane.values[1], plane.values[2]);
  double d = plane.values[3];
  const double norm = n.norm();
  if (!(norm > 0.0)) return std::nullopt;
  n /= norm;
  d /= norm;
  // n . p + d = 0 on the plane; the origin's side is where n . p + d has the sign of d.
  if (d < 0.0) {
    n = -n;
    d = -d;
  }
  // Below the origin: the normal pointing to the origin must point up.
  if (n.z() <= 0.0) return std::nullopt;
  GroundPlane out;
  out.normal = n;
  out.height = d;
  out.inliers = static_cast<int>(inliers.indices.size());
  return out;
}

}  // namespace rtabmap
