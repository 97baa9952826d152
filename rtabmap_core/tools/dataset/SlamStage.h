#pragma once
// rtabmap-dataset's mapping stage: each frame after odometry goes through Rtabmap::process();
// at the end the optimised trajectory, the grid and the figures of the run are written.
#include <nlohmann/json.hpp>

#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "dataset/DatasetRun.h"
#include "rtabmap_core/slam/Rtabmap.h"

namespace rtabmap::tools::dataset {

struct SlamRunOptions {
  bool enabled = false;        // --slam (implied by --continue and --localization)
  bool continueDatabase = false;  // --continue: add a session to DIR/rtabmap.db
  bool localization = false;      // --localization: localise against DIR/rtabmap.db
  std::string database;           // DIR/rtabmap.db
};

class SlamStage {
 public:
  // Removes an existing database unless continuing or localising. Throws on bad parameters or
  // an unusable database.
  SlamStage(const RunOptions& run, const SlamRunOptions& options);
  void process(const FrameResult& frame, const SensorData& data);
  // Closes the map; writes DIR/poses.tum (optimised nodes, node stamps), DIR/frames.tum (every
  // frame: its last node's optimised pose composed with the odometry since that node, for
  // per-scan metrics such as the Radish relations) and DIR/grid.pgm + .yaml + .png when there
  // is a grid. In localization mode, DIR/localization.tum instead: every frame's pose in the map
  // as the robot would publish it (map -> odom after the frame times its odometry).
  void finish();
  // frames, nodes, sessions, loop_closures, proximity_links, time_proximity_links, rejected_links, slam_ms_* ,
  // slam_stage_ms (Timing/* median and p99), max_wm_size, realtime_factor, ate_rmse (against the frames' ground truth).
  nlohmann::json toJson(double datasetSeconds) const;
  const Rtabmap& rtabmap() const { return rtabmap_; }

 private:
  RunOptions run_;
  SlamRunOptions options_;
  Rtabmap rtabmap_;
  std::map<int, double> nodeStamps_;     // node id -> frame stamp
  std::map<int, Transform> nodeOdometry_;  // node id -> odometry pose when created
  struct FrameRef {
    double stamp;
    int node;          // last node of the map when the frame was processed
    Transform odometry;
  };
  std::vector<FrameRef> frameRefs_;
  // Mem/ReduceGraph: a frame hanging on a node merged away hangs on the node it merged into,
  // at the offset the graph had between them (node -> (into, pose in into's frame)).
  std::map<int, std::pair<int, Transform>> reduced_;
  void reanchorReducedFrames(const Statistics& stats);
  // The optimised pose of `node`, or of the node it was merged into composed with the offset
  // (null if none).
  Transform finalPoseOf(int node) const;
  std::map<double, Transform> groundTruth_;  // frame stamp -> ground truth (base)
  std::vector<std::pair<double, Transform>> localizationFrames_;  // localization mode: stamp -> pose in the map
  std::vector<double> updateMs_;
  std::map<std::string, std::vector<double>> stageMs_;  // Timing/... statistic -> per update
  double wallSeconds_ = 0.0;
  std::ofstream updatesCsv_;  // --updates-csv
  std::map<int, Transform> finalPoses_;
  int sessions_ = 0;
  int frames_ = 0;
};

}  // namespace rtabmap::tools::dataset
