#pragma once
// A refined neighbour link fused with the odometry it refines (RGBD/NeighborLinkRefiningPrior).
//
// ICP between two scans of a corridor constrains the motion across the corridor and the turn,
// not the motion along it: there its covariance is large and its result slides toward no
// motion (ACES: 0.16 m of odometry refined to -0.01 m), while the wheels measured it well.
// Replacing the odometry by ICP (the original's refinement) throws that away; fusing the two by
// information keeps each where it is informative:
//
//   d  = log(odometry^-1 * registered)          the registration's correction, 6-vector
//   d* = (L_reg + L_odo)^-1 L_reg d             (the odometry's own correction is zero)
//   fused = odometry * exp(d*)
//
// with L_reg the registration's information and L_odo = diag(1/s^2, 1/s^2, 1/s^2, 0, 0, 0),
// s = 1 cm + prior x the odometry's translation: a weak prior on translation only, since ICP's
// rotation is better than wheel odometry's wherever a wall is seen. Small corrections are
// assumed (the tangent space of the guess; ICP's corrections are bounded by Icp/MaxTranslation
// and Icp/MaxRotation).
#include <Eigen/Core>

#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap {

// `registered` and `odometry` are the same motion (from the previous node to the new one);
// `information` is the registration's (x, y, z, roll, pitch, yaw). prior <= 0, a null
// transform or an information whose sum with the prior cannot be solved: `registered`.
Transform fuseWithOdometryPrior(const Transform& registered, const Eigen::Matrix<double, 6, 6>& information,
                                const Transform& odometry, double prior);

}  // namespace rtabmap
