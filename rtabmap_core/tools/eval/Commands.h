#pragma once
// The sub-commands of rtabmap-eval. Each takes the arguments after "rtabmap-eval" (args[0] is
// the sub-command's name) and returns the tool's exit code.
#include <string>
#include <vector>

namespace rtabmap::tools::eval {

struct SubCommand {
  const char* name;
  const char* summary;
  int (*run)(int argc, char** argv);
};

// ate, rpe, kitti, relations, path, pr, trajectory.
const std::vector<SubCommand>& subCommands();

int runAte(int argc, char** argv);
int runRpe(int argc, char** argv);
int runKitti(int argc, char** argv);
int runRelations(int argc, char** argv);
int runPr(int argc, char** argv);
int runTrajectory(int argc, char** argv);
int runPath(int argc, char** argv);

}  // namespace rtabmap::tools::eval
