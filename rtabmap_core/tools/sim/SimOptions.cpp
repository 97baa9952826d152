#include "sim/SimOptions.h"

#include <cmath>
#include <sstream>

namespace rtabmap::tools::sim {

namespace {

const char* kFolderNote =
    "Output folder (a \"sim\" dataset; every file is a function of the scenario, seed and options, so the same command "
    "writes the same bytes):\n"
    "  info.yaml            scenario, seed, options, simulator version, counts, sensors and their parameters\n"
    "  calib/rgb.yaml, left.yaml, right.yaml   ROS camera_info YAML with the base_link -> optical frame transform\n"
    "  transforms.txt       static transforms `parent child x y z qx qy qz qw`\n"
    "  frames.txt           `index stamp` + odometry pose (x y z qx qy qz qw) + covariance since the previous frame\n"
    "                       (x, y, yaw upper triangle: cxx cxy cxw cyy cyw cww)\n"
    "  groundtruth.txt      TUM `stamp x y z qx qy qz qw` of base_link at each frame (for rtabmap-eval ate)\n"
    "  odometry.txt         TUM wheel odometry at --odom-rate; odometry_twist.txt: `stamp v w` + covariance\n"
    "  imu.txt              `stamp wx wy wz ax ay az` at --imu-rate (specific force: +9.81 up at rest)\n"
    "  rgb/NNNNNN.png       colour (BGR8)      depth/NNNNNN.png  depth registered to rgb (16-bit mm)\n"
    "  right/NNNNNN.png     right stereo image (grey; the left one is rgb in grey)\n"
    "  depth32/NNNNNN.bin   exact float depth (--depth32)\n"
    "  scan_urg/, scan_utm/ NNNNNN.bin: float32 ranges[beams] then intensities[beams] (+inf: no return)\n"
    "  lidar/NNNNNN.bin     float32 x y z intensity per point (--lidar3d)\n"
    "multisession writes one such folder per run: DIR/session1, DIR/session2, DIR/session3 (and DIR/info.yaml).\n"
    "Read it with the \"sim\" dataset reader (rtabmap-dataset --format sim DIR, or DIR?camera=stereo&scan=utm).";

std::string text(double v) {
  std::ostringstream out;
  out.precision(17);
  out << v;
  return out.str();
}

double positive(const CommandLine& cli, const std::string& name) {
  const double v = cli.optionDouble(name);
  if (!(v > 0.0)) throw UsageError("--" + name + " must be > 0 (got " + cli.option(name) + ")");
  return v;
}

double nonNegative(const CommandLine& cli, const std::string& name) {
  const double v = cli.optionDouble(name);
  if (!(v >= 0.0)) throw UsageError("--" + name + " must be >= 0 (got " + cli.option(name) + ")");
  return v;
}

}  // namespace

void declareOptions(CommandLine& cli) {
  std::string scenarios;
  for (const auto& n : rtabmap::sim::scenarioNames()) scenarios += (scenarios.empty() ? "" : ", ") + n;
  cli.addOption("scenario", "NAME", "What to simulate: " + scenarios + ".");
  cli.addOption("seed", "N", "Seed of the building, route and noise (same seed, same bytes).", "1");
  cli.addOption("output", "DIR", "Dataset folder to write (created).");
  cli.addOption("bag", "OUT.bag", "Also convert the folder to a rosbag with rtabmap-bag (multisession: OUT_session1.bag, ...).");
  cli.addOption("width", "PX", "Image width.", "640");
  cli.addOption("height", "PX", "Image height.", "480");
  cli.addOption("rate", "HZ", "Frame rate (images and scans); default 10, 1 for long.");
  cli.addOption("baseline", "M", "Stereo baseline.", "0.12");
  cli.addOption("duration", "S", "Stop after S seconds of driving (long: the tour's length; default 7200).");
  cli.addOption("speed", "M/S", "Top speed of the robot.", "0.5");
  cli.addOption("imu-rate", "HZ", "IMU rate.", "200");
  cli.addOption("odom-rate", "HZ", "Wheel-odometry rate.", "50");
  cli.addOption("camera-height", "M", "Height of the camera's optical centre above the floor.", "0.5");
  cli.addOption("odom-noise-trans", "M/SQRT(M)", "Odometry distance noise (standard deviation after 1 m).", "0.02");
  cli.addOption("odom-noise-rot", "RAD/SQRT(RAD)", "Odometry heading noise per radian turned.", "0.03");
  cli.addOption("odom-noise-rot-per-m", "RAD/SQRT(M)", "Odometry heading noise per metre driven.", "0.01");
  cli.addOption("odom-bias-scale", "RATIO", "Systematic odometry distance error (0.005 = +0.5%).", "0.005");
  cli.addOption("odom-bias-yaw", "RAD/M", "Systematic odometry heading drift per metre.", "0.002");
  cli.addFlag("exact-odometry", "Odometry without noise or bias (equals the ground truth, up to the start pose).");
  cli.addOption("imu-noise", "SCALE", "Scale of the IMU noise and bias model (0: exact IMU).", "1");
  cli.addOption("laser-noise", "M", "Range noise of the 2D lasers and the lidar (0: exact).", "0");
  cli.addOption("image-noise", "LEVELS", "Pixel noise of the camera images (0: none).", "0");
  cli.addFlag("no-rgbd", "Do not write RGB-D images (also drops the stereo pair, whose left image is the RGB one).");
  cli.addFlag("no-stereo", "Do not write the right stereo image.");
  cli.addFlag("no-urg", "Do not write URG-04LX scans (240 deg, 5.6 m).");
  cli.addFlag("no-utm", "Do not write UTM-30LX scans (270 deg, 30 m).");
  cli.addFlag("lidar3d", "Also write 16-beam lidar clouds.");
  cli.addFlag("depth32", "Also write the exact float depth (depth32/).");
  cli.addFlag("no-lighting", "Flat shading (no per-wall light, no gradient towards the ceiling lights).");
  cli.addFlag("no-vignetting", "No lens vignetting.");
  cli.addOption("start-stamp", "S", "Stamp of the first sample (seconds).", "1700000000");
  cli.addOption("texture-size", "TEXELS", "Material tile size (power of two): 512 = 128 texels per metre; smaller is faster to generate.", "512");
  cli.addOption("threads", "N", "Image encoding threads.", "2");
  cli.addFlag("overwrite", "Replace a previous rtabmap-sim output in DIR (only its files are removed).");
  cli.addNote(kFolderNote);
  cli.addNote("Example: rtabmap-sim --scenario loop --seed 7 --output /tmp/loop --json | tail -n 1");
}

SimRun readOptions(const CommandLine& cli) {
  SimRun run;
  run.scenario = cli.option("scenario");
  try {
    run.spec = rtabmap::sim::scenarioSpec(run.scenario);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--scenario: ") + e.what());
  }
  const std::string seedText = cli.option("seed");
  try {
    size_t used = 0;
    run.seed = std::stoull(seedText, &used);
    if (used != seedText.size() || seedText[0] == '-') throw std::invalid_argument("seed");
  } catch (const std::exception&) {
    throw UsageError("--seed expects a non-negative integer, got \"" + seedText + "\"");
  }
  run.output = cli.option("output");
  run.bag = cli.has("bag") ? cli.option("bag") : "";
  run.overwrite = cli.flag("overwrite");
  run.depth32 = cli.flag("depth32");
  run.threads = cli.optionInt("threads");
  if (run.threads < 1 || run.threads > 64) throw UsageError("--threads must be in [1, 64]");

  const int width = cli.optionInt("width");
  const int height = cli.optionInt("height");
  if (width < 16 || height < 16 || width > 8192 || height > 8192) throw UsageError("--width and --height must be in [16, 8192]");
  const int textureSize = cli.optionInt("texture-size");
  if (textureSize < 32 || textureSize > 4096 || (textureSize & (textureSize - 1))) {
    throw UsageError("--texture-size must be a power of two in [32, 4096]");
  }
  run.spec.building.materialSize = textureSize;
  run.spec.building.materialTexelsPerMetre = textureSize / 4.0f;  // tiles stay 4 m wide
  run.spec.building.decalTexelsPerMetre = std::min(256.0f, textureSize / 2.0f);

  rtabmap::sim::SimulationConfig& c = run.config;
  const double baseline = positive(cli, "baseline");
  const double cameraHeight = positive(cli, "camera-height");
  if (cameraHeight >= run.spec.building.ceilingHeight - 0.1) throw UsageError("--camera-height must be below the ceiling (2.7 m)");
  c.camera = rtabmap::sim::CameraSpec::standard(width, height, baseline, cameraHeight);
  c.frameRate = cli.has("rate") ? positive(cli, "rate") : run.spec.defaultRate;
  c.imuRate = positive(cli, "imu-rate");
  c.odomRate = positive(cli, "odom-rate");
  if (c.frameRate > 1000 || c.imuRate > 1000 || c.odomRate > 1000) throw UsageError("rates must be at most 1000 Hz (the simulation step is 1 ms)");
  run.duration = cli.has("duration") ? positive(cli, "duration") : 0.0;
  if (run.spec.name != "long") c.maxDuration = run.duration;
  c.motion.maxSpeed = positive(cli, "speed");
  if (c.motion.maxSpeed > 2.0) throw UsageError("--speed above 2 m/s is not an indoor robot");
  if (cli.flag("exact-odometry")) {
    c.odometryNoise = rtabmap::sim::OdometryNoise::none();
  } else {
    c.odometryNoise.translation = nonNegative(cli, "odom-noise-trans");
    c.odometryNoise.rotation = nonNegative(cli, "odom-noise-rot");
    c.odometryNoise.rotationPerMetre = nonNegative(cli, "odom-noise-rot-per-m");
    c.odometryNoise.scaleBias = cli.optionDouble("odom-bias-scale");
    c.odometryNoise.yawBiasPerMetre = cli.optionDouble("odom-bias-yaw");
  }
  const double imuScale = nonNegative(cli, "imu-noise");
  rtabmap::sim::ImuNoise& in = c.imuNoise;
  in.gyroNoiseDensity *= imuScale;
  in.accelNoiseDensity *= imuScale;
  in.gyroBiasWalk *= imuScale;
  in.accelBiasWalk *= imuScale;
  in.gyroBiasInitial *= imuScale;
  in.accelBiasInitial *= imuScale;
  const double laserNoise = nonNegative(cli, "laser-noise");
  c.urg.noiseSigma = c.utm.noiseSigma = c.lidar.noiseSigma = laserNoise;
  c.render.noiseSigma = nonNegative(cli, "image-noise");
  c.render.lighting = !cli.flag("no-lighting");
  c.render.vignetting = !cli.flag("no-vignetting");
  c.colour = !cli.flag("no-rgbd");
  c.stereo = c.colour && !cli.flag("no-stereo");
  c.scanUrg = !cli.flag("no-urg");
  c.scanUtm = !cli.flag("no-utm");
  c.lidar3d = cli.flag("lidar3d");
  c.startStamp = nonNegative(cli, "start-stamp");

  auto& r = run.recorded;
  r = {{"scenario", run.scenario},
       {"seed", std::to_string(run.seed)},
       {"width", std::to_string(width)},
       {"height", std::to_string(height)},
       {"rate", text(c.frameRate)},
       {"baseline", text(baseline)},
       {"duration", text(run.duration)},
       {"speed", text(c.motion.maxSpeed)},
       {"imu_rate", text(c.imuRate)},
       {"odom_rate", text(c.odomRate)},
       {"camera_height", text(cameraHeight)},
       {"odom_noise_trans", text(c.odometryNoise.translation)},
       {"odom_noise_rot", text(c.odometryNoise.rotation)},
       {"odom_noise_rot_per_m", text(c.odometryNoise.rotationPerMetre)},
       {"odom_bias_scale", text(c.odometryNoise.scaleBias)},
       {"odom_bias_yaw", text(c.odometryNoise.yawBiasPerMetre)},
       {"imu_noise", text(imuScale)},
       {"laser_noise", text(laserNoise)},
       {"image_noise", text(c.render.noiseSigma)},
       {"rgbd", c.colour ? "true" : "false"},
       {"stereo", c.stereo ? "true" : "false"},
       {"urg", c.scanUrg ? "true" : "false"},
       {"utm", c.scanUtm ? "true" : "false"},
       {"lidar3d", c.lidar3d ? "true" : "false"},
       {"depth32", run.depth32 ? "true" : "false"},
       {"lighting", c.render.lighting ? "true" : "false"},
       {"vignetting", c.render.vignetting ? "true" : "false"},
       {"start_stamp", text(c.startStamp)},
       {"texture_size", std::to_string(textureSize)}};
  return run;
}

}  // namespace rtabmap::tools::sim
