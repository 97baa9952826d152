#pragma once
// ICP registration of laser scans (2D) and point clouds (3D) through PCL (JFR 2019, 3.1.2 and
// 4.2): the rigid transform that aligns a scan onto another, starting from a guess.
//
// Pipeline, each step from an Icp/* parameter:
//   range limits (Icp/RangeMin/Max) -> one point out of Icp/DownsamplingStep -> voxel grid
//   (Icp/VoxelSize) -> normals when point-to-plane (Icp/PointToPlaneK or Radius; 2D scans get
//   2D normals, never a normal out of their plane) -> structural complexity -> ICP
//   (Icp/MaxCorrespondenceDistance, Icp/Iterations, Icp/Epsilon; 3 degrees of freedom for 2D
//   scans and with Reg/Force3DoF, 4 with Icp/Force4DoF, else 6) -> acceptance (correspondence
//   ratio, Icp/MaxTranslation, Icp/MaxRotation) -> low-complexity strategy -> covariance.
//
// Structural complexity (Icp/PointToPlaneMinComplexity): how many directions the scan's
// surfaces constrain. The second moment of the unit normals, M = mean(n n^T), has eigenvalues
// summing to 1; its smallest (the 2nd in 2D, the 3rd in 3D) times the dimension is 1 when the
// normals are spread evenly over every direction and 0 when some direction has no surface
// facing it (a corridor: every wall is parallel to the direction of travel, so ICP cannot see
// motion along it). Below the minimum, Icp/PointToPlaneLowComplexityStrategy decides: reject,
// keep the rotation and the translation along the constrained directions while the
// unconstrained ones come from the guess, or accept a point-to-point result as is.
#include <string>

#include "rtabmap_core/geometry/LaserScan.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/params/Parameters.h"
#include "rtabmap_core/registration/RegistrationInfo.h"

namespace rtabmap {

struct IcpOptions {
  float maxTranslation = 0.2f;             // Icp/MaxTranslation (m, 0 = no limit)
  float maxRotation = 0.78f;               // Icp/MaxRotation (rad, 0 = no limit)
  float voxelSize = 0.05f;                 // Icp/VoxelSize (m, 0 = none)
  int downsamplingStep = 1;                // Icp/DownsamplingStep
  float rangeMin = 0.0f;                   // Icp/RangeMin (m, 0 = none)
  float rangeMax = 0.0f;                   // Icp/RangeMax (m, 0 = none)
  float maxCorrespondenceDistance = 0.05f; // Icp/MaxCorrespondenceDistance (m)
  int iterations = 30;                     // Icp/Iterations
  float epsilon = 0.0f;                    // Icp/Epsilon (0 = all iterations)
  float correspondenceRatio = 0.1f;        // Icp/CorrespondenceRatio
  bool force4DoF = false;                  // Icp/Force4DoF
  bool force3DoF = false;                  // Reg/Force3DoF
  bool pointToPlane = false;               // Icp/PointToPlane
  int pointToPlaneK = 5;                   // Icp/PointToPlaneK
  float pointToPlaneRadius = 0.0f;         // Icp/PointToPlaneRadius
  float groundNormalsUp = 0.0f;            // Icp/PointToPlaneGroundNormalsUp
  float minComplexity = 0.02f;             // Icp/PointToPlaneMinComplexity
  int lowComplexityStrategy = 1;           // Icp/PointToPlaneLowComplexityStrategy
  float maxNormalAngle = 0.0f;             // Icp/PointToPlaneMaxNormalAngle, here in radians (0 = any)

  // From Icp/* and Reg/Force3DoF (defaults for absent keys). Throws ParameterError on an
  // undeclared key or an invalid value.
  static IcpOptions fromParameters(const ParametersMap& parameters);
  // False with the reason (naming the parameter) for a combination no ICP can run with.
  bool IsValid(std::string* why = nullptr) const;
};

class IcpRegistration {
 public:
  // Throws ParameterError on bad parameters (see IcpOptions).
  explicit IcpRegistration(const ParametersMap& parameters = {});
  explicit IcpRegistration(const IcpOptions& options);

  const IcpOptions& options() const { return options_; }

  // The pose of `to`'s base frame in `from`'s base frame (each scan's points go through its
  // localTransform first), refined from `guess` (null = identity). Returns a null Transform
  // when rejected, with info->rejectedMsg saying why: empty / too few / non-finite points,
  // too few correspondences, a correction beyond Icp/MaxTranslation or Icp/MaxRotation, a
  // low-complexity scan under strategy 0. Never throws on bad scan data.
  Transform computeTransform(const LaserScan& from, const LaserScan& to,
                             const Transform& guess = Transform(),
                             RegistrationInfo* info = nullptr) const;

 private:
  IcpOptions options_;
};

}  // namespace rtabmap
