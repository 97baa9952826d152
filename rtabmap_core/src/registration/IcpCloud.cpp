// Preparing scans for ICP: LaserScan -> PCL cloud, filters, normals, structural complexity.
#include "IcpCloud.h"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace rtabmap::icp {

namespace {

std::string pointsText(int n) { return std::to_string(n) + (n == 1 ? " point" : " points"); }

bool finiteNormal(const Point& p) {
  return std::isfinite(p.normal_x) && std::isfinite(p.normal_y) && std::isfinite(p.normal_z) &&
         (p.normal_x != 0.0f || p.normal_y != 0.0f || p.normal_z != 0.0f);
}

// Flips n to face the viewpoint (a surface is seen from the sensor's side).
void orientTowards(Point& p, const Eigen::Vector3f& viewpoint) {
  const Eigen::Vector3f toViewpoint = viewpoint - p.getVector3fMap();
  if (p.getNormalVector3fMap().dot(toViewpoint) < 0.0f) {
    p.normal_x = -p.normal_x;
    p.normal_y = -p.normal_y;
    p.normal_z = -p.normal_z;
  }
}

// Packs a voxel's integer coordinates into one key: 21 bits each, i.e. +-1M voxels per axis
// (52 km at 5 cm), far beyond any local map.
std::uint64_t voxelKey(const Eigen::Vector3f& p, float inverseSize) {
  const auto axis = [&](float v) {
    const std::int64_t i = static_cast<std::int64_t>(std::floor(v * inverseSize));
    return static_cast<std::uint64_t>(i + (1 << 20)) & 0x1FFFFFu;
  };
  return (axis(p.x()) << 42) | (axis(p.y()) << 21) | axis(p.z());
}

}  // namespace

void voxelFilter(Cloud& cloud, float voxelSize) {
  if (voxelSize <= 0.0f || cloud.size() < 2) return;
  const float inverse = 1.0f / voxelSize;
  struct Accumulator {
    Eigen::Vector3f point = Eigen::Vector3f::Zero();
    Eigen::Vector3f normal = Eigen::Vector3f::Zero();
    int count = 0;
  };
  std::unordered_map<std::uint64_t, int> slots;
  slots.reserve(cloud.size());
  std::vector<Accumulator> voxels;
  voxels.reserve(cloud.size());
  for (const Point& p : cloud) {
    const auto inserted = slots.emplace(voxelKey(p.getVector3fMap(), inverse), static_cast<int>(voxels.size()));
    if (inserted.second) voxels.emplace_back();
    Accumulator& a = voxels[inserted.first->second];
    a.point += p.getVector3fMap();
    // Normals of one surface are summed as they come; opposite normals in one voxel (both
    // sides of a thin wall) cancel, and removeInvalidNormals drops that point later.
    a.normal += p.getNormalVector3fMap();
    ++a.count;
  }
  if (voxels.size() == cloud.size()) return;
  Cloud filtered;
  filtered.resize(voxels.size());
  for (size_t i = 0; i < voxels.size(); ++i) {
    Point& q = filtered[i];
    q.getVector3fMap() = voxels[i].point / static_cast<float>(voxels[i].count);
    const float norm = voxels[i].normal.norm();
    if (norm > 1e-3f * voxels[i].count) {
      q.getNormalVector3fMap() = voxels[i].normal / norm;
    } else {
      q.normal_x = q.normal_y = q.normal_z = 0.0f;
    }
    q.curvature = 0.0f;
  }
  cloud.swap(filtered);
}

void computeNormals2D(Cloud& cloud, int k, float radius, const Eigen::Vector3f& viewpoint) {
  const int n = static_cast<int>(cloud.size());
  if (n == 0) return;
  const int window = std::max(k, 2);
  const float radius2 = radius * radius;
  std::vector<std::pair<float, int>> candidates;
  std::vector<Eigen::Vector2d> normals(static_cast<size_t>(n), Eigen::Vector2d::Zero());
  std::vector<float> curvature(static_cast<size_t>(n), 0.0f);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2f p = cloud[i].getVector3fMap().head<2>();
    candidates.clear();
    if (radius > 0.0f) {
      // Walk both ways along the scan until a point falls outside the radius.
      candidates.emplace_back(0.0f, i);
      for (int j = i - 1; j >= 0; --j) {
        const float d2 = (cloud[j].getVector3fMap().head<2>() - p).squaredNorm();
        if (d2 > radius2) break;
        candidates.emplace_back(d2, j);
      }
      for (int j = i + 1; j < n; ++j) {
        const float d2 = (cloud[j].getVector3fMap().head<2>() - p).squaredNorm();
        if (d2 > radius2) break;
        candidates.emplace_back(d2, j);
      }
    } else {
      for (int j = std::max(0, i - window); j <= std::min(n - 1, i + window); ++j) {
        candidates.emplace_back((cloud[j].getVector3fMap().head<2>() - p).squaredNorm(), j);
      }
      if (static_cast<int>(candidates.size()) > window) {
        std::nth_element(candidates.begin(), candidates.begin() + window, candidates.end());
        candidates.resize(static_cast<size_t>(window));
      }
    }
    if (candidates.size() < 2) continue;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& c : candidates) mean += cloud[c.second].getVector3fMap().head<2>().cast<double>();
    mean /= static_cast<double>(candidates.size());
    double sxx = 0.0, sxy = 0.0, syy = 0.0;
    for (const auto& c : candidates) {
      const Eigen::Vector2d d = cloud[c.second].getVector3fMap().head<2>().cast<double>() - mean;
      sxx += d.x() * d.x();
      sxy += d.x() * d.y();
      syy += d.y() * d.y();
    }
    // Neighbours all at one spot define no line.
    if (sxx + syy < 1e-12) continue;
    // Direction of the fitted line: the major axis of the 2x2 covariance.
    const double lineAngle = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
    normals[static_cast<size_t>(i)] = Eigen::Vector2d(-std::sin(lineAngle), std::cos(lineAngle));
    // Ratio of the minor to the total spread: 0 on a straight wall, 0.5 on a blob.
    const double minor = 0.5 * (sxx + syy) - std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
    curvature[static_cast<size_t>(i)] = static_cast<float>(std::max(0.0, minor) / (sxx + syy));
  }
  for (int i = 0; i < n; ++i) {
    Point& p = cloud[i];
    p.normal_x = static_cast<float>(normals[static_cast<size_t>(i)].x());
    p.normal_y = static_cast<float>(normals[static_cast<size_t>(i)].y());
    p.normal_z = 0.0f;
    p.curvature = curvature[static_cast<size_t>(i)];
    orientTowards(p, viewpoint);
  }
}

NeighbourhoodShape neighbourhoodShape(const Eigen::Vector3d& eigenvalues) {
  // Standard deviations along the principal axes, largest first (Demantke et al. 2011).
  const double s1 = std::sqrt(std::max(0.0, eigenvalues(2)));
  const double s2 = std::sqrt(std::max(0.0, eigenvalues(1)));
  const double s3 = std::sqrt(std::max(0.0, eigenvalues(0)));
  NeighbourhoodShape shape;
  if (!(s1 > 0.0)) return shape;
  shape.linearity = (s1 - s2) / s1;
  shape.planarity = (s2 - s3) / s1;
  shape.scattering = s3 / s1;
  return shape;
}

void computeNormals3D(Cloud& cloud, int k, float radius, const Eigen::Vector3f& viewpoint,
                      float groundNormalsUp) {
  if (cloud.empty()) return;
  Cloud::Ptr input(new Cloud(cloud));
  Tree tree;
  tree.setInputCloud(input);
  const int neighbours = std::max(k, 3);
  pcl::Indices indices;
  std::vector<float> distances;
  for (size_t i = 0; i < cloud.size(); ++i) {
    Point& p = cloud[i];
    p.normal_x = p.normal_y = p.normal_z = 0.0f;  // undefined until proven planar
    p.curvature = 0.0f;
    if (radius > 0.0f) {
      tree.radiusSearch(p, radius, indices, distances);
    } else {
      tree.nearestKSearch(p, neighbours, indices, distances);
    }
    if (indices.size() < 3) continue;
    // Covariance about the neighbourhood's mean, in double: PCL's single-pass float sums lose
    // the small eigenvalues of a thin neighbourhood far from the origin.
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const int j : indices) mean += (*input)[j].getVector3fMap().cast<double>();
    mean /= static_cast<double>(indices.size());
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (const int j : indices) {
      const Eigen::Vector3d d = (*input)[j].getVector3fMap().cast<double>() - mean;
      covariance.noalias() += d * d.transpose();
    }
    covariance /= static_cast<double>(indices.size());
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
    solver.computeDirect(covariance);
    const Eigen::Vector3d values = solver.eigenvalues();  // ascending
    // A normal only where the neighbourhood is a surface. On a ring lidar the k nearest points
    // are often one ring's arc (a line: any direction around it fits as well) or straddle two
    // surfaces (the floor and a wall): there the smallest axis is an accident of sampling, and
    // point-to-plane would pull the scan along it (upwards on a floor seen as thin arcs).
    if (!neighbourhoodShape(values).isPlanar()) continue;
    const double sum = values.sum();
    const Eigen::Vector3d normal = solver.eigenvectors().col(0).normalized();
    p.getNormalVector3fMap() = normal.cast<float>();
    p.curvature = sum > 0.0 ? static_cast<float>(std::max(0.0, values(0)) / sum) : 0.0f;
    orientTowards(p, viewpoint);
    // The ground seen from a sensor above it gets upward normals anyway; but seen through a
    // gap or by a sensor tilted down, some point down, and point-to-plane pairs ground points
    // whose normals disagree. Flipping them keeps the ground one surface.
    if (groundNormalsUp > 0.0f && p.normal_z < -groundNormalsUp) {
      p.normal_x = -p.normal_x;
      p.normal_y = -p.normal_y;
      p.normal_z = -p.normal_z;
    }
  }
}

int removeInvalidNormals(Cloud& cloud) {
  const size_t before = cloud.size();
  Cloud kept;
  kept.reserve(cloud.size());
  for (const Point& p : cloud) {
    if (finiteNormal(p)) kept.push_back(p);
  }
  if (kept.size() != before) cloud.swap(kept);
  return static_cast<int>(before - cloud.size());
}

Eigen::Matrix3d normalMomentSum(const Cloud& cloud, bool is2d, int* count) {
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  *count = 0;
  for (const Point& p : cloud) {
    Eigen::Vector3d n = p.getNormalVector3fMap().cast<double>();
    if (is2d) n.z() = 0.0;
    const double norm = n.norm();
    if (!std::isfinite(norm) || norm < 1e-6) continue;
    n /= norm;
    sum += n * n.transpose();
    ++*count;
  }
  return sum;
}

StructuralComplexity cloudComplexity(const IcpCloud& cloud, const Eigen::Matrix3d& rotation) {
  return computeStructuralComplexity(rotation * cloud.normalMoment * rotation.transpose(), cloud.normalCount,
                                     cloud.is2d);
}

LaserScan toLaserScan(const Cloud& cloud, bool is2d, bool withNormals, int maxPoints) {
  const LaserScan::Format format =
      is2d ? (withNormals ? LaserScan::kXYNormal : LaserScan::kXY)
           : (withNormals ? LaserScan::kXYZNormal : LaserScan::kXYZ);
  const int cn = LaserScan::channels(format);
  if (cloud.empty()) return LaserScan(cv::Mat(), 0, 0.0, 0.0, format);
  cv::Mat data(1, static_cast<int>(cloud.size()), CV_32FC(cn));
  float* out = data.ptr<float>(0);
  for (const Point& p : cloud) {
    *out++ = p.x;
    *out++ = p.y;
    if (!is2d) *out++ = p.z;
    if (withNormals) {
      *out++ = p.normal_x;
      *out++ = p.normal_y;
      *out++ = p.normal_z;
    }
  }
  return LaserScan(data, maxPoints, 0.0, 0.0, format);
}

int countCorrespondences(const IcpCloud& target, const Cloud& sourceInTarget, float maxDistance,
                         double* meanSquaredDistance) {
  const float max2 = maxDistance * maxDistance;
  int count = 0;
  double sum = 0.0;
  float d2 = 0.0f;
  for (const Point& p : sourceInTarget) {
    if (target.index.nearest(p.getVector3fMap(), max2, &d2) >= 0) {
      ++count;
      sum += d2;
    }
  }
  if (meanSquaredDistance) *meanSquaredDistance = count > 0 ? sum / count : 0.0;
  return count;
}

bool prepareIcpCloud(const LaserScan& scan, const IcpOptions& options, bool needNormals,
                     const std::string& name, IcpCloud* out, std::string* why, int minPoints) {
  const auto fail = [&](const std::string& reason) {
    if (why) *why = reason;
    out->cloud->clear();
    out->index.clear();
    return false;
  };
  out->is2d = scan.is2d();
  out->hasNormals = false;
  out->normalMoment.setZero();
  out->normalCount = 0;
  out->cloud->clear();
  out->index.clear();
  if (scan.empty()) return fail("scan '" + name + "' is empty");
  if (scan.size() < minPoints) {
    return fail("scan '" + name + "' has " + pointsText(scan.size()) + " (at least " +
                std::to_string(minPoints) + " needed)");
  }

  const int cn = LaserScan::channels(scan.format());
  const bool scanNormals = scan.hasNormals();
  const Transform& local = scan.localTransform().isNull() ? Transform::Identity() : scan.localTransform();
  const Eigen::Matrix3f R = local.rotationMatrix().cast<float>();
  const Eigen::Vector3f t = local.translation().cast<float>();
  const float min2 = options.rangeMin > 0.0f ? options.rangeMin * options.rangeMin : 0.0f;
  const float max2 = options.rangeMax > 0.0f ? options.rangeMax * options.rangeMax : 0.0f;
  const int step = std::max(1, options.downsamplingStep);

  Cloud& cloud = *out->cloud;
  cloud.reserve(scan.size() / step + 1);
  int finite = 0;
  const float* data = scan.data().ptr<float>(0);
  for (int i = 0; i < scan.size(); ++i) {
    const float* v = data + static_cast<size_t>(i) * cn;
    const Eigen::Vector3f p(v[0], v[1], out->is2d ? 0.0f : v[2]);
    if (!p.allFinite()) continue;
    ++finite;
    if (i % step != 0) continue;
    const float r2 = p.squaredNorm();
    if ((min2 > 0.0f && r2 < min2) || (max2 > 0.0f && r2 > max2)) continue;
    Point q;
    q.getVector3fMap() = R * p + t;
    if (out->is2d) q.z = 0.0f;  // a planar scan stays in the base's plane
    if (scanNormals) {
      const float* n = v + cn - 3;
      q.getNormalVector3fMap() = R * Eigen::Vector3f(n[0], n[1], n[2]);
      if (out->is2d) q.normal_z = 0.0f;
    } else {
      q.normal_x = q.normal_y = q.normal_z = 0.0f;
    }
    q.curvature = 0.0f;
    cloud.push_back(q);
  }
  if (finite == 0) {
    return fail("scan '" + name + "' has no finite point (" + std::to_string(scan.size()) +
                " NaN or infinite)");
  }
  const int fullScan = scan.maxPoints() > 0 ? std::max(scan.maxPoints(), finite) : finite;

  voxelFilter(cloud, options.voxelSize);

  if (needNormals) {
    const Eigen::Vector3f viewpoint = t;  // the sensor origin in the base frame
    if (!scanNormals) {
      if (out->is2d) {
        computeNormals2D(cloud, options.pointToPlaneK, options.pointToPlaneRadius, viewpoint);
      } else {
        computeNormals3D(cloud, options.pointToPlaneK, options.pointToPlaneRadius, viewpoint,
                         options.groundNormalsUp);
      }
    }
    removeInvalidNormals(cloud);
    out->hasNormals = true;
    out->normalMoment = normalMomentSum(cloud, out->is2d, &out->normalCount);
  }

  if (out->size() < minPoints) {
    return fail("scan '" + name + "' has " + pointsText(out->size()) + " left of " +
                pointsText(scan.size()) + " after range limits, downsampling" +
                (needNormals ? ", voxel filter and normals" : " and voxel filter") +
                " (at least " + std::to_string(minPoints) + " needed)");
  }
  out->expectedPoints = static_cast<int>(
      std::lround(static_cast<double>(fullScan) * out->size() / std::max(1, finite)));
  out->expectedPoints = std::max(out->expectedPoints, out->size());
  return true;
}

}  // namespace rtabmap::icp
