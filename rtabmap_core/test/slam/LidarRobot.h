#pragma once
// A 2D lidar robot for the Rtabmap tests on ICP scenes (registration/IcpTestScenes.h): links by
// point-to-plane ICP on 5 cm voxels, 3 DoF, neighbour links refined by the scans, no proximity
// detection, one node per frame.
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap::test {

inline ParametersMap lidarRobot() {
  return {{Parameters::kRtabmapDetectionRate(), "0"},
          {Parameters::kRegStrategy(), "1"},
          {Parameters::kRegForce3DoF(), "true"},
          {Parameters::kRGBDNeighborLinkRefining(), "true"},
          {Parameters::kRGBDProximityBySpace(), "false"},
          {Parameters::kIcpPointToPlane(), "true"},
          {Parameters::kIcpVoxelSize(), "0.05"},
          {Parameters::kIcpMaxCorrespondenceDistance(), "0.3"},
          {Parameters::kIcpIterations(), "30"},
          {Parameters::kIcpMaxTranslation(), "1"}};
}

}  // namespace rtabmap::test
