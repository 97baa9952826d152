#include "Bench.h"

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <random>

#include "Conversion.h"
#include "common/Json.h"

namespace fs = std::filesystem;

namespace rtabmap_bag {

namespace {

struct BenchDataset {
  const char* name;
  const char* format;
  const char* relative;  // in the data folder
};

// ACES is the reference (7,374 scans); 7-Scenes and EuRoC exercise the image paths,
// KITTI the 3D clouds.
constexpr BenchDataset kDatasets[] = {
    {"aces", "carmen", "radish/aces.clf.bz2"},
    {"intel", "carmen", "radish/intel.clf.bz2"},
    {"7scenes", "7scenes", "rgbd_7scenes"},
    {"euroc", "euroc", "euroc_v1_01_micro"},
    {"kitti", "kitti", "kitti00_velodyne"},
};

}  // namespace

int runBench(const std::vector<std::string>& dataDirs, const std::string& tempDir) {
  const fs::path work = fs::path(tempDir) / ("rtabmap_bag_bench_" + std::to_string(std::random_device{}()));
  fs::create_directories(work);
  nlohmann::json results = nlohmann::json::array();
  nlohmann::json skipped = nlohmann::json::array();
  for (const BenchDataset& d : kDatasets) {
    fs::path input;
    for (const std::string& dir : dataDirs) {
      if (!dir.empty() && fs::exists(fs::path(dir) / d.relative)) {
        input = fs::path(dir) / d.relative;
        break;
      }
    }
    if (input.empty()) {
      std::cout << d.name << ": skipped (no " << d.relative << " in the data folders)\n";
      skipped.push_back(d.name);
      continue;
    }
    ConversionRequest request;
    request.format = d.format;
    request.input = input.string();
    request.output = (work / (std::string(d.name) + ".bag")).string();
    const ConversionResult r = convert(request, false, false);
    char line[256];
    const double mib = r.summary.bytes / 1048576.0;
    std::snprintf(line, sizeof(line),
                  "%s (%s): %llu messages (%llu frames) in %.2f s = %.0f messages/s, %.1f frames/s, %.1f MiB/s\n",
                  d.name, d.format, (unsigned long long)r.summary.messages, (unsigned long long)r.summary.frames,
                  r.wallSeconds, r.messagesPerSecond(), r.wallSeconds > 0 ? r.summary.frames / r.wallSeconds : 0.0,
                  r.wallSeconds > 0 ? mib / r.wallSeconds : 0.0);
    std::cout << line << std::flush;
    nlohmann::json j = toJson(request, r);
    j["dataset"] = d.name;
    j["frames_per_second"] = r.wallSeconds > 0 ? r.summary.frames / r.wallSeconds : 0.0;
    results.push_back(j);
    std::error_code ec;
    fs::remove(request.output, ec);
  }
  std::error_code ec;
  fs::remove_all(work, ec);
  rtabmap::tools::printJsonLine(
      {{"bench", "rtabmap-bag"}, {"data", dataDirs}, {"results", results}, {"skipped", skipped}});
  return results.empty() ? 1 : 0;
}

}  // namespace rtabmap_bag
