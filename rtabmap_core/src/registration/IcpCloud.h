#pragma once
// Private to the library: a scan converted to a PCL cloud and made ready for ICP (filtered,
// with normals and a search index when needed), and the ICP itself on such clouds. Kept out of the
// public headers so only the few files that run ICP pay PCL's compile time.
//
// The public IcpRegistration prepares both scans on every call; the lidar odometry keeps its
// map or key frame as a prepared IcpCloud so its search index is built once per key frame, not
// once per scan.
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>

#include <Eigen/Core>

#include <string>

#include "rtabmap_core/geometry/LaserScan.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/registration/IcpRegistration.h"
#include "rtabmap_core/registration/RegistrationInfo.h"
#include "rtabmap_core/registration/StructuralComplexity.h"
#include "IcpScanIndex.h"

namespace rtabmap::icp {

// Every cloud uses PointNormal (normals zero when absent): one type means one instantiation
// of PCL's ICP templates, and a 2D point is simply one with z = 0.
using Point = pcl::PointNormal;
using Cloud = pcl::PointCloud<Point>;
using Tree = pcl::search::KdTree<Point>;

struct IcpCloud {
  Cloud::Ptr cloud{new Cloud};
  ScanIndex index;          // over `cloud`, built by buildIndex() (empty until then)
  bool is2d = true;
  bool hasNormals = false;  // every point has a finite unit normal
  // How many points this cloud would have if every beam of the scan had returned, after the
  // same filtering (scan maxPoints scaled by what the filters kept; the size if unknown). The
  // correspondence ratio divides by it, so a scan that sees little of its surroundings is not
  // judged a good match because the little it sees matches.
  int expectedPoints = 0;
  // Sum of n n^T over the normals (hasNormals), kept by whoever edits the cloud: the structural
  // complexity of the cloud, turned by any rotation, without visiting its normals again.
  Eigen::Matrix3d normalMoment = Eigen::Matrix3d::Zero();
  int normalCount = 0;

  int size() const { return static_cast<int>(cloud->size()); }
  bool empty() const { return cloud->empty(); }
  // Indexes the cloud for correspondences up to `maxDistance` (Icp/MaxCorrespondenceDistance).
  void buildIndex(float maxDistance) { index.build(*cloud, maxDistance, is2d); }
};

// Range limits and downsampling step of the options, non-finite points dropped, points (and
// normals) to the base frame, voxel grid, then normals when `needNormals` (kept from the scan
// when it has them, else computed from Icp/PointToPlaneK or Radius, oriented towards the
// sensor; points whose normal cannot be computed are dropped). Returns false with the reason
// when the scan is unusable: empty, or fewer than `minPoints` points left (naming `name`).
bool prepareIcpCloud(const LaserScan& scan, const IcpOptions& options, bool needNormals,
                     const std::string& name, IcpCloud* out, std::string* why, int minPoints = 3);

// Grid filter keeping one averaged point (and renormalised normal) per occupied voxel, in the
// order voxels are first met, so a 2D scan stays ordered by bearing. Hash-based: PCL's
// VoxelGrid indexes voxels with 32-bit integers and silently stops filtering on wide clouds
// (a large 3D map at a fine voxel size).
void voxelFilter(Cloud& cloud, float voxelSize);

// Normals of a planar scan: for each point, the line fitted to its k nearest neighbours (or
// those within radius) in the xy plane; the normal is perpendicular to it in that plane,
// pointing towards `viewpoint`. A 3D normal estimator would give (0, 0, 1) for every point of
// a planar cloud. Neighbours are looked for among the k points before and after in the scan's
// order (a planar lidar's points come ordered by bearing, and voxelFilter keeps that order):
// no tree to build, and across a depth gap the far side is not among the nearest.
void computeNormals2D(Cloud& cloud, int k, float radius, const Eigen::Vector3f& viewpoint);
// Shape of a neighbourhood from the eigenvalues of its covariance (ascending), the
// dimensionality features of Demantke et al. 2011 ("Dimensionality based scale selection in 3D
// lidar point clouds"): with s1 >= s2 >= s3 the standard deviations along the principal axes,
// linearity (s1 - s2) / s1, planarity (s2 - s3) / s1, scattering s3 / s1 (they sum to 1).
// The neighbourhood is a surface, and its smallest axis a normal, when planarity dominates.
struct NeighbourhoodShape {
  double linearity = 0.0;
  double planarity = 0.0;
  double scattering = 0.0;
  bool isPlanar() const { return planarity > linearity && planarity > scattering; }
};
NeighbourhoodShape neighbourhoodShape(const Eigen::Vector3d& ascendingEigenvalues);

// Normals of a 3D cloud from the k nearest neighbours (or those within radius), pointing
// towards `viewpoint`; with groundNormalsUp > 0, normals pointing down more than that (-z
// alignment) are flipped up. A point whose neighbourhood is not planar (NeighbourhoodShape: a
// single ring's arc, a corner, clutter) gets no normal (zero), so removeInvalidNormals drops it.
void computeNormals3D(Cloud& cloud, int k, float radius, const Eigen::Vector3f& viewpoint,
                      float groundNormalsUp);
// Drops points without a finite normal; returns how many were dropped.
int removeInvalidNormals(Cloud& cloud);

// Sum of n n^T over the cloud's normals (each normalised; invalid ones skipped), and their count.
Eigen::Matrix3d normalMomentSum(const Cloud& cloud, bool is2d, int* count);
// The complexity of the cloud's normals turned by `rotation` (into another frame).
StructuralComplexity cloudComplexity(const IcpCloud& cloud,
                                     const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity());

// Back to a LaserScan (XY/XYNormal for 2D, XYZ/XYZNormal otherwise), identity local transform.
LaserScan toLaserScan(const Cloud& cloud, bool is2d, bool withNormals, int maxPoints = 0);

// The ICP: the pose of `source`'s frame in `target`'s frame, from `guess` (pose of the source
// frame in the target frame). `target` needs its index (buildIndex with at least
// Icp/MaxCorrespondenceDistance) and, for point-to-plane,
// normals; `source` needs normals only for the structural complexity (point-to-plane).
// Null with info->rejectedMsg on failure; info gets the ICP fields and the covariance.
Transform registerClouds(const IcpCloud& target, const IcpCloud& source, const Transform& guess,
                         const IcpOptions& options, RegistrationInfo* info);

// Nearest target point within maxDistance of each transformed source point: the count, and the
// mean squared distance of those pairs.
int countCorrespondences(const IcpCloud& target, const Cloud& sourceInTarget, float maxDistance,
                         double* meanSquaredDistance = nullptr);

}  // namespace rtabmap::icp
