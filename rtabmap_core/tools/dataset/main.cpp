// rtabmap-dataset: runs odometry (and, with the SLAM issue, mapping) over a dataset read by the
// eval readers, writes DIR/odom.tum, and scores it against the dataset's ground truth.
#include <opencv2/core.hpp>

#include <cstring>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "common/CommandLine.h"
#include "common/Json.h"
#include "common/ProgressBar.h"
#include "dataset/DatasetRun.h"
#include "rtabmap_core/memory/ProcessMemory.h"

namespace {

// The form `--json PATH`: the common --json flag takes no value, so a PATH ending in
// .json right after it is taken out here (and the summary also written there).
std::vector<std::string> takeJsonPath(int argc, char** argv, std::string& jsonPath) {
  std::vector<std::string> args(argv, argv + argc);
  for (size_t i = 1; i + 1 < args.size(); ++i) {
    const std::string& next = args[i + 1];
    if (args[i] == "--json" && next.size() > 5 && next.compare(next.size() - 5, 5, ".json") == 0) {
      jsonPath = next;
      args.erase(args.begin() + static_cast<long>(i) + 1);
      break;
    }
  }
  return args;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace rtabmap;
  memory::configureAllocator();  // as the rtabmap node: a long run's allocator (issue 10)
  return tools::runTool("rtabmap-dataset", [&] {
    std::string jsonPath;
    std::vector<std::string> args = takeJsonPath(argc, argv, jsonPath);
    std::vector<char*> argp;
    for (std::string& a : args) argp.push_back(a.data());

    tools::CommandLine cli("rtabmap-dataset",
                           "Runs odometry over a dataset (RGB-D, stereo, 2D laser or 3D lidar), writes its "
                           "trajectory as DIR/odom.tum and, when the dataset has ground truth, its absolute "
                           "trajectory error (ATE, after rigid alignment). With --slam, maps it too (RTAB-Map: "
                           "loop closure, proximity detection, graph optimisation, memory management) into "
                           "DIR/rtabmap.db, with the optimised trajectory DIR/poses.tum and the occupancy grid "
                           "DIR/grid.pgm + grid.yaml (map_server) + grid.png.");
    cli.addPositional("dataset", "Dataset folder or file (as the format expects).");
    cli.addOption("format", "FORMAT",
                  "Dataset layout: 7scenes, tum, euroc, kitti, carmen, images, sim (see rtabmap-eval).");
    cli.addOption("odom", "APPROACH",
                  "f2m, f2f (visual), s2m, s2s (lidar), or wheel (the dataset's own odometry, e.g. a CARMEN "
                  "log's). Default: from Odom/Strategy and Reg/Strategy.");
    cli.addOption("output", "DIR", "Folder for odom.tum (and gt.tum when there is ground truth), and the map.");
    cli.addFlag("slam", "Map the dataset (needs --output): DIR/rtabmap.db, DIR/poses.tum, DIR/grid.*. An existing "
                        "DIR/rtabmap.db is replaced.");
    cli.addFlag("continue", "Like --slam, but add a session to an existing DIR/rtabmap.db (multi-session mapping).");
    cli.addFlag("localization", "Localise the dataset against the existing DIR/rtabmap.db without modifying it "
                                "(Mem/IncrementalMemory false); every frame's pose in the map goes to "
                                "DIR/localization.tum.");
    cli.addOption("start", "N", "Skip the first N frames.", "0");
    cli.addOption("max-frames", "N", "Stop after N frames (0 = all).", "0");
    cli.addOption("rate", "HZ", "Frame rate for layouts without stamps (0 = the layout's default).", "0");
    cli.addOption("gt", "FILE", "Ground-truth trajectory overriding the dataset's own.");
    cli.addOption("calibration", "FILE", "Camera calibration overriding the dataset's own.");
    cli.addFlag("register-depth", "7scenes: register each depth image to the colour camera (published Kinect "
                                  "calibration, colour f = 525 or --calibration's) instead of using it as recorded.");
    cli.addFlag("guess-odom", "Use the dataset's wheel odometry (motion since the previous frame) as the "
                              "odometry's motion guess instead of the constant-velocity model.");
    cli.addFlag("imu", "Give the dataset's IMU samples (EuRoC, sim) to odometry: the gyroscope's rotation between "
                       "two frames is the rotation of the motion guess.");
    cli.addOption("ate-frame", "FRAME",
                  "Frame whose trajectory ATE compares: base (the dataset's ground-truth frame) or camera "
                  "(the (left) camera optical frame, e.g. EuRoC's camera rather than its IMU).",
                  "base");
    cli.addOption("frames-csv", "FILE",
                  "Write one CSV line per frame: id, stamp, lost, features, matches, inliers, key frame, "
                  "local map size, time, position, ground-truth position, lost reason.");
    cli.addOption("updates-csv", "FILE",
                  "With --slam, write one CSV line per map update: node id, nodes in the map, Working Memory "
                  "size, update time, Map_assembling time (ms), the process's resident size (VmRSS), live heap, "
                  "heap kept free, SQLite and global grid memory, resident anonymous and file-backed memory "
                  "(MB), nodes whose grid cells were read back from the database, words in the vocabulary, "
                  "time giving freed heap back to the system (ms), memory of the locations in RAM and of the "
                  "vocabulary (MB), points in the vocabulary's index, and what the global grid's update did: its "
                  "path (0 none, 1 incremental, 2 region, 3 full), nodes moved, nodes replayed, cell updates.");
    cli.addOption("threads", "N", "OpenCV threads (0 = OpenCV's default, 1 = single core as the bench).", "0");
    cli.addNote("With --json, the last stdout line is a JSON object: frames, lost, key_frames, imu_guesses, odom_ms_median, "
                "odom_ms_mean, odom_ms_max, odom_ate_rmse (and mean, median, max) when there is ground truth; "
                "with --slam also nodes, sessions, loop_closures, proximity_links, time_proximity_links, rejected_links, "
                "slam_ms_median, slam_ms_p99, slam_ms_max, max_wm_size, realtime_factor and ate_rmse (optimised "
                "poses). `--json FILE.json` also writes it to FILE.json.");
    cli.addNote("Example (2D lidar SLAM on wheel odometry): rtabmap-dataset --format carmen --odom wheel --slam "
                "--output /tmp/intel --Reg/Strategy 1 --Reg/Force3DoF true --RGBD/ProximityPathMaxNeighbors 10 "
                "data/radish/intel.clf");
    cli.addNote("Example: rtabmap-dataset --format 7scenes --odom f2m --output /tmp/run "
                "--json ../shared/data/rgbd_7scenes");
    if (auto exitCode = cli.parse(static_cast<int>(argp.size()), argp.data())) return *exitCode;

    tools::dataset::RunOptions options;
    if (!cli.has("format")) throw tools::UsageError("--format is required");
    options.format = cli.option("format");
    options.path = cli.positional("dataset");
    if (cli.has("odom")) {
      if (cli.option("odom") == "wheel") {
        options.wheelOdometry = true;
      } else {
        options.odometry = Odometry::typeFromName(cli.option("odom"));
      }
    }
    options.slam = cli.flag("slam");
    options.continueDatabase = cli.flag("continue");
    options.localization = cli.flag("localization");
    if (options.continueDatabase && options.localization) throw tools::UsageError("--continue and --localization exclude each other");
    if ((options.slam || options.continueDatabase || options.localization) && !cli.has("output")) {
      throw tools::UsageError("--slam, --continue and --localization need --output DIR (the map is DIR/rtabmap.db)");
    }
    if (cli.has("output")) options.outputDir = cli.option("output");
    options.parameters = cli.parameters();
    options.reader.startFrame = cli.optionInt("start");
    options.reader.maxFrames = cli.optionInt("max-frames");
    options.reader.frameRate = cli.optionDouble("rate");
    if (cli.has("gt")) options.reader.groundTruthPath = cli.option("gt");
    if (cli.has("calibration")) options.reader.calibrationPath = cli.option("calibration");
    options.reader.registerDepth = cli.flag("register-depth");
    options.reader.imu = cli.flag("imu");
    options.wheelOdometryGuess = cli.flag("guess-odom");
    if (cli.has("frames-csv")) options.framesCsv = cli.option("frames-csv");
    if (cli.has("updates-csv")) options.updatesCsv = cli.option("updates-csv");
    const std::string ateFrame = cli.option("ate-frame");
    if (ateFrame != "base" && ateFrame != "camera") throw tools::UsageError("--ate-frame must be base or camera");
    options.ateInCameraFrame = ateFrame == "camera";
    if (options.reader.startFrame < 0 || options.reader.maxFrames < 0) {
      throw tools::UsageError("--start and --max-frames must not be negative");
    }
    const int threads = cli.optionInt("threads");
    if (threads < 0) throw tools::UsageError("--threads must not be negative");
    if (threads > 0) cv::setNumThreads(threads);

    std::unique_ptr<tools::ProgressBar> bar;
    auto progress = [&](size_t done, int expected) {
      if (!bar) bar = std::make_unique<tools::ProgressBar>("odometry", expected > 0 ? static_cast<size_t>(expected) : 0, cli);
      bar->update(done);
    };
    const tools::dataset::RunStatistics statistics = tools::dataset::runDataset(options, progress);
    if (bar) bar->finish();
    if (statistics.frames() == 0) throw Error("the dataset gave no frame");
    statistics.writeOutputs();
    const nlohmann::json summary = statistics.toJson();
    if (!jsonPath.empty()) {
      std::ofstream out(jsonPath);
      if (!out) throw Error("cannot write " + jsonPath);
      out << tools::toJsonLine(summary) << "\n";
    }
    if (cli.json()) {
      tools::printJsonLine(summary);
    } else {
      statistics.printText(std::cout);
    }
    return tools::kExitSuccess;
  });
}
