#include "dataset/DatasetRun.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <filesystem>
#include <fstream>
#include <iomanip>

#include "rtabmap_core/common/Error.h"
#include "dataset/SlamStage.h"
#include "rtabmap_core/eval/TrajectoryError.h"

namespace rtabmap::tools::dataset {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

Transform cameraLocalOf(const SensorData& data) {
  if (data.isStereo()) return data.stereoCameraModels().front().localTransform();
  if (!data.cameraModels().empty()) return data.cameraModels().front().localTransform();
  return Transform();
}

}  // namespace

OdometryStage::OdometryStage(const RunOptions& options)
    : wheelGuess_(options.wheelOdometryGuess), wheelOnly_(options.wheelOdometry) {
  // With wheel odometry the registration approach is still built: it validates the parameters
  // and names the approach nobody runs ("wheel" is reported instead).
  odometry_ = options.odometry ? Odometry::create(*options.odometry, options.parameters)
                               : Odometry::create(options.parameters);
}

Eigen::Matrix<double, 6, 6> wheelIncrementCovariance(const Transform& motion) {
  const double d = motion.getNorm();
  const double a = std::fabs(motion.getAngle());
  const double sigmaT = 0.001 + 0.05 * d;
  const double sigmaR = 0.001 + 0.05 * a + 0.035 * d;
  Eigen::Matrix<double, 6, 6> c = Eigen::Matrix<double, 6, 6>::Zero();
  for (int i = 0; i < 3; ++i) c(i, i) = sigmaT * sigmaT;
  for (int i = 3; i < 6; ++i) c(i, i) = sigmaR * sigmaR;
  return c;
}

std::optional<FrameResult> OdometryStage::process(DatasetRecord& record) {
  if (record.kind == DatasetRecord::Kind::kImu) {
    odometry_->addImu(record.stamp, record.data.imu());
    return std::nullopt;
  }
  if (record.kind == DatasetRecord::Kind::kOdometry) {
    if (!record.data.odomPose().isNull()) latestWheel_ = record.data.odomPose();
    return std::nullopt;
  }
  if (record.kind != DatasetRecord::Kind::kFrame) return std::nullopt;
  SensorData& data = record.data;
  // The frame's own wheel odometry, else the latest odometry record before it. Read before
  // process(), which overwrites the frame's odometry pose with its own result.
  if (!data.odomPose().isNull()) latestWheel_ = data.odomPose();
  Transform guess;
  if ((wheelGuess_ || wheelOnly_) && !latestWheel_.isNull() && !previousWheel_.isNull()) {
    guess = previousWheel_.inverse() * latestWheel_;
  }
  if (!latestWheel_.isNull()) previousWheel_ = latestWheel_;

  FrameResult result;
  result.id = data.id();
  result.stamp = record.stamp;
  result.groundTruth = data.groundTruth();
  result.cameraLocal = cameraLocalOf(data);
  if (wheelOnly_) {
    result.pose = latestWheel_;
    result.info.lost = latestWheel_.isNull();
    result.info.lostReason = result.info.lost ? "no wheel odometry before this frame" : "";
    result.info.transform = guess.isNull() ? Transform::Identity() : guess;
    result.info.covariance = wheelIncrementCovariance(result.info.transform);
    if (result.info.lost) result.info.covariance = Eigen::Matrix<double, 6, 6>::Identity() * 9999.0;
    wheelDistance_ += result.info.transform.getNorm();
    result.info.distanceTravelled = wheelDistance_;
    result.info.stamp = record.stamp;
    data.setOdom(result.pose, result.info.covariance);
    return result;
  }
  result.pose = odometry_->process(data, guess, &result.info);
  // Per-feature ids are for display; a long run does not need to keep them.
  result.info.reg.matchesIDs.clear();
  result.info.reg.inliersIDs.clear();
  return result;
}

FrameRecord::FrameRecord(const FrameResult& frame)
    : id(frame.id),
      stamp(frame.stamp),
      pose(frame.pose),
      groundTruth(frame.groundTruth),
      cameraLocal(frame.cameraLocal),
      lost(frame.info.lost),
      keyFrameAdded(frame.info.keyFrameAdded),
      autoReset(frame.info.autoReset),
      guessFromImu(frame.info.guessFromImu),
      features(frame.info.features),
      matches(frame.info.reg.matches),
      inliers(frame.info.reg.inliers),
      localMapSize(frame.info.localMapSize),
      timeTotalMs(frame.info.timeTotalMs),
      distanceTravelled(frame.info.distanceTravelled),
      lostReason(frame.info.lostReason) {}

void RunStatistics::add(const FrameResult& frame) { frames_.emplace_back(frame); }

Trajectory RunStatistics::estimate(bool cameraFrame) const {
  Trajectory t;
  for (const FrameRecord& f : frames_) {
    if (f.pose.isNull()) continue;
    if (cameraFrame && f.cameraLocal.isNull()) continue;
    t.add(f.stamp, cameraFrame ? f.pose * f.cameraLocal : f.pose);
  }
  return t;
}

Trajectory RunStatistics::groundTruth(bool cameraFrame) const {
  Trajectory t;
  for (const FrameRecord& f : frames_) {
    if (f.groundTruth.isNull()) continue;
    if (cameraFrame && f.cameraLocal.isNull()) continue;
    t.add(f.stamp, cameraFrame ? f.groundTruth * f.cameraLocal : f.groundTruth);
  }
  return t;
}

void RunStatistics::writeOutputs() const {
  if (options_.outputDir.empty()) {
    writeFramesCsv();
    return;
  }
  std::filesystem::create_directories(options_.outputDir);
  writeTrajectory(options_.outputDir + "/odom.tum", estimate(false), TrajectoryFormat::kTum);
  const Trajectory gt = groundTruth(false);
  if (!gt.empty()) writeTrajectory(options_.outputDir + "/gt.tum", gt, TrajectoryFormat::kTum);
  writeFramesCsv();
}

void RunStatistics::writeFramesCsv() const {
  if (options_.framesCsv.empty()) return;
  std::ofstream out(options_.framesCsv);
  if (!out) throw Error("cannot write " + options_.framesCsv);
  out << "id,stamp,lost,features,matches,inliers,key_frame,local_map,ms,x,y,z,gt_x,gt_y,gt_z,reason\n";
  out << std::setprecision(9);
  for (const FrameRecord& f : frames_) {
    // Stamps in seconds since 1970 need their own precision: 9 digits would drop the fraction.
    out << f.id << "," << std::fixed << std::setprecision(6) << f.stamp << std::defaultfloat << std::setprecision(9)
        << "," << f.lost << "," << f.features << "," << f.matches << ","
        << f.inliers << "," << f.keyFrameAdded << "," << f.localMapSize << "," << f.timeTotalMs;
    for (const Transform* t : {&f.pose, &f.groundTruth}) {
      if (t->isNull()) {
        out << ",,,";
      } else {
        out << "," << t->x() << "," << t->y() << "," << t->z();
      }
    }
    std::string reason = f.lostReason;
    std::replace(reason.begin(), reason.end(), ',', ';');
    out << "," << reason << "\n";
  }
}

nlohmann::json RunStatistics::toJson() const {
  nlohmann::json j;
  j["format"] = options_.format;
  j["dataset"] = options_.path;
  j["odometry"] = approach_;
  std::vector<double> times, features, inliers;
  int lost = 0, keyFrames = 0, resets = 0, imuGuesses = 0;
  double distance = 0.0;
  for (const FrameRecord& f : frames_) {
    times.push_back(f.timeTotalMs);
    features.push_back(f.features);
    if (f.lost) {
      ++lost;
    } else {
      inliers.push_back(f.inliers);
      distance = f.distanceTravelled;
    }
    keyFrames += f.keyFrameAdded ? 1 : 0;
    resets += f.autoReset ? 1 : 0;
    imuGuesses += f.guessFromImu ? 1 : 0;
  }
  j["frames"] = frames_.size();
  j["lost"] = lost;
  j["key_frames"] = keyFrames;
  j["resets"] = resets;
  j["imu_guesses"] = imuGuesses;  // frames whose guess turned as the IMU measured (--imu)
  j["odom_ms_median"] = median(times);
  j["odom_ms_mean"] = times.empty() ? 0.0 : std::accumulate(times.begin(), times.end(), 0.0) / static_cast<double>(times.size());
  j["odom_ms_max"] = times.empty() ? 0.0 : *std::max_element(times.begin(), times.end());
  j["features_median"] = median(features);
  j["inliers_median"] = median(inliers);
  j["distance_m"] = distance;
  const Trajectory gt = groundTruth(options_.ateInCameraFrame);
  const Trajectory est = estimate(options_.ateInCameraFrame);
  if (!gt.empty()) {
    j["ate_frame"] = options_.ateInCameraFrame ? "camera" : "base";
    try {
      AteOptions ate;
      ate.maxTimeDifference = 0.001;  // the same frames on both sides
      const AteResult r = computeAte(gt, est, ate);
      j["odom_ate_rmse"] = r.translation.rmse;
      j["odom_ate_mean"] = r.translation.mean;
      j["odom_ate_median"] = r.translation.median;
      j["odom_ate_max"] = r.translation.max;
      j["ate_poses"] = r.pairs.size();
    } catch (const Error& e) {
      j["ate_error"] = e.what();
    }
  }
  if (!options_.outputDir.empty()) j["odom_tum"] = options_.outputDir + "/odom.tum";
  for (const auto& [key, value] : slam_.items()) j[key] = value;
  return j;
}

void RunStatistics::printText(std::ostream& out) const {
  const nlohmann::json j = toJson();
  out << std::fixed << std::setprecision(2);
  out << "odometry: " << approach_ << " on " << options_.format << " " << options_.path << "\n";
  out << "frames: " << j["frames"].get<size_t>() << " (lost " << j["lost"].get<int>() << ", key frames "
      << j["key_frames"].get<int>() << ", resets " << j["resets"].get<int>() << ")\n";
  out << "odometry time: median " << j["odom_ms_median"].get<double>() << " ms, mean " << j["odom_ms_mean"].get<double>()
      << " ms, max " << j["odom_ms_max"].get<double>() << " ms\n";
  out << "features per frame (median): " << j["features_median"].get<double>() << ", inliers (median): "
      << j["inliers_median"].get<double>() << "\n";
  out << "distance travelled: " << j["distance_m"].get<double>() << " m\n";
  if (j.contains("odom_ate_rmse")) {
    out << std::setprecision(4) << "ATE (" << j["ate_frame"].get<std::string>() << " frame, " << j["ate_poses"].get<size_t>()
        << " poses): RMSE " << j["odom_ate_rmse"].get<double>() << " m, mean " << j["odom_ate_mean"].get<double>()
        << " m, max " << j["odom_ate_max"].get<double>() << " m\n";
  } else if (j.contains("ate_error")) {
    out << "ATE not computed: " << j["ate_error"].get<std::string>() << "\n";
  }
  if (j.contains("odom_tum")) out << "trajectory: " << j["odom_tum"].get<std::string>() << "\n";
  if (!slam_.empty()) {
    out << std::setprecision(2) << "SLAM: " << slam_["nodes"].get<int>() << " nodes, " << slam_["sessions"].get<int>()
        << " session(s), " << slam_["loop_closures"].get<int>() << " loop closures, "
        << slam_["proximity_links"].get<int>() << " proximity links, " << slam_["rejected_links"].get<int>()
        << " rejected links\n";
    out << "SLAM update: median " << slam_["slam_ms_median"].get<double>() << " ms, p99 "
        << slam_["slam_ms_p99"].get<double>() << " ms, max " << slam_["slam_ms_max"].get<double>() << " ms, max WM "
        << slam_["max_wm_size"].get<int>() << ", realtime x" << slam_["realtime_factor"].get<double>() << "\n";
    if (slam_.contains("ate_rmse")) {
      out << std::setprecision(4) << "SLAM ATE (optimised poses, " << slam_["ate_poses"].get<size_t>()
          << " nodes): RMSE " << slam_["ate_rmse"].get<double>() << " m\n";
    }
    out << "map: " << slam_["database"].get<std::string>() << "\n";
  }
}

RunStatistics runDataset(const RunOptions& options, const std::function<void(size_t, int)>& progress) {
  std::unique_ptr<DatasetReader> reader = openDatasetReader(options.format, options.path, options.reader);
  OdometryStage odometry(options);
  RunStatistics statistics(options);
  statistics.setApproach(options.wheelOdometry ? "wheel" : Odometry::typeName(odometry.odometry().type()));
  std::unique_ptr<SlamStage> slam;
  if (options.slam || options.continueDatabase || options.localization) {
    SlamRunOptions s;
    s.enabled = true;
    s.continueDatabase = options.continueDatabase;
    s.localization = options.localization;
    s.database = options.outputDir.empty() ? std::string() : options.outputDir + "/rtabmap.db";
    slam = std::make_unique<SlamStage>(options, s);
  }
  const int expected = reader->frameCount();
  DatasetRecord record;
  double firstStamp = -1.0, lastStamp = 0.0;
  while (reader->next(record)) {
    std::optional<FrameResult> frame = odometry.process(record);
    if (!frame) continue;
    if (firstStamp < 0.0) firstStamp = frame->stamp;
    lastStamp = frame->stamp;
    if (slam) slam->process(*frame, record.data);
    statistics.add(*frame);
    if (progress) progress(statistics.frames(), expected);
  }
  if (slam) {
    slam->finish();
    statistics.setSlam(slam->toJson(firstStamp >= 0.0 ? lastStamp - firstStamp : 0.0));
  }
  return statistics;
}

}  // namespace rtabmap::tools::dataset
