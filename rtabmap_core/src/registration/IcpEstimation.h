#pragma once
// Private: the transform estimation step of ICP restricted to some degrees of freedom, as a PCL
// TransformationEstimation so pcl::IterativeClosestPoint drives it like its own.
//
// Why not PCL's: TransformationEstimationPointToPlaneLLS always solves all six degrees of
// freedom, so a planar scan would wander in z, roll and pitch whenever its normals do not pin
// them; TransformationEstimation2D is point-to-point only and moves z by the centroid
// difference. This one linearises the rotation (small angles, as PCL's LLS does: ICP iterates)
// and solves the normal equations over the chosen subset of (x, y, z, roll, pitch, yaw) only:
//   point-to-plane, per pair (p source, q target, n target normal):
//     n . (p + w x p + t - q) = 0   ->  [n, p x n] . [t; w] = n . (q - p)
//   point-to-point, per pair: p + w x p + t - q = 0  ->  [I, -[p]x] [t; w] = q - p
// A direction the pairs do not constrain (a corridor's axis) gets a near-zero system; a tiny
// damping keeps its update at zero instead of letting noise decide it.
#include <pcl/registration/transformation_estimation.h>

#include <Eigen/Core>

#include <array>

#include "IcpCloud.h"

namespace rtabmap::icp {

// Which of x, y, z, roll, pitch, yaw are estimated.
using DofMask = std::array<bool, 6>;
inline DofMask dofPlanar() { return {true, true, false, false, false, true}; }
inline DofMask dof4() { return {true, true, true, false, false, true}; }
inline DofMask dof6() { return {true, true, true, true, true, true}; }

class ConstrainedEstimation : public pcl::registration::TransformationEstimation<Point, Point, float> {
 public:
  using Matrix4 = pcl::registration::TransformationEstimation<Point, Point, float>::Matrix4;

  ConstrainedEstimation(const DofMask& dofs, bool pointToPlane) : dofs_(dofs), pointToPlane_(pointToPlane) {}

  void estimateRigidTransformation(const Cloud& source, const Cloud& target,
                                   Matrix4& transform) const override;
  void estimateRigidTransformation(const Cloud& source, const pcl::Indices& sourceIndices,
                                   const Cloud& target, Matrix4& transform) const override;
  void estimateRigidTransformation(const Cloud& source, const pcl::Indices& sourceIndices,
                                   const Cloud& target, const pcl::Indices& targetIndices,
                                   Matrix4& transform) const override;
  void estimateRigidTransformation(const Cloud& source, const Cloud& target,
                                   const pcl::Correspondences& correspondences,
                                   Matrix4& transform) const override;

 private:
  template <typename PairAt>
  void solve(size_t pairs, const PairAt& pairAt, Matrix4& transform) const;

  DofMask dofs_;
  bool pointToPlane_;
};

// Gauss-Newton information of the final alignment `pose` (source frame in target frame), over
// a perturbation of the pose in the *source* frame (pose * delta): the rows above with the
// source points in their own frame and the target points and normals brought into it. So the
// covariance is the robot's (x forward, yaw about the robot), not about the target's origin,
// which for a map can be far away. normalisedInformation = J^T J / n, n the residual count
// (1 per pair point-to-plane, 2 or 3 point-to-point in 2D or 3D); residualVariance =
// sum(r^2) / (n - dofs). Used for the covariance (see IcpAlign.cpp).
struct AlignmentInformation {
  Eigen::Matrix<double, 6, 6> normalisedInformation = Eigen::Matrix<double, 6, 6>::Zero();
  double residualVariance = 0.0;
  int residuals = 0;
};
AlignmentInformation alignmentInformation(const Cloud& source, const Cloud& target,
                                          const pcl::Correspondences& correspondences,
                                          const Eigen::Isometry3d& pose, bool pointToPlane,
                                          bool is2d, int dofs);

}  // namespace rtabmap::icp
