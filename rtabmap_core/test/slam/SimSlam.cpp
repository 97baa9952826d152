#include "SimSlam.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <vector>

#include "common/ToolRun.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/eval/TrajectoryError.h"

namespace rtabmap::test {

namespace {

// Datasets of the same scenario made by an earlier simulator (another key): no test of this build
// reads them. Best effort: a folder another process is still writing is its own temporary one.
void removeOtherSimulators(const std::filesystem::path& cache, const std::string& prefix,
                           const std::filesystem::path& keep) {
  std::error_code ec;
  std::vector<std::filesystem::path> stale;
  for (const auto& entry : std::filesystem::directory_iterator(cache, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) == 0 && entry.path() != keep) stale.push_back(entry.path());
  }
  for (const auto& path : stale) std::filesystem::remove_all(path, ec);
}

}  // namespace

std::string simDataset(const std::string& scenario, std::string* why) {
  // The simulator is deterministic (same options, same bytes): a dataset is made once per build
  // tree and simulator (RTABMAP_CORE_SIM_KEY, a hash of its sources, see CMakeLists.txt) and
  // shared by the tests, which ctest runs as separate processes, maybe at once. Each writer works
  // in its own folder and renames it into place; the first rename wins.
  const std::string options = "--rate 2 --width 320 --height 240 --no-stereo --no-urg";
  const std::filesystem::path cache = std::filesystem::path(RTABMAP_CORE_BINARY_DIR) / "test_data";
  const std::string prefix = "sim_" + scenario + "_r2_320_";
  const std::filesystem::path final = cache / (prefix + RTABMAP_CORE_SIM_KEY);
  if (std::filesystem::exists(final / "info.yaml") || std::filesystem::exists(final / "session1" / "info.yaml")) {
    return final.string();
  }
  std::filesystem::create_directories(cache);
  removeOtherSimulators(cache, prefix, final);
  TempDir work("rtabmap_slam_sim");
  const std::string out = work.file(scenario);
  const ToolRun r = runTool("sim", "--scenario " + scenario + " --output " + out + " " + options + " --json", work);
  if (r.exitCode != 0) {
    if (why) *why = "rtabmap-sim failed: " + r.stderrText;
    return "";
  }
  std::error_code ec;
  std::filesystem::rename(out, final, ec);
  if (ec && !std::filesystem::exists(final)) {
    // Another file system: copy instead.
    std::filesystem::copy(out, final, std::filesystem::copy_options::recursive, ec);
    if (ec) {
      if (why) *why = "cannot keep the dataset in " + final.string() + ": " + ec.message();
      return "";
    }
  }
  return final.string();
}

ParametersMap simSlamParameters() {
  // The robot's parameters are declared once, in the repository's config/sim_robot.ini (the ROS
  // demo's, the bench's): the tests run the robot users run.
  return Parameters::readIni(std::string(RTABMAP_CORE_SOURCE_DIR) + "/../config/sim_robot.ini");
}

void runSimSlam(const std::string& folder, const ParametersMap& parameters, const std::string& database,
                SimSlamRun& run) {
  std::unique_ptr<DatasetReader> reader = openDatasetReader("sim", folder);
  Rtabmap slam;
  slam.init(parameters, database);
  DatasetRecord record;
  while (reader->next(record)) {
    if (record.kind != DatasetRecord::Kind::kFrame) continue;
    const SensorData& data = record.data;
    if (!slam.process(data)) {
      // A frame kept as an intermediate node (Rtabmap/CreateIntermediateNodes).
      const int newest = slam.newestNodeId();
      if (newest > 0 && newest != slam.lastNodeId() && !run.odometry.count(newest)) {
        run.odometry[newest] = data.odomPose();
        if (!data.groundTruth().isNull()) run.groundTruth[newest] = data.groundTruth();
        run.intermediate.insert(newest);
      }
      continue;
    }
    const int id = slam.statistics().refImageId;
    if (id <= 0) continue;
    run.odometry[id] = data.odomPose();
    if (!data.groundTruth().isNull()) run.groundTruth[id] = data.groundTruth();
    const auto& values = slam.statistics().data();
    const auto gt = values.find("Gt/Translational_rmse/m");
    run.lastGroundTruthRmse = gt == values.end() ? -1.0 : gt->second;
  }
  run.optimized = slam.optimizedPoses();
  run.links = slam.allLinks();
  run.lastMapId = slam.mapId();
  const SlamSummary s = slam.summary();
  run.summary.nodesAdded += s.nodesAdded;
  run.summary.intermediateNodes += s.intermediateNodes;
  run.summary.loopClosures += s.loopClosures;
  run.summary.proximityLinks += s.proximityLinks;
  run.summary.timeLinks += s.timeLinks;
  run.summary.skippedMapStart += s.skippedMapStart;
  run.summary.rejectedLinks += s.rejectedLinks;
  run.summary.localizations += s.localizations;
  run.summary.mapsStarted += s.mapsStarted;
  run.summary.remerges += s.remerges;
  run.refused += s.refused;
  slam.close();
}

double nodeAte(const std::map<int, Transform>& poses, const std::map<int, Transform>& groundTruth) {
  Trajectory gt, est;
  for (const auto& [id, pose] : poses) {
    auto g = groundTruth.find(id);
    if (g == groundTruth.end()) continue;
    gt.add(static_cast<double>(id), g->second);
    est.add(static_cast<double>(id), pose);
  }
  AteOptions o;
  o.maxTimeDifference = 0.1;
  return computeAte(gt, est, o).translation.rmse;
}

namespace {
// Calls visit(link, truth, error) for each link of `types` whose two ends have
// ground truth; error is the norm of truth^-1 * link. Returns how many it visited.
template <typename Visit>
int forEachLinkError(const std::multimap<int, Link>& links, const std::map<int, Transform>& groundTruth,
                     const std::set<Link::Type>& types, Visit visit) {
  int n = 0;
  for (const auto& [from, link] : links) {
    if (!types.count(link.type())) continue;
    auto a = groundTruth.find(link.from());
    auto b = groundTruth.find(link.to());
    if (a == groundTruth.end() || b == groundTruth.end()) continue;
    const Transform truth = a->second.inverse() * b->second;
    visit(link, truth, (truth.inverse() * link.transform()).getNorm());
    ++n;
  }
  return n;
}
}  // namespace

double worstLinkError(const std::multimap<int, Link>& links, const std::map<int, Transform>& groundTruth,
                      const std::set<Link::Type>& types, int* count, std::string* which) {
  double worst = 0.0;
  const int n = forEachLinkError(links, groundTruth, types, [&](const Link& link, const Transform& truth, double e) {
    if (e > worst && which) {
      *which = link.typeName() + " " + std::to_string(link.from()) + "->" + std::to_string(link.to()) + ": " +
               link.transform().prettyPrint() + ", truth " + truth.prettyPrint();
    }
    worst = std::max(worst, e);
  });
  if (count) *count = n;
  return worst;
}

double meanLinkError(const std::multimap<int, Link>& links, const std::map<int, Transform>& groundTruth,
                     const std::set<Link::Type>& types, int* count) {
  double sum = 0.0;
  const int n = forEachLinkError(links, groundTruth, types, [&](const Link&, const Transform&, double e) { sum += e; });
  if (count) *count = n;
  return n > 0 ? sum / n : 0.0;
}

}  // namespace rtabmap::test
