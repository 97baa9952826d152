#include "IcpEstimation.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

namespace rtabmap::icp {

namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// Adds the rows of one pair to J^T J and J^T b (and returns the squared residual).
double accumulatePair(const Point& p, const Point& q, bool pointToPlane, Matrix6d& jtj, Vector6d& jtb) {
  const Eigen::Vector3d ps = p.getVector3fMap().cast<double>();
  const Eigen::Vector3d qt = q.getVector3fMap().cast<double>();
  if (pointToPlane) {
    const Eigen::Vector3d n = q.getNormalVector3fMap().cast<double>();
    Vector6d row;
    row << n, ps.cross(n);
    const double b = n.dot(qt - ps);
    jtj.noalias() += row * row.transpose();
    jtb.noalias() += row * b;
    return b * b;
  }
  // Rows [I, -[p]x]: d(w x p)/dw = -[p]x.
  Eigen::Matrix<double, 3, 6> rows;
  rows.leftCols<3>().setIdentity();
  rows.rightCols<3>() << 0.0, ps.z(), -ps.y(),
                         -ps.z(), 0.0, ps.x(),
                         ps.y(), -ps.x(), 0.0;
  const Eigen::Vector3d b = qt - ps;
  jtj.noalias() += rows.transpose() * rows;
  jtb.noalias() += rows.transpose() * b;
  return b.squaredNorm();
}

}  // namespace

template <typename PairAt>
void ConstrainedEstimation::solve(size_t pairs, const PairAt& pairAt, Matrix4& transform) const {
  transform.setIdentity();
  Matrix6d jtj = Matrix6d::Zero();
  Vector6d jtb = Vector6d::Zero();
  for (size_t i = 0; i < pairs; ++i) {
    const auto pair = pairAt(i);
    if (pointToPlane_ && !pair.second->getNormalVector3fMap().allFinite()) continue;
    accumulatePair(*pair.first, *pair.second, pointToPlane_, jtj, jtb);
  }
  int index[6];
  int n = 0;
  for (int i = 0; i < 6; ++i) {
    if (dofs_[i]) index[n++] = i;
  }
  Eigen::MatrixXd a(n, n);
  Eigen::VectorXd g(n);
  for (int r = 0; r < n; ++r) {
    g(r) = jtb(index[r]);
    for (int c = 0; c < n; ++c) a(r, c) = jtj(index[r], index[c]);
  }
  const double damping = 1e-9 * std::max(a.trace(), 1e-12);
  a.diagonal().array() += damping;
  const Eigen::VectorXd x = a.ldlt().solve(g);
  if (!x.allFinite()) return;  // identity: leave the pose where it is
  Vector6d delta = Vector6d::Zero();
  for (int r = 0; r < n; ++r) delta(index[r]) = x(r);

  // Rotation as R = Rz(yaw) Ry(pitch) Rx(roll) from the small-angle solution, like PCL's LLS.
  const Eigen::Matrix3d rotation =
      (Eigen::AngleAxisd(delta(5), Eigen::Vector3d::UnitZ()) *
       Eigen::AngleAxisd(delta(4), Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(delta(3), Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  transform.topLeftCorner<3, 3>() = rotation.cast<float>();
  transform.block<3, 1>(0, 3) = delta.head<3>().cast<float>();
}

void ConstrainedEstimation::estimateRigidTransformation(const Cloud& source, const Cloud& target,
                                                        Matrix4& transform) const {
  const size_t n = std::min(source.size(), target.size());
  solve(n, [&](size_t i) { return std::make_pair(&source[i], &target[i]); }, transform);
}

void ConstrainedEstimation::estimateRigidTransformation(const Cloud& source, const pcl::Indices& sourceIndices,
                                                        const Cloud& target, Matrix4& transform) const {
  const size_t n = std::min(sourceIndices.size(), target.size());
  solve(n, [&](size_t i) { return std::make_pair(&source[sourceIndices[i]], &target[i]); }, transform);
}

void ConstrainedEstimation::estimateRigidTransformation(const Cloud& source, const pcl::Indices& sourceIndices,
                                                        const Cloud& target, const pcl::Indices& targetIndices,
                                                        Matrix4& transform) const {
  const size_t n = std::min(sourceIndices.size(), targetIndices.size());
  solve(n, [&](size_t i) { return std::make_pair(&source[sourceIndices[i]], &target[targetIndices[i]]); },
        transform);
}

void ConstrainedEstimation::estimateRigidTransformation(const Cloud& source, const Cloud& target,
                                                        const pcl::Correspondences& correspondences,
                                                        Matrix4& transform) const {
  solve(correspondences.size(),
        [&](size_t i) {
          return std::make_pair(&source[correspondences[i].index_query], &target[correspondences[i].index_match]);
        },
        transform);
}

AlignmentInformation alignmentInformation(const Cloud& source, const Cloud& target,
                                          const pcl::Correspondences& correspondences,
                                          const Eigen::Isometry3d& pose, bool pointToPlane,
                                          bool is2d, int dofs) {
  AlignmentInformation info;
  Matrix6d jtj = Matrix6d::Zero();
  Vector6d jtb = Vector6d::Zero();
  double squared = 0.0;
  const Eigen::Isometry3d inverse = pose.inverse();
  for (const pcl::Correspondence& c : correspondences) {
    const Point& q = target[c.index_match];
    if (pointToPlane && !q.getNormalVector3fMap().allFinite()) continue;
    // The target point and normal in the source frame: then the rows of accumulatePair are
    // those of a perturbation of the pose on the source side, and the residuals unchanged.
    Point local = q;
    local.getVector3fMap() = (inverse * q.getVector3fMap().cast<double>()).cast<float>();
    local.getNormalVector3fMap() = (inverse.linear() * q.getNormalVector3fMap().cast<double>()).cast<float>();
    squared += accumulatePair(source[c.index_query], local, pointToPlane, jtj, jtb);
    // A planar pair's z residual is 0 by construction, not a measurement.
    info.residuals += pointToPlane ? 1 : (is2d ? 2 : 3);
  }
  if (info.residuals == 0) return info;
  info.normalisedInformation = jtj / info.residuals;
  info.residualVariance = squared / std::max(1, info.residuals - dofs);
  return info;
}

}  // namespace rtabmap::icp
