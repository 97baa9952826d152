#pragma once
// rtabmap-sim's command line: declaration (with the --help text that documents the output
// folder) and its translation into the simulator's configuration.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "common/CommandLine.h"
#include "rtabmap_core/sim/Scenarios.h"
#include "rtabmap_core/sim/Simulator.h"

namespace rtabmap::tools::sim {

struct SimRun {
  std::string scenario;
  uint64_t seed = 0;
  std::string output;
  std::string bag;            // "" = no bag
  bool overwrite = false;
  bool depth32 = false;
  int threads = 2;
  double duration = 0.0;      // --duration (0: the scenario's)
  rtabmap::sim::ScenarioSpec spec;
  rtabmap::sim::SimulationConfig config;
  // Every option that shapes the output, as (name, value) for info.yaml (not the output path,
  // the bag, the thread count or --json: they change no byte of the dataset).
  std::vector<std::pair<std::string, std::string>> recorded;
};

void declareOptions(CommandLine& cli);
// Reads and checks the options (UsageError on a bad value).
SimRun readOptions(const CommandLine& cli);

}  // namespace rtabmap::tools::sim
