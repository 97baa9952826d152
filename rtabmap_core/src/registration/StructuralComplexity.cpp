#include "rtabmap_core/registration/StructuralComplexity.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace rtabmap {

StructuralComplexity computeStructuralComplexity(const Eigen::Matrix3Xf& normals, bool is2d) {
  Eigen::Matrix3d moment = Eigen::Matrix3d::Zero();
  int count = 0;
  for (Eigen::Index i = 0; i < normals.cols(); ++i) {
    Eigen::Vector3d n = normals.col(i).cast<double>();
    if (is2d) n.z() = 0.0;
    if (!n.allFinite()) continue;
    const double norm = n.norm();
    if (norm < 1e-6) continue;
    n /= norm;
    moment += n * n.transpose();
    ++count;
  }
  return computeStructuralComplexity(moment, count, is2d);
}

StructuralComplexity computeStructuralComplexity(const Eigen::Matrix3d& momentSum, int normals, bool is2d) {
  StructuralComplexity result;
  result.dimensions = is2d ? 2 : 3;
  result.normals = normals;
  if (normals <= 0) return result;
  const Eigen::Matrix3d moment = momentSum / normals;
  Eigen::Vector3d values;
  Eigen::Matrix3d vectors;
  if (is2d) {
    // Only the plane: z has no normal component (its row and column are 0).
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> planar(moment.topLeftCorner<2, 2>());
    values << planar.eigenvalues().cwiseMax(0.0), 0.0;
    vectors.setZero();
    vectors.topLeftCorner<2, 2>() = planar.eigenvectors();
    vectors(2, 2) = 1.0;
  } else {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(moment);  // ascending eigenvalues
    values = solver.eigenvalues().cwiseMax(0.0);
    vectors = solver.eigenvectors();
  }
  result.eigenvalues = values;
  result.directions = vectors;
  result.value = std::min(1.0, values(0) * result.dimensions);
  return result;
}

StructuralComplexity computeStructuralComplexity(const LaserScan& scan) {
  if (!scan.hasNormals() || scan.empty()) {
    StructuralComplexity none;
    none.dimensions = scan.is2d() ? 2 : 3;
    return none;
  }
  // Normals are the last three channels of every format that has them.
  const int channels = LaserScan::channels(scan.format());
  Eigen::Matrix3Xf normals(3, scan.size());
  const float* data = scan.data().ptr<float>(0);
  for (int i = 0; i < scan.size(); ++i) {
    const float* p = data + i * channels + channels - 3;
    normals.col(i) << p[0], p[1], p[2];
  }
  return computeStructuralComplexity(normals, scan.is2d());
}

}  // namespace rtabmap
