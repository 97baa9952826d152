#include "MultiCameraReprojection.h"

#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include "MultiCameraReprojectionCost.h"

namespace rtabmap::registration_internal {

Eigen::Isometry3d refineMultiCameraReprojection(const Eigen::Isometry3d& motion,
                                                const std::vector<CameraObservation>& observations,
                                                const std::vector<int>& inliers,
                                                const std::vector<PinholeCamera>& cameras, int iterations) {
  const Eigen::Isometry3d inverse = motion.inverse();
  Eigen::Quaterniond q(inverse.rotation());
  q.normalize();
  Eigen::Vector3d t = inverse.translation();
  ceres::Problem problem;
  for (int k : inliers) {
    const CameraObservation& o = observations[static_cast<size_t>(k)];
    problem.AddResidualBlock(MultiCameraReprojectionCost::create(o, cameras[static_cast<size_t>(o.camera)]), nullptr,
                             q.coeffs().data(), t.data());
  }
  if (problem.NumResidualBlocks() == 0) return motion;
  problem.SetManifold(q.coeffs().data(), new ceres::EigenQuaternionManifold());
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;  // 6 unknowns
  options.max_num_iterations = iterations;
  options.num_threads = 1;  // called per frame from odometry: no thread pool for a 6x6 system
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (!summary.IsSolutionUsable()) return motion;
  Eigen::Isometry3d refined = Eigen::Isometry3d::Identity();
  refined.linear() = q.normalized().toRotationMatrix();
  refined.translation() = t;
  return refined.inverse();
}

}  // namespace rtabmap::registration_internal
