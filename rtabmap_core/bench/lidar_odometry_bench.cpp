// bench-lidar_odometry_bench: lidar odometry and ICP on real data.
//
//  - 2D: scan-to-map (S2M) and scan-to-scan (S2S) odometry over the whole Radish ACES log
//    (7,374 SICK scans, 180 beams), each with the wheel odometry increment as motion guess and
//    with the constant-velocity model alone. Accuracy is the relation error of Kuemmerle et al.
//    2009 against aces.relations (odometry alone, no loop closure), next to the raw wheel
//    odometry's own (a lost scan is scored at the last pose found); time is the CPU time of process() per scan, on the calling thread (on a
//    machine shared with other jobs, wall time also counts waiting for a core).
//  - 3D: ICP between KITTI 00 Velodyne scans 94->95 and 198->199 from the identity, against the
//    ground-truth relative poses, point-to-plane and point-to-point.
//  - The IMU's gyroscope as the rotation of S2M's motion guess (Odometry::addImu, rtabmap-dataset
//    --imu), where it matters: the simulator's `loop` (2D lasers, its IMU with noise and bias) at
//    3 Hz, where turns between scans outrun the constant-velocity model, and at 10 Hz; ATE and
//    lost scans with and without the IMU (tools beside the bench: rtabmap-sim, rtabmap-dataset).
// Human-readable lines first, then one JSON line with every figure.
//
// Usage: bench-lidar_odometry_bench [--data DIR] [--frames N]
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "RunTool.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/eval/RelationError.h"
#include "rtabmap_core/eval/TrajectoryError.h"  // percentile
#include "rtabmap_core/odometry/OdometryS2M.h"
#include "rtabmap_core/odometry/OdometryS2S.h"
#include "rtabmap_core/registration/IcpRegistration.h"

namespace fs = std::filesystem;
using namespace rtabmap;
using Json = nlohmann::json;

namespace {

// Velodyne -> cam0 of KITTI odometry sequence 00: the Tr line of that sequence's calib.txt
// (the same for sequences 00-02 and 13-21). The KITTI poses are cam0 poses, so comparing an ICP
// of two Velodyne scans with them needs this exact mounting; the shared data has no calib.txt.
// These are the numbers of the Tr line of sequences 00-02 of the KITTI odometry development
// kit's calib.txt, identical in every public copy of that file we checked.
// The eval reader's fallback (0.27 m behind, 0.08 m above cam0, axes parallel) ignores the
// ~0.5 degree tilt of the real mounting.
constexpr const char* kKitti00Tr =
    "Tr: 4.276802385584e-04 -9.999672484946e-01 -8.084491683471e-03 -1.198459927713e-02 "
    "-7.210626507497e-03 8.081198471645e-03 -9.999413164504e-01 -5.403984729748e-02 "
    "9.999738645903e-01 4.859485810390e-04 -7.206933692422e-03 -2.921968648686e-01\n";

// Mean translational relation error of the raw ACES wheel odometry given in the data README.
constexpr double kAcesWheelReadme = 0.549;

struct Settings {
  std::string data;
  int frames = 0;  // 0 = the whole log
};

double cpuMs() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

std::string findData(const Settings& s, const std::string& entry) {
  if (!s.data.empty()) return s.data;
  if (const char* env = std::getenv("RTABMAP_DATA_DIR"); env && *env) return env;
  std::vector<fs::path> starts;
  std::error_code ec;
  starts.push_back(fs::current_path(ec));
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) starts.push_back(exe.parent_path());
  const fs::path source = fs::canonical(fs::path(__FILE__), ec);
  if (!ec) starts.push_back(source.parent_path());
  for (fs::path dir : starts) {
    for (; !dir.empty(); dir = dir.parent_path()) {
      for (const fs::path& c : {dir / ".." / "shared" / "data", dir / "shared" / "data", dir / "data"}) {
        if (fs::exists(c / entry, ec)) return fs::weakly_canonical(c, ec).string();
      }
      if (dir == dir.root_path()) break;
    }
  }
  return "";
}

// ---- ACES -----------------------------------------------------------------------------------

// The 2D lidar settings of these runs (the same for S2M and S2S). The ACES scans are 1-degree
// SICK scans of corridors and offices:
//  - point-to-plane with normals from 5 neighbours along the scan: walls, not points, are what
//    two scans share, as beams never hit the same spot twice;
//  - 5 cm voxels and 10 cm correspondences (twice the voxel): at the guess, the scan is within
//    a few centimetres of the map; farther pairs are mostly wrong ones (people, glass);
//  - 10 iterations, stopping when a step moves less than 1 mm / 0.06 deg;
//  - Icp/PointToPlaneMinComplexity 0.1: ACES is long corridors whose doors and pillars barely
//    pin the position along them (complexity 0.05-0.15); below 0.1 the travel along the
//    corridor comes from the guess;
//  - a map of 5,000 points (OdomF2M/ScanMaxSize): about one corridor.
// Without the wheel guess, a frame with no prediction at all (after a lost frame) that ICP
// cannot align is retried from a coarse alignment (see ScanOdometryCommon.h).
ParametersMap acesParameters(bool scanToMap) {
  return {{Parameters::kRegStrategy(), "1"},
          {Parameters::kOdomStrategy(), scanToMap ? "0" : "1"},
          {Parameters::kIcpPointToPlane(), "true"},
          {Parameters::kIcpPointToPlaneK(), "5"},
          {Parameters::kIcpVoxelSize(), "0.05"},
          {Parameters::kIcpMaxCorrespondenceDistance(), "0.1"},
          {Parameters::kIcpIterations(), "10"},
          {Parameters::kIcpEpsilon(), "0.001"},
          {Parameters::kIcpPointToPlaneMinComplexity(), "0.1"},
          {Parameters::kOdomF2MScanMaxSize(), "5000"}};
}

struct AcesRun {
  std::string name;
  RelationResult relations;
  std::vector<double> ms;
  int lost = 0;
  int keyFrames = 0;
  int frames = 0;

  Json json() const {
    return {{"frames", frames},
            {"lost", lost},
            {"key_frames", keyFrames},
            {"relations_used", relations.used},
            {"trans_mean_m", relations.translation.mean},
            {"trans_std_m", relations.translation.std},
            {"rot_mean_deg", relations.rotation.mean},
            {"rot_std_deg", relations.rotation.std},
            {"ms_median", percentile(ms, 0.5)},
            {"ms_p90", percentile(ms, 0.9)},
            {"ms_max", ms.empty() ? 0.0 : *std::max_element(ms.begin(), ms.end())}};
  }
};

AcesRun runAces(const std::string& name, bool scanToMap, bool wheelGuess, const std::vector<DatasetRecord>& frames,
                const std::vector<Relation>& relations) {
  AcesRun run;
  run.name = name;
  const ParametersMap p = acesParameters(scanToMap);
  std::unique_ptr<Odometry> odometry;
  if (scanToMap) {
    odometry = std::make_unique<OdometryS2M>(p);
  } else {
    odometry = std::make_unique<OdometryS2S>(p);
  }
  Trajectory estimate;
  Transform previousWheel;
  for (const DatasetRecord& record : frames) {
    SensorData data = record.data;
    const Transform wheel = data.odomPose();
    const Transform guess = wheelGuess && !previousWheel.isNull() ? previousWheel.inverse() * wheel : Transform();
    previousWheel = wheel;
    OdometryInfo info;
    const double t0 = cpuMs();
    const Transform pose = odometry->process(data, guess, &info);
    run.ms.push_back(cpuMs() - t0);
    run.keyFrames += info.keyFrameAdded;
    ++run.frames;
    // A lost frame keeps the last pose (what the odometry still believes), so every relation
    // is scored: skipping the relations of lost frames would hide what losing them cost.
    if (pose.isNull()) ++run.lost;
    estimate.add(record.stamp, pose.isNull() ? odometry->getPose() : pose);
  }
  run.relations = computeRelationError(estimate, relations);
  return run;
}

void printRelation(const std::string& name, const RelationResult& r) {
  std::printf("  %-30s trans %.3f +- %.3f m   rot %.2f +- %.2f deg   (%zu relations)\n", name.c_str(),
              r.translation.mean, r.translation.std, r.rotation.mean, r.rotation.std, r.used);
}

Json benchAces(const std::string& dir, const Settings& s) {
  DatasetReaderOptions options;
  options.odometry = false;  // the FLASER frames carry the wheel odometry of their instant
  options.imu = false;
  options.maxFrames = s.frames;
  auto reader = openDatasetReader("carmen", dir + "/aces.clf.bz2", options);
  std::vector<DatasetRecord> frames;
  DatasetRecord record;
  while (reader->next(record)) {
    if (record.kind == DatasetRecord::Kind::kFrame) frames.push_back(record);
  }
  std::vector<Relation> relations;
  for (const Relation& r : readRelations(dir + "/aces.relations")) {
    if (r.stamp2 <= frames.back().stamp + 1e-3) relations.push_back(r);
  }
  Trajectory wheel;
  for (const DatasetRecord& f : frames) wheel.add(f.stamp, f.data.odomPose());
  const RelationResult wheelError = computeRelationError(wheel, relations);

  std::printf("ACES (Radish): %zu scans, %zu relations (Kuemmerle et al. 2009), odometry only\n", frames.size(),
              relations.size());
  printRelation("wheel odometry (raw)", wheelError);
  std::printf("  %-30s (data README: %.3f m)\n", "", kAcesWheelReadme);

  const std::vector<std::tuple<std::string, bool, bool>> variants = {
      {"s2m_wheel_guess", true, true},
      {"s2m_constant_velocity", true, false},
      {"s2s_wheel_guess", false, true},
      {"s2s_constant_velocity", false, false}};
  Json out = {{"scans", frames.size()},
              {"relations", relations.size()},
              {"wheel_odometry", {{"trans_mean_m", wheelError.translation.mean},
                                  {"trans_std_m", wheelError.translation.std},
                                  {"rot_mean_deg", wheelError.rotation.mean},
                                  {"rot_std_deg", wheelError.rotation.std}}}};
  for (const auto& [name, scanToMap, guess] : variants) {
    const AcesRun run = runAces(name, scanToMap, guess, frames, relations);
    printRelation(name, run.relations);
    std::printf("  %-30s CPU ms per scan: median %.2f, p90 %.2f, max %.2f; %d lost, %d key frames\n", "",
                percentile(run.ms, 0.5), percentile(run.ms, 0.9),
                run.ms.empty() ? 0.0 : *std::max_element(run.ms.begin(), run.ms.end()), run.lost, run.keyFrames);
    out[name] = run.json();
  }
  std::printf(
      "  note: the translations of aces.relations are the wheel odometry increments plus a correction\n"
      "        on a 5 cm grid (38%% of them with none): over short relations the wheels win translation\n"
      "        by construction; the long ones (revisits) measure the drift.\n");
  return out;
}

// ---- KITTI ----------------------------------------------------------------------------------

// 3D ICP from the identity (the car moves ~0.5 m per scan at 10 Hz): 20 cm voxels (~25,000 of
// the ~120,000 points), correspondences up to 1 m, normals from 10 neighbours.
ParametersMap kittiParameters(bool pointToPlane) {
  return {{Parameters::kIcpPointToPlane(), pointToPlane ? "true" : "false"},
          {Parameters::kIcpPointToPlaneK(), "10"},
          {Parameters::kIcpVoxelSize(), "0.2"},
          {Parameters::kIcpMaxCorrespondenceDistance(), "1.0"},
          {Parameters::kIcpIterations(), "30"},
          {Parameters::kIcpEpsilon(), "0.0001"},
          {Parameters::kIcpMaxTranslation(), "2"}};
}

Json benchKitti(const std::string& dir) {
  const fs::path calib = fs::temp_directory_path() / ("rtabmap_kitti00_calib_" + std::to_string(getpid()) + ".txt");
  std::ofstream(calib) << kKitti00Tr;
  DatasetReaderOptions options;
  options.calibrationPath = calib.string();
  options.images = false;
  auto reader = openDatasetReader("kitti", dir, options);
  std::map<int, SensorData> frames;  // by KITTI frame number
  DatasetRecord record;
  while (reader->next(record)) {
    if (record.kind == DatasetRecord::Kind::kFrame) frames[record.data.id() - 1] = record.data;
  }
  std::error_code ec;
  fs::remove(calib, ec);

  std::printf("KITTI 00 Velodyne: ICP from the identity against the ground truth (exact Tr of sequence 00)\n");
  Json out = Json::object();
  for (const auto& [a, b] : {std::pair<int, int>{94, 95}, std::pair<int, int>{198, 199}}) {
    const std::string name = std::to_string(a) + "_" + std::to_string(b);
    if (!frames.count(a) || !frames.count(b) || frames[a].groundTruth().isNull() || frames[b].groundTruth().isNull()) {
      std::printf("  %d->%d: skipped (scan or ground truth missing)\n", a, b);
      continue;
    }
    const Transform truth = frames[a].groundTruth().inverse() * frames[b].groundTruth();
    Json pair = {{"truth_m", truth.getNorm()}, {"truth_deg", truth.getAngle() * 180.0 / M_PI}};
    for (bool plane : {true, false}) {
      RegistrationInfo info;
      const double t0 = cpuMs();
      const Transform t = IcpRegistration(kittiParameters(plane))
                              .computeTransform(frames[a].laserScanRaw(), frames[b].laserScanRaw(),
                                                Transform::Identity(), &info);
      const double ms = cpuMs() - t0;
      const char* metric = plane ? "point_to_plane" : "point_to_point";
      if (t.isNull()) {
        std::printf("  %d->%d %-15s rejected: %s\n", a, b, metric, info.rejectedMsg.c_str());
        pair[metric] = {{"rejected", info.rejectedMsg}};
        continue;
      }
      const Transform error = truth.inverse() * t;
      std::printf("  %d->%d %-15s error %.3f m %.3f deg (motion %.3f m %.2f deg), %.0f ms, %d pairs, ratio %.2f\n", a, b,
                  metric, error.getNorm(), error.getAngle() * 180.0 / M_PI, truth.getNorm(),
                  truth.getAngle() * 180.0 / M_PI, ms, info.icpCorrespondences, info.icpInliersRatio);
      pair[metric] = {{"trans_err_m", error.getNorm()},
                      {"rot_err_deg", error.getAngle() * 180.0 / M_PI},
                      {"ms", ms},
                      {"correspondences", info.icpCorrespondences},
                      {"ratio", info.icpInliersRatio}};
    }
    out[name] = pair;
  }
  return out;
}

// ---- IMU guess on the simulator ----------------------------------------------------------------

// A planar robot's 2D laser odometry (the README's IMU figures): 5 cm voxels, point-to-plane,
// 0.3 m correspondences.
constexpr const char* kSimLaser =
    "--Reg/Force3DoF true --Icp/VoxelSize 0.05 --Icp/PointToPlane true --Icp/MaxCorrespondenceDistance 0.3 ";

Json benchImuGuess(const fs::path& work) {
  std::error_code ec;
  const fs::path tools = fs::read_symlink("/proc/self/exe", ec).parent_path();
  if (ec || !fs::exists(tools / "rtabmap-sim") || !fs::exists(tools / "rtabmap-dataset")) {
    std::printf("IMU guess: skipped (rtabmap-sim or rtabmap-dataset not beside the bench)\n");
    return Json();
  }
  Json out;
  for (const int rate : {3, 10}) {
    const fs::path data = work / ("loop_" + std::to_string(rate) + "hz");
    if (!fs::exists(data / "groundtruth.txt")) {
      bench::runToolJson(tools.string(), "rtabmap-sim", "--scenario loop --no-rgbd --overwrite --rate " +
                                                            std::to_string(rate) + " --output " + data.string());
    }
    Json row;
    for (const bool imu : {false, true}) {
      const fs::path odom = work / ("odom_" + std::to_string(rate) + (imu ? "hz_imu" : "hz"));
      const Json r = bench::runToolJson(tools.string(), "rtabmap-dataset",
                                        std::string("--format sim --odom s2m ") + kSimLaser + (imu ? "--imu " : "") +
                                            "--output " + odom.string() + " " + data.string());
      std::printf("IMU guess, sim loop at %d Hz, S2M %s: ATE %.3f m, %d of %d scans lost, %d guesses from the IMU\n",
                  rate, imu ? "with the gyroscope" : "constant velocity", r.value("odom_ate_rmse", -1.0),
                  r.value("lost", -1), r.value("frames", -1), r.value("imu_guesses", 0));
      row[imu ? "imu" : "constant_velocity"] = {{"ate_rmse", r.value("odom_ate_rmse", -1.0)},
                                                {"lost", r.value("lost", -1)},
                                                {"frames", r.value("frames", -1)},
                                                {"imu_guesses", r.value("imu_guesses", 0)}};
    }
    out[std::to_string(rate) + "hz"] = row;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  Settings s;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--data" && i + 1 < argc) {
      s.data = argv[++i];
    } else if (a == "--frames" && i + 1 < argc) {
      s.frames = std::atoi(argv[++i]);
    } else {
      std::cerr << "usage: bench-lidar_odometry_bench [--data DIR] [--frames N]\n";
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  Json out = {{"bench", "lidar_odometry"}};
  try {
    const std::string radishRoot = findData(s, "radish/aces.relations");
    if (!radishRoot.empty()) {
      out["aces"] = benchAces(radishRoot + "/radish", s);
    } else {
      std::printf("ACES: skipped (../shared/data/radish absent; set RTABMAP_DATA_DIR or --data)\n");
    }
    const fs::path work = fs::read_symlink("/proc/self/exe").parent_path() / ".." / "bench_output" / "imu_guess";
    fs::create_directories(work);
    out["imu_guess"] = benchImuGuess(work);
    const std::string kittiRoot = findData(s, "kitti00_velodyne/000094.bin");
    if (!kittiRoot.empty()) {
      out["kitti00"] = benchKitti(kittiRoot + "/kitti00_velodyne");
    } else {
      std::printf("KITTI: skipped (../shared/data/kitti00_velodyne absent)\n");
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "bench-lidar_odometry_bench: %s\n", e.what());
    out["error"] = e.what();
    std::cout << out.dump() << std::endl;
    return 1;
  }
  std::cout << out.dump() << std::endl;
  return 0;
}
