#pragma once
// rtabmap-bag --bench: converter throughput (messages per second, reading + writing) on the
// real datasets found in data folders laid out as ../shared/data: the ACES and Intel CARMEN
// logs (radish/, also shipped in the repository's data/), the 7-Scenes RGB-D frames, the EuRoC
// stereo sample and the KITTI Velodyne scans. Absent datasets are skipped and said so. One line per dataset, then
// one JSON line (the last line of stdout).
#include <string>
#include <vector>

namespace rtabmap_bag {

// dataDirs are searched in order for each dataset. Returns the exit code: 0, or 1 when no
// dataset was found at all.
int runBench(const std::vector<std::string>& dataDirs, const std::string& tempDir);

}  // namespace rtabmap_bag
