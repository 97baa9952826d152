#pragma once
// The laser scan a new node keeps (Mem/LaserScanDownsampleStepSize, Mem/LaserScanVoxelSize,
// Mem/LaserScanNormalK, Mem/LaserScanNormalRadius, as the original's): filtered once, when the
// node is made, so that every later use of it (neighbour-link refining, proximity detection,
// loop-closure ICP, the local grid, the database, the clouds shown in rviz) works on the smaller
// scan, and the normals point-to-plane ICP needs are computed once instead of at every
// registration. What a 3D lidar of 100,000 points a sweep needs; a 2D lidar rarely does.
#include <string>

#include "rtabmap_core/geometry/LaserScan.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {

struct ScanFilterOptions {
  int downsampleStep = 1;     // Mem/LaserScanDownsampleStepSize: one point out of N (1 = all)
  float voxelSize = 0.0f;     // Mem/LaserScanVoxelSize (m, 0 = none)
  int normalK = 0;            // Mem/LaserScanNormalK: normals from K neighbours (0 = none)
  float normalRadius = 0.0f;  // Mem/LaserScanNormalRadius (m): normals from neighbours within it

  // From the Mem/LaserScan* parameters (defaults for absent keys); throws ParameterError.
  static ScanFilterOptions fromParameters(const ParametersMap& parameters);
  bool IsValid(std::string* why = nullptr) const;
  bool active() const { return downsampleStep > 1 || voxelSize > 0.0f || wantsNormals(); }
  bool wantsNormals() const { return normalK > 0 || normalRadius > 0.0f; }
};

// One point out of downsampleStep, non-finite points dropped, a voxel grid (one averaged point
// per voxel, a 2D scan kept in bearing order), then normals when asked and the scan has none
// (2D normals in the scan's plane for a 2D scan; points whose neighbourhood gives no normal
// are dropped). Same format family (2D stays 2D), same local transform, range limits and
// maxPoints scaled by what the filters kept (ICP's correspondence ratio divides by it). A scan
// that is empty, or that nothing is left of, comes back empty with the reason in *why.
LaserScan filterScan(const LaserScan& scan, const ScanFilterOptions& options, std::string* why = nullptr);

}  // namespace rtabmap
