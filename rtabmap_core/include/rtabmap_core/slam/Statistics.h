#pragma once
// Statistics of one SLAM update (published on `info`, saved per node in the database).
//
// Scalar statistics are a map key -> value with keys in the original style
// "Group/Name/unit": the unit after the last slash, empty for counts and ids
// ("Loop/Highest_hypothesis_id/"). The standard keys are declared once, in
// RTABMAP_STATISTICS_LIST below, which generates one constant per key
// (Statistics::kTimingTotal == "Timing/Total/ms") and the registry standardKeys(); code never
// types a standard key by hand. addStatistic() also takes dynamic keys (per-sensor timings...).
//
// The structured results of the update (ids, posterior, WM state, poses...) are plain members.
#include <map>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/memory/Link.h"

// X(Group, Name, unit) for every standard statistic. Names keep the original spelling so that
// tools reading original logs and databases find the same keys.
#define RTABMAP_STATISTICS_LIST(X)                  \
  X(Loop, Accepted_hypothesis_id, )                 \
  X(Loop, Suppressed_hypothesis_id, )               \
  X(Loop, Highest_hypothesis_id, )                  \
  X(Loop, Highest_hypothesis_value, )               \
  X(Loop, Rejected_hypothesis, )                    \
  X(Loop, Hypothesis_ratio, )                       \
  X(Loop, Hypothesis_reactivated, )                 \
  X(Loop, Vp_hypothesis, )                          \
  X(Loop, Reactivate_id, )                          \
  X(Loop, Map_id, )                                 \
  X(Loop, Last_id, )                                \
  X(Loop, Visual_words, )                           \
  X(Loop, Visual_matches, )                         \
  X(Loop, Visual_inliers, )                         \
  X(Loop, Visual_inliers_ratio, )                   \
  X(Loop, Distance_since_last_loc, m)               \
  X(Loop, Optimization_max_error, m)                \
  X(Loop, Optimization_max_error_ratio, )           \
  X(Loop, Optimization_error, )                     \
  X(Loop, Optimization_iterations, )                \
  X(Loop, Linear_variance, )                        \
  X(Loop, Angular_variance, )                       \
  X(Loop, Landmark_detected, )                      \
  X(Loop, Odom_correction_norm, m)                  \
  X(Loop, Odom_correction_angle, deg)               \
  X(Proximity, Time_detections, )                   \
  X(Proximity, Space_last_detection_id, )           \
  X(Proximity, Space_paths, )                       \
  X(Proximity, Space_visual_paths_checked, )        \
  X(Proximity, Space_scan_paths_checked, )          \
  X(Proximity, Space_detections_added_visually, )   \
  X(Proximity, Space_detections_added_icp_multi, )  \
  X(Proximity, Space_detections_added_icp_global, ) \
  X(NeighborLinkRefining, Accepted, )               \
  X(NeighborLinkRefining, Inliers, )                \
  X(NeighborLinkRefining, ICP_inliers_ratio, )      \
  X(NeighborLinkRefining, ICP_rms, )                \
  X(NeighborLinkRefining, Variance, )               \
  X(NeighborLinkRefining, Pts, )                    \
  X(Memory, Working_memory_size, )                  \
  X(Memory, Short_time_memory_size, )               \
  X(Memory, Durable_node_id, )                      \
  X(Memory, Database_write_failed, )                \
  X(Memory, Database_memory_used, MB)               \
  X(Memory, Similarity, )                           \
  X(Memory, Last_loop_closure_id, )                 \
  X(Memory, Rehearsal_merged, )                     \
  X(Memory, Rehearsal_id, )                         \
  X(Memory, Local_graph_size, )                     \
  X(Memory, Small_movement, )                       \
  X(Memory, Fast_movement, )                        \
  X(Memory, Odometry_variance_lin, )                \
  X(Memory, Odometry_variance_ang, )                \
  X(Memory, Distance_travelled, m)                  \
  X(Memory, Signatures_removed, )                   \
  X(Memory, Signatures_retrieved, )                 \
  X(Memory, Immunized_globally, )                   \
  X(Memory, Immunized_locally, )                    \
  X(Memory, Immunized_locally_max, )                \
  X(Memory, Images_buffered, )                      \
  X(Memory, RAM_usage, MB)                          \
  X(Memory, RAM_estimated, MB)                      \
  X(Memory, Closest_node_distance, m)               \
  X(Memory, Closest_node_angle, rad)                \
  X(Keypoint, Dictionary_size, words)               \
  X(Keypoint, Current_frame, words)                 \
  X(Keypoint, Indexed_words, words)                 \
  X(Keypoint, Index_memory_usage, KB)               \
  X(Timing, Memory_update, ms)                      \
  X(Timing, Neighbor_link_refining, ms)             \
  X(Timing, Proximity_by_time, ms)                  \
  X(Timing, Proximity_by_space_search, ms)          \
  X(Timing, Proximity_by_space_visual, ms)          \
  X(Timing, Proximity_by_space, ms)                 \
  X(Timing, Cleaning_neighbors, ms)                 \
  X(Timing, Reactivation, ms)                       \
  X(Timing, Add_loop_closure_link, ms)              \
  X(Timing, Map_optimization, ms)                   \
  X(Timing, Map_assembling, ms)                     \
  X(Timing, Likelihood_computation, ms)             \
  X(Timing, Posterior_computation, ms)              \
  X(Timing, Hypotheses_creation, ms)                \
  X(Timing, Hypotheses_validation, ms)              \
  X(Timing, Statistics_creation, ms)                \
  X(Timing, Memory_cleanup, ms)                     \
  X(Timing, Forgetting, ms)                         \
  X(Timing, Joining_trash, ms)                      \
  X(Timing, Emptying_trash, ms)                     \
  X(Timing, Finalizing_statistics, ms)              \
  X(Timing, RAM_estimation, ms)                     \
  X(Timing, Memory_release, ms)                     \
  X(Timing, Total, ms)                              \
  X(TimingMem, Pre_update, ms)                      \
  X(TimingMem, Signature_creation, ms)              \
  X(TimingMem, Rehearsal, ms)                       \
  X(TimingMem, Keypoints_detection, ms)             \
  X(TimingMem, Descriptors_extraction, ms)          \
  X(TimingMem, Stereo_correspondences, ms)          \
  X(TimingMem, Rectification, ms)                   \
  X(TimingMem, Keypoints_3D, ms)                    \
  X(TimingMem, Joining_dictionary_update, ms)       \
  X(TimingMem, Add_new_words, ms)                   \
  X(TimingMem, Compressing_data, ms)                \
  X(TimingMem, Occupancy_grid, ms)                  \
  X(Gt, Translational_rmse, m)                      \
  X(Gt, Translational_mean, m)                      \
  X(Gt, Translational_median, m)                    \
  X(Gt, Translational_std, m)                       \
  X(Gt, Translational_min, m)                       \
  X(Gt, Translational_max, m)                       \
  X(Gt, Rotational_rmse, deg)                       \
  X(Gt, Rotational_mean, deg)                       \
  X(Gt, Rotational_median, deg)                     \
  X(Gt, Rotational_std, deg)                        \
  X(Gt, Rotational_min, deg)                        \
  X(Gt, Rotational_max, deg)                        \
  X(Gt, Localization_linear_error, m)               \
  X(Gt, Localization_angular_error, deg)

namespace rtabmap {

// One key of the registry, split in its parts.
struct StatisticKey {
  const char* key;    // "Timing/Total/ms"
  const char* group;  // "Timing"
  const char* name;   // "Total"
  const char* unit;   // "ms" ("" for counts and ids)
};

class Statistics {
 public:
#define RTABMAP_STAT_CONSTANT(Group, Name, Unit) \
  static constexpr const char* k##Group##Name = #Group "/" #Name "/" #Unit;
  RTABMAP_STATISTICS_LIST(RTABMAP_STAT_CONSTANT)
#undef RTABMAP_STAT_CONSTANT

  // Every standard key, in declaration order.
  static const std::vector<StatisticKey>& standardKeys();
  static bool isStandardKey(const std::string& key);
  // Splits "Group/Name/unit" (the name may itself contain slashes: the group ends at the first
  // slash, the unit starts after the last). False if the key has fewer than two slashes or an
  // empty group or name.
  static bool parseKey(const std::string& key, std::string* group, std::string* name,
                       std::string* unit);
  // "" if the key is malformed.
  static std::string unitOf(const std::string& key);

  // Sets a statistic (standard or dynamic key). Throws FormatError on a malformed key.
  void addStatistic(const std::string& key, float value);
  // True and *value if the key was set this update.
  bool getStatistic(const std::string& key, float* value) const;
  const std::map<std::string, float>& data() const { return data_; }
  void setData(const std::map<std::string, float>& data);

  // --- results of the update, filled by Rtabmap::process() ---
  int refImageId = 0;           // the node created by this update
  int refImageMapId = -1;
  int loopClosureId = 0;        // accepted global loop closure (0 if none)
  int loopClosureMapId = -1;
  int proximityDetectionId = 0; // accepted proximity detection (0 if none)
  int proximityDetectionMapId = -1;
  int landmarkId = 0;
  Transform loopClosureTransform;  // from refImageId to the loop-closure node
  double stamp = 0.0;
  int currentGoalId = 0;
  Transform mapCorrection;         // map -> odom
  std::map<int, float> posterior;      // hypothesis id -> probability (Bayes filter)
  std::map<int, float> likelihood;     // after normalisation
  std::map<int, float> rawLikelihood;  // before normalisation
  std::map<int, int> weights;          // WM node id -> weight
  std::map<int, std::string> labels;   // node id -> label
  std::vector<int> wmState;            // ids of the Working Memory
  std::map<int, int> reducedIds;       // Mem/ReduceGraph: node -> the older node it was merged into
  std::map<int, Transform> reducedTransforms;  // ... -> its pose in that node's frame (from the graph)
  std::map<int, Transform> poses;      // optimised poses of the local map
  std::multimap<int, Link> constraints;

 private:
  std::map<std::string, float> data_;
};

}  // namespace rtabmap
