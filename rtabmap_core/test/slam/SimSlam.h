#pragma once
// Test helpers of the SLAM tests: simulator datasets made once per test binary, and SLAM runs
// over them that keep, per node, its optimised pose and its ground truth.
#include <map>
#include <set>
#include <string>

#include "common/TestData.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/params/Parameters.h"
#include "rtabmap_core/slam/Rtabmap.h"

namespace rtabmap::test {

// The folder of a simulated scenario (small images, 2 Hz, RGB-D + UTM laser), generated with
// rtabmap-sim on first use and kept in the build tree for the other tests until the simulator's
// sources change. "" (and *why) if the simulator failed.
std::string simDataset(const std::string& scenario, std::string* why);
// `var` = simDataset(scenario), or the test fails saying why.
#define REQUIRE_SIM(var, scenario)                                 \
  std::string why_##var;                                           \
  const std::string var = test::simDataset(scenario, &why_##var); \
  ASSERT_FALSE(var.empty()) << why_##var;

struct SimSlamRun {
  SlamSummary summary;
  std::map<int, Transform> optimized;    // final optimised poses (current referential)
  std::map<int, Transform> odometry;     // node id -> odometry pose at creation
  std::map<int, Transform> groundTruth;  // node id -> ground truth
  std::multimap<int, Link> links;        // every link of the map at the end
  std::set<int> intermediate;            // the intermediate nodes (Rtabmap/CreateIntermediateNodes)
  int lastMapId = 0;
  int refused = 0;
  double lastGroundTruthRmse = -1.0;  // the last update's Gt/Translational_rmse/m (-1: none)
};

// Runs Rtabmap over a sim dataset folder with its wheel odometry; appends to `run` (several
// sessions on one database keep one SimSlamRun). Closes the map at the end.
void runSimSlam(const std::string& folder, const ParametersMap& parameters, const std::string& database,
                SimSlamRun& run);

// Parameters of the sim tests: the robot of the simulator as config/sim_robot.ini declares it
// (RGB-D + laser, visual loop closure refined by point-to-plane ICP, proximity by scans, 1 Hz,
// a 3 m bound on loop-closure corrections: the building's corridors and rooms repeat, so one
// 4 or 8 m further on can look the same).
ParametersMap simSlamParameters();

// ATE RMSE (m) of `poses` against the ground truth of the same nodes, one rigid alignment.
double nodeAte(const std::map<int, Transform>& poses, const std::map<int, Transform>& groundTruth);

// Largest error (m) of the links of these types against the ground truth of their ends.
double worstLinkError(const std::multimap<int, Link>& links, const std::map<int, Transform>& groundTruth,
                      const std::set<Link::Type>& types, int* count = nullptr, std::string* which = nullptr);
// Mean error (m) of the links of these types against the ground truth of their ends (0: none).
double meanLinkError(const std::multimap<int, Link>& links, const std::map<int, Transform>& groundTruth,
                     const std::set<Link::Type>& types, int* count = nullptr);

}  // namespace rtabmap::test
