// rtabmap-eval: scores SLAM and loop-closure results against ground truth (ATE, RPE, KITTI
// odometry error, Kuemmerle relations, deviation from a reference path, loop-closure
// precision-recall), and exports a dataset's odometry or ground truth as a trajectory file.
#include <cstring>
#include <iostream>
#include <string>

#include "common/CommandLine.h"
#include "eval/Commands.h"

namespace {

void printUsage(std::ostream& out) {
  out << "Usage: rtabmap-eval COMMAND [options]\n\n"
         "Scores trajectories and loop closures against ground truth. Every command prints a\n"
         "human-readable summary and, with --json, one JSON object as the last line of stdout.\n\n"
         "Commands:\n";
  for (const auto& c : rtabmap::tools::eval::subCommands()) {
    std::string name = c.name;
    name.resize(12, ' ');
    out << "  " << name << c.summary << "\n";
  }
  out << "\nTrajectory files: tum (`t x y z qx qy qz qw`), kitti (3x4 row-major per line, row n\n"
         "has stamp n), g2o (VERTEX_SE2 / VERTEX_SE3:QUAT, the vertex id as stamp), euroc\n"
         "(state_groundtruth_estimate0/data.csv); detected from the content unless given.\n\n"
         "Run 'rtabmap-eval COMMAND --help' for the options of a command.\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "rtabmap-eval: error: missing command\n";
    printUsage(std::cerr);
    return rtabmap::tools::kExitUsage;
  }
  const std::string command = argv[1];
  if (command == "--help" || command == "-h" || command == "help") {
    printUsage(std::cout);
    return rtabmap::tools::kExitSuccess;
  }
  for (const auto& c : rtabmap::tools::eval::subCommands()) {
    if (command == c.name) return c.run(argc - 1, argv + 1);
  }
  std::cerr << "rtabmap-eval: error: unknown command '" << command << "'\n";
  printUsage(std::cerr);
  return rtabmap::tools::kExitUsage;
}
