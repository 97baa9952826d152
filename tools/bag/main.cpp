// rtabmap-bag: converts a dataset (CARMEN log, 7-Scenes, TUM RGB-D, EuRoC, KITTI, image folder,
// simulator output) into a rosbag with the standard topics and frames, for rosbag play --clock.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "Bench.h"
#include "Conversion.h"
#include "common/CommandLine.h"
#include "common/Json.h"
#include "common/ProgressBar.h"

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  return rtabmap::tools::runTool("rtabmap-bag", [&] {
    using rtabmap::tools::UsageError;
    rtabmap::tools::CommandLine cli(
        "rtabmap-bag",
        "Converts a dataset into a rosbag with the standard topics and frames (REP-105): /scan or "
        "/velodyne_points, /odom and tf odom -> base_link, /tf_static with the sensor mountings, "
        "/camera/rgb/image_rect_color, /camera/depth_registered/image_raw, /camera/rgb/camera_info, "
        "/stereo_camera/{left,right}/{image_rect,camera_info}, /imu/data and /ground_truth. Message "
        "stamps are the dataset's own times, so the bag replays with `rosbag play --clock`.");
    cli.addOption("format", "FORMAT", "Dataset layout: " + joined(rtabmap::datasetFormats()) + ".");
    cli.addPositional("input", "Dataset: a .clf[.bz2] log (carmen) or a folder.", false);
    cli.addPositional("output", "Bag to write (overwritten).", false);
    cli.addOption("compression", "TYPE", "Chunk compression of the bag: none, bz2 or lz4.", "none");
    cli.addOption("time-offset", "SECONDS",
                  "Added to every dataset stamp. Default: 0, or the whole seconds that bring a clock "
                  "starting at 0 (synthesised stamps) to 1 s.");
    cli.addOption("start-frame", "N", "Skip the first N sensor frames.", "0");
    cli.addOption("max-frames", "N", "Stop after N sensor frames (0 = all).", "0");
    cli.addOption("frame-rate", "HZ", "Frame rate of layouts without times (7scenes, images, kitti).");
    cli.addOption("calibration", "FILE", "Camera calibration overriding the dataset's (camera_info YAML; KITTI calib.txt).");
    cli.addOption("gt", "FILE", "Ground-truth file overriding the dataset's.");
    cli.addOption("scan-range-max", "METRES", "carmen: readings at or beyond are no-returns (default: from the log).");
    cli.addFlag("no-imu", "Leave out the IMU.");
    cli.addFlag("no-images", "Leave out the images (scans, odometry and ground truth only).");
    cli.addFlag("bench", "Measure the converter throughput on the datasets of --data instead (no INPUT/OUTPUT).");
    cli.addOption("data", "DIRS", "--bench: data folders laid out as ../shared/data, separated by ':' and "
                                  "searched in order (default: $RTABMAP_DATA_DIR).");
    cli.addNote("Example: rtabmap-bag --format carmen ../shared/data/radish/aces.clf.bz2 aces.bag && "
                "rosbag play --clock aces.bag");
    cli.addNote("Frames: base_link -> laser | velodyne | imu_link, base_link -> camera_link -> "
                "camera_rgb_optical_frame (RGB-D) or camera_left_optical_frame and "
                "camera_right_optical_frame (stereo); images name their optical frame.");
    if (auto exitCode = cli.parse(argc, argv)) return *exitCode;

    if (cli.flag("bench")) {
      std::string data = cli.has("data") ? cli.option("data") : "";
      if (data.empty() && std::getenv("RTABMAP_DATA_DIR")) data = std::getenv("RTABMAP_DATA_DIR");
      if (data.empty()) throw UsageError("--bench needs --data DIRS (or RTABMAP_DATA_DIR)");
      std::vector<std::string> dirs;
      std::stringstream list(data);
      for (std::string dir; std::getline(list, dir, ':');) dirs.push_back(dir);
      return rtabmap_bag::runBench(dirs, std::filesystem::temp_directory_path().string());
    }

    rtabmap_bag::ConversionRequest request;
    if (!cli.has("format")) throw UsageError("--format is required (" + joined(rtabmap::datasetFormats()) + ")");
    request.format = cli.option("format");
    const std::vector<std::string> formats = rtabmap::datasetFormats();
    if (std::find(formats.begin(), formats.end(), request.format) == formats.end()) {
      throw UsageError("unknown --format '" + request.format + "'; expected one of " + joined(formats));
    }
    request.input = cli.positional("input");
    request.output = cli.positional("output");
    if (request.input.empty() || request.output.empty()) throw UsageError("INPUT and OUTPUT are required");
    request.writer.compression = cli.option("compression");
    if (request.writer.compression != "none" && request.writer.compression != "bz2" &&
        request.writer.compression != "lz4") {
      throw UsageError("--compression must be none, bz2 or lz4, not '" + request.writer.compression + "'");
    }
    if (cli.has("time-offset")) request.writer.timeOffset = cli.optionDouble("time-offset");
    request.reader.startFrame = cli.optionInt("start-frame");
    request.reader.maxFrames = cli.optionInt("max-frames");
    if (cli.has("frame-rate")) request.reader.frameRate = cli.optionDouble("frame-rate");
    if (cli.has("calibration")) request.reader.calibrationPath = cli.option("calibration");
    if (cli.has("gt")) request.reader.groundTruthPath = cli.option("gt");
    if (cli.has("scan-range-max")) request.reader.scanRangeMax = cli.optionDouble("scan-range-max");
    request.reader.imu = !cli.flag("no-imu");
    request.reader.images = !cli.flag("no-images");

    const bool live = !cli.json() && rtabmap::tools::stderrIsTerminal();
    const rtabmap_bag::ConversionResult result = rtabmap_bag::convert(request, !cli.json(), live);
    if (cli.json()) {
      rtabmap::tools::printJsonLine(rtabmap_bag::toJson(request, result));
    } else {
      std::cout << rtabmap_bag::toText(request, result);
    }
    return rtabmap::tools::kExitSuccess;
  });
}
