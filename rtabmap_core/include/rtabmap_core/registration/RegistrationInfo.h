#pragma once
// What a registration (visual or ICP) found, or why it found nothing. Every registration
// returns the transform (null on failure) and fills one of these.
#include <Eigen/Core>

#include <string>
#include <vector>

namespace rtabmap {

struct RegistrationInfo {
  // Null transform returned <=> !success; `rejectedMsg` then says why in words a user
  // understands ("only 12 inliers, Vis/MinInliers is 20", "correspondence ratio 0.05 under
  // Icp/CorrespondenceRatio 0.1", ...).
  bool success = false;
  std::string rejectedMsg;
  // Covariance of the transform (x y z roll pitch yaw); identity-scaled when unknown.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Identity();

  // Visual
  int matches = 0;               // putative correspondences
  int inliers = 0;               // after RANSAC (and bundle adjustment)
  double inliersMeanDistance = 0.0;  // m, of the inlier 3D points
  double inliersDistribution = 0.0;  // spread of inliers over the image (0..1)
  std::vector<int> matchesIDs;   // word/feature ids of the matches (for display)
  std::vector<int> inliersIDs;   // word/feature ids of the inliers

  // ICP
  int icpCorrespondences = 0;
  double icpInliersRatio = 0.0;           // correspondences / points of the smaller cloud
  double icpTranslation = 0.0;            // m, of the ICP correction applied to the guess
  double icpRotation = 0.0;               // rad, of the ICP correction
  double icpStructuralComplexity = 0.0;   // PCA of normals (see Icp/PointToPlaneMinComplexity)
  double icpStructuralDistribution = 0.0;

  double totalTimeMs = 0.0;
};

}  // namespace rtabmap
