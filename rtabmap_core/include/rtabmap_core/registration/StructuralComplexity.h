#pragma once
// Structural complexity of a scan (JFR 2019, 3.1.2, Icp/PointToPlaneMinComplexity): how well its
// surfaces constrain a registration in every direction, from its normals alone.
//
// M = mean(n n^T) over the unit normals. A surface with normal n only constrains motion along
// n, so an eigenvector of M with a small eigenvalue is a direction in which few surfaces face
// the sensor and ICP can slide. M's eigenvalues sum to 1, so the smallest one is at most 1/2
// in 2D and 1/3 in 3D: times 2 (2D) or 3 (3D) it is a complexity in [0, 1], 1 when normals
// face every direction equally (a room), ~0 in a corridor or in front of a single wall.
//
// M is the second moment, not the covariance about the mean normal: n and -n constrain the
// same direction, and a corner seen from inside (normals (-1,0) and (0,-1)) must count as fully
// constrained; subtracting the mean normal would make it look degenerate.
#include <Eigen/Core>

#include "rtabmap_core/geometry/LaserScan.h"

namespace rtabmap {

struct StructuralComplexity {
  double value = 0.0;  // smallest eigenvalue x dimension, in [0, 1]; 0 without normals
  int dimensions = 2;  // 2 for planar scans (normals in the xy plane), 3 otherwise
  int normals = 0;     // finite normals used
  // Eigenvalues of M, ascending over the first `dimensions` entries (in 2D the third is z's, 0),
  // and the matching unit eigenvectors as columns of `directions`.
  Eigen::Vector3d eigenvalues = Eigen::Vector3d::Zero();
  Eigen::Matrix3d directions = Eigen::Matrix3d::Identity();

  // Eigenvalue i relative to an even spread (eigenvalue x dimension): a direction is
  // constrained when this is at least Icp/PointToPlaneMinComplexity.
  double relativeEigenvalue(int i) const { return eigenvalues[i] * dimensions; }
};

// From unit normals (columns; non-finite ones are skipped, the others need not be exactly
// unit: each is normalised). is2d uses only x and y.
StructuralComplexity computeStructuralComplexity(const Eigen::Matrix3Xf& normals, bool is2d);
// From the sum of n n^T over `normals` unit normals: a map that gains and loses points keeps
// that sum up to date instead of going over all its normals again (and R sum R^T is the
// complexity of the same normals rotated by R).
StructuralComplexity computeStructuralComplexity(const Eigen::Matrix3d& momentSum, int normals, bool is2d);
// From a scan with normals (XYNormal, XYZNormal, ...), in its sensor frame; value 0 and no
// normals counted when the scan has none.
StructuralComplexity computeStructuralComplexity(const LaserScan& scan);

}  // namespace rtabmap
