#pragma once
// rtabmap-export's work, apart from its command line: read the nodes of a database, make their
// maps from the local grids stored with them (or computed again from their sensor data), write
// the files asked for. Nodes are placed at the pose stored in each node row (odometry, or the
// optimised pose once the SLAM pipeline rewrites it there): the maps take poses as input, so the
// export does not optimise the graph itself.
#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

#include "rtabmap_core/params/Parameters.h"

namespace rtabmap::tools::exporter {

struct Request {
  std::string database;
  std::string gridPath;     // .pgm (+ .yaml and .png beside it); "" = none
  std::string octomapPath;  // .bt or .ot
  std::string cloudPath;    // .ply or .pcd
  std::string posesPath;    // TUM: stamp x y z qx qy qz qw
  bool regenerate = false;  // compute every local grid again from the sensor data
  int pngScale = 1;
  // Core parameters: the database's last session parameters overridden by the command line's.
  ParametersMap parameters;
  bool cellSizeGiven = false;  // Grid/CellSize given on the command line
};

struct Report {
  nlohmann::json json;  // what --json prints
  std::vector<std::string> warnings;
};

// Throws rtabmap::Error (DatabaseError, FormatError, ParameterError) when the run fails.
// progress(done, total) is called after each node.
Report run(const Request& request, const std::function<void(size_t, size_t)>& progress);

// Human-readable summary of a report.
std::string describe(const Report& report);

}  // namespace rtabmap::tools::exporter
