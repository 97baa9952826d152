#pragma once
// The error of a link and the chi2 of a graph, in g2o's convention (the one of the reference
// values in the data README and of the optimiser's objective):
//
//   chi2 = sum over links of e' * Omega * e,   E = Z^-1 * (Xi^-1 * Xj)
//   SE2: e = [x, y, theta] of E, theta wrapped to (-pi, pi]; Omega on x, y, yaw.
//   SE3: e = [x, y, z, qx, qy, qz] of E with the quaternion's w >= 0 (its vector part, about
//        half the rotation angle); Omega on x, y, z and the quaternion vector.
//
// A Link's information is per radian (x y z roll pitch yaw, see memory/Link.h), so in SE3 its
// rotation rows and columns are scaled by 2 to weigh the quaternion vector (an error of angle a
// about axis u has vector part sin(a/2) u, about a/2 u): Omega_g2o = D * Omega_link * D with
// D = diag(1, 1, 1, 2, 2, 2). g2o files store Omega_g2o; the file readers convert both ways.
//
// Priors (kPosePrior, from == to) use E = Z^-1 * X with the same error vector.
#include <map>

#include <Eigen/Core>

#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/memory/Link.h"

namespace rtabmap::graph {

using Vector6 = Eigen::Matrix<double, 6, 1>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

// Information on (x, y, yaw): rows/columns 0, 1, 5 of the link's matrix.
Eigen::Matrix3d informationSE2(const Link::InfMatrix& information);
// A Link information from an (x, y, theta) one; z, roll and pitch get `unusedDiagonal` (they
// are ignored in 3DoF, but a Link needs a positive-definite matrix).
Link::InfMatrix linkInformationFromSE2(const Eigen::Matrix3d& information,
                                       double unusedDiagonal = 1.0);
// Link (per radian) <-> g2o SE3 (per quaternion-vector unit).
Matrix6 informationSE3ToG2o(const Link::InfMatrix& information);
Link::InfMatrix informationSE3FromG2o(const Matrix6& information);

// Error vectors of a relative measurement `z` between poses `from` and `to`.
Eigen::Vector3d errorSE2(const Transform& from, const Transform& to, const Transform& z);
Vector6 errorSE3(const Transform& from, const Transform& to, const Transform& z);

// e' * Omega * e of one link (a prior if from == to) given the poses of its ends (the pose of
// `from` only for a prior). With identityInformation, Omega = identity (Optimizer/VarianceIgnored).
double linkChi2(const Link& link, const Transform& from, const Transform& to, bool is2D,
                bool identityInformation = false);

// Sum of linkChi2 over the links whose ends all have a non-null pose in `poses`, with types
// relative links and priors (gravity and links with an absent end are skipped).
double computeChi2(const std::map<int, Transform>& poses, const std::multimap<int, Link>& links,
                   bool is2D, bool identityInformation = false);

}  // namespace rtabmap::graph
