#include "dataset/SlamStage.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/eval/TrajectoryError.h"
#include "rtabmap_core/maps/MapIO.h"
#include "rtabmap_core/memory/ProcessMemory.h"

namespace rtabmap::tools::dataset {

SlamStage::SlamStage(const RunOptions& run, const SlamRunOptions& options) : run_(run), options_(options) {
  if (options_.database.empty()) throw Error("SLAM needs --output DIR (the map is DIR/rtabmap.db)");
  std::filesystem::create_directories(std::filesystem::path(options_.database).parent_path());
  const bool keep = options_.continueDatabase || options_.localization;
  if (!keep) {
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(options_.database + suffix);
  }
  ParametersMap parameters = run_.parameters;
  if (options_.localization) parameters[Parameters::kMemIncrementalMemory()] = "false";
  // A map for navigation is the point of a dataset run: local grids unless told otherwise.
  parameters.emplace(Parameters::kRGBDCreateOccupancyGrid(), "true");
  rtabmap_.init(parameters, options_.database);
  if (!run_.updatesCsv.empty()) {
    updatesCsv_.open(run_.updatesCsv);
    if (!updatesCsv_) throw Error("cannot write " + run_.updatesCsv);
    updatesCsv_ << "node,nodes,wm,update_ms,map_assembling_ms,rss_mb,heap_mb,heap_free_mb,sqlite_mb,grid_mb,"
                   "rss_anon_mb,rss_file_mb,grid_read_back,words,memory_release_ms,"
                   "locations_mb,vocabulary_mb,index_points,grid_path,grid_moved,grid_replayed,grid_cell_updates\n";
  }
}

void SlamStage::process(const FrameResult& frame, const SensorData& data) {
  ++frames_;
  if (!frame.groundTruth.isNull()) groundTruth_[frame.stamp] = frame.groundTruth;
  if (frame.pose.isNull()) return;  // odometry lost: Rtabmap would refuse it anyway
  const auto start = std::chrono::steady_clock::now();
  const bool used = rtabmap_.process(data, frame.pose, frame.info.covariance);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  wallSeconds_ += ms / 1000.0;
  if (options_.localization) localizationFrames_.emplace_back(frame.stamp, rtabmap_.mapCorrection() * frame.pose);
  reanchorReducedFrames(rtabmap_.statistics());  // a frame not used may still push a node out of STM
  if (used) {
    updateMs_.push_back(ms);
    for (const auto& [key, value] : rtabmap_.statistics().data()) {
      if (key.rfind("Timing/", 0) == 0) stageMs_[key].push_back(value);
    }
    const int id = rtabmap_.statistics().refImageId;
    if (id > 0 && !nodeStamps_.count(id)) {
      nodeStamps_[id] = frame.stamp;
      nodeOdometry_[id] = frame.pose;
    }
    if (updatesCsv_.is_open()) {
      const auto& d = rtabmap_.statistics().data();
      auto get = [&d](const char* key) {
        auto it = d.find(key);
        return it == d.end() ? -1.0 : static_cast<double>(it->second);
      };
      constexpr double kMb = 1.0 / (1024.0 * 1024.0);
      const memory::Resident rss = memory::residentMemory();
      updatesCsv_ << id << ',' << nodeStamps_.size() << ',' << get("Memory/Working_memory_size/") << ',' << ms << ','
                  << get("Timing/Map_assembling/ms") << ',' << rss.total * kMb << ',' << get("Memory/RAM_usage/MB") << ','
                  << get("Memory/Heap_free/MB") << ',' << get("Memory/Database_memory_used/MB") << ','
                  << get("Memory/Grid_memory_used/MB") << ',' << rss.anon * kMb << ',' << rss.file * kMb << ','
                  << get("Memory/Grid_nodes_read_back/") << ',' << get("Keypoint/Dictionary_size/words") << ','
                  << get("Timing/Memory_release/ms") << ',' << get("Memory/Locations_memory_used/MB") << ','
                  << get("Memory/Vocabulary_memory_used/MB") << ',' << get("Memory/Vocabulary_index_points/") << ','
                  << get("Memory/Grid_path/") << ',' << get("Memory/Grid_nodes_moved/") << ','
                  << get("Memory/Grid_nodes_replayed/") << ',' << get("Memory/Grid_cell_updates/") << '\n';
    }
  }
  // A skipped frame kept as an intermediate node (Rtabmap/CreateIntermediateNodes) is a node of
  // poses.tum too, and the node its frame's pose hangs on.
  const int newest = rtabmap_.newestNodeId();
  if (!used && newest > 0 && newest != rtabmap_.lastNodeId() && !nodeStamps_.count(newest)) {
    nodeStamps_[newest] = frame.stamp;
    nodeOdometry_[newest] = frame.pose;
  }
  if (newest > 0) frameRefs_.push_back({frame.stamp, newest, frame.pose});
}

void SlamStage::reanchorReducedFrames(const Statistics& stats) {
  for (const auto& [id, offset] : stats.reducedTransforms) {
    auto into = stats.reducedIds.find(id);
    if (into != stats.reducedIds.end()) reduced_[id] = {into->second, offset};
  }
}

Transform SlamStage::finalPoseOf(int node) const {
  Transform offset = Transform::Identity();
  for (auto r = reduced_.find(node); r != reduced_.end(); r = reduced_.find(node)) {
    offset = r->second.second * offset;
    node = r->second.first;
  }
  auto pose = finalPoses_.find(node);
  return pose == finalPoses_.end() ? Transform() : pose->second * offset;
}

void SlamStage::finish() {
  finalPoses_ = rtabmap_.optimizedPoses();
  const SlamSummary s = rtabmap_.summary();
  sessions_ = s.mapsStarted;
  const GridMap grid = rtabmap_.gridMap();
  rtabmap_.close();
  const std::string dir = std::filesystem::path(options_.database).parent_path().string();
  if (!options_.localization) {
    Trajectory poses;
    for (const auto& [id, pose] : finalPoses_) {
      auto stamp = nodeStamps_.find(id);
      if (stamp != nodeStamps_.end()) poses.add(stamp->second, pose);
    }
    writeTrajectory(dir + "/poses.tum", poses, TrajectoryFormat::kTum);
    Trajectory frames;
    for (const FrameRef& f : frameRefs_) {
      const Transform node = finalPoseOf(f.node);
      auto odom = nodeOdometry_.find(f.node);
      if (node.isNull() || odom == nodeOdometry_.end()) continue;
      frames.add(f.stamp, node * (odom->second.inverse() * f.odometry));
    }
    writeTrajectory(dir + "/frames.tum", frames, TrajectoryFormat::kTum);
  } else {
    Trajectory frames;
    for (const auto& [stamp, pose] : localizationFrames_) frames.add(stamp, pose);
    writeTrajectory(dir + "/localization.tum", frames, TrajectoryFormat::kTum);
  }
  if (!grid.empty()) {
    writeMapServer(grid, dir + "/grid.pgm", dir + "/grid.yaml");
    writeGridPng(grid, dir + "/grid.png");
  }
}

nlohmann::json SlamStage::toJson(double datasetSeconds) const {
  const SlamSummary s = rtabmap_.summary();
  nlohmann::json j;
  j["frames"] = frames_;
  j["nodes"] = s.nodesAdded;
  j["intermediate_nodes"] = s.intermediateNodes;
  j["reduced_nodes"] = s.reducedNodes;
  j["sessions"] = sessions_;
  j["loop_closures"] = s.loopClosures;
  j["proximity_links"] = s.proximityLinks;
  j["time_proximity_links"] = s.timeLinks;
  j["rejected_links"] = s.rejectedLinks;
  j["localizations"] = s.localizations;
  j["refused"] = s.refused;
  j["transferred"] = s.transferred;
  j["retrieved"] = s.retrieved;
  j["slam_ms_median"] = percentile(updateMs_, 0.5);
  j["slam_ms_p99"] = percentile(updateMs_, 0.99);
  j["slam_ms_max"] = updateMs_.empty() ? 0.0 : *std::max_element(updateMs_.begin(), updateMs_.end());
  // Where the time goes, stage by stage (median and p99 over the updates that ran the stage).
  nlohmann::json stages = nlohmann::json::object();
  for (const auto& [key, values] : stageMs_) {
    stages[key] = {{"median", percentile(values, 0.5)}, {"p99", percentile(values, 0.99)}};
  }
  j["slam_stage_ms"] = stages;
  j["max_wm_size"] = s.maxWmSize;
  j["realtime_factor"] = wallSeconds_ > 0.0 ? datasetSeconds / wallSeconds_ : 0.0;
  if (!groundTruth_.empty() && !options_.localization) {
    Trajectory gt, est;
    for (const auto& [stamp, pose] : groundTruth_) gt.add(stamp, pose);
    for (const auto& [id, pose] : finalPoses_) {
      auto stamp = nodeStamps_.find(id);
      if (stamp != nodeStamps_.end()) est.add(stamp->second, pose);
    }
    try {
      AteOptions ate;
      ate.maxTimeDifference = 0.001;
      const AteResult r = computeAte(gt, est, ate);
      j["ate_rmse"] = r.translation.rmse;
      j["ate_poses"] = r.pairs.size();
    } catch (const Error& e) {
      j["ate_error"] = e.what();
    }
  }
  j["database"] = options_.database;
  return j;
}

}  // namespace rtabmap::tools::dataset
