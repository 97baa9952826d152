#pragma once
// --bag: rtabmap-sim does not write rosbags itself; the converter rtabmap-bag (a ROS tool built
// beside it) does, from the folder rtabmap-sim has just written. It is looked for next to this
// executable (as invoked, then with symlinks resolved: build/bin holds links into the catkin
// devel space), then on PATH.
#include <string>

namespace rtabmap::tools::sim {

// The rtabmap-bag executable to use, or "" if there is none. argv0: how we were invoked.
std::string findBagConverter(const std::string& argv0);
// Runs `converter --format sim datasetDir bagPath`; its stdout goes to our stderr when
// quietStdout (so a --json line stays the last stdout line). Throws rtabmap::Error naming the
// command if it cannot start or does not exit with 0.
void runBagConverter(const std::string& converter, const std::string& datasetDir, const std::string& bagPath, bool quietStdout);

}  // namespace rtabmap::tools::sim
