#pragma once
// The simulator's scenarios: a building (BuildingSpec) and the robot's route(s) through it.
//
//   loop          a block of rooms inside a ring corridor, with rooms around it. The robot
//                 drives the ring once (visiting two rooms), then goes on along the first
//                 third of it again: loop closures on a revisit in the same direction.
//   reverse       the same building; after one lap the robot turns round and drives the lap
//                 the other way. The camera sees the other side of every place, so only
//                 laser proximity can close the loop.
//   corridor      a long corridor with plain walls, a plain ceiling and few decals: driven to
//                 the far end and back. Visual odometry's hard case.
//   multisession  two blocks; three runs, each starting somewhere else with odometry reset to
//                 zero, each overlapping an earlier one (run 2 shares the middle corridor with
//                 run 1, run 3 crosses the paths of both). Written as session1..3 subfolders.
//   long          a large building (4 x 3 blocks, about 100 rooms) and a random tour of laps and
//                 room visits lasting at least two hours: many revisits, for memory management.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rtabmap_core/sim/Building.h"
#include "rtabmap_core/sim/Motion.h"

namespace rtabmap::sim {

struct ScenarioSpec {
  std::string name;
  std::string description;
  BuildingSpec building;
  double defaultRate = 10.0;      // frames per second
  double targetDuration = 0.0;    // seconds the route lasts at least (0: as the route gives)
  int sessions = 1;
};

struct SessionRoute {
  std::string name;                        // "session1", ... ("" for single-session scenarios)
  std::vector<Eigen::Vector2d> waypoints;  // through the building's navigation graph
  std::vector<int> nodes;                  // the navigation nodes visited, in order
};

std::vector<std::string> scenarioNames();
// Throws std::invalid_argument naming the known scenarios.
ScenarioSpec scenarioSpec(const std::string& name);
// The routes of a scenario in its building. `targetDuration` (s, > 0) overrides the spec's for
// scenarios whose route length is open (long); the others have fixed routes.
std::vector<SessionRoute> planRoutes(const ScenarioSpec& spec, const Building& building, uint64_t seed,
                                     const MotionLimits& limits, double targetDuration = 0.0);

}  // namespace rtabmap::sim
