// The 3D map topics (MapsPublisher.h).
#include "MapsPublisher.h"

#include <nav_msgs/OccupancyGrid.h>
#include <rtabmap_ros/OctoMap.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include <optional>
#include <utility>
#include <vector>

#include "rtabmap_slam_node/MapsMessages.h"
#include "rtabmap_slam_node/SlamNodeSupport.h"

namespace rtabmap_ros {

namespace {

template <class M>
ros::Publisher latched(ros::NodeHandle& nh, const std::string& topic, const ros::SubscriberStatusCallback& onConnect) {
  return nh.advertise<M>(topic, 1, onConnect, ros::SubscriberStatusCallback(), ros::VoidConstPtr(), true);
}

bool listened(const ros::Publisher& p) { return p && p.getNumSubscribers() > 0; }

// One job's messages, made on the worker thread, published after the generation check.
struct MapsMessages {
  std::vector<std::pair<ros::Publisher, sensor_msgs::PointCloud2>> clouds;
  std::vector<std::pair<ros::Publisher, rtabmap_ros::OctoMap>> octomaps;
  std::vector<std::pair<ros::Publisher, nav_msgs::OccupancyGrid>> grids;
  std::optional<std::pair<ros::Publisher, visualization_msgs::MarkerArray>> markers;
  bool empty() const { return clouds.empty() && octomaps.empty() && grids.empty() && !markers; }
  void publish() const {
    for (const auto& [pub, msg] : clouds) pub.publish(msg);
    for (const auto& [pub, msg] : octomaps) pub.publish(msg);
    for (const auto& [pub, msg] : grids) pub.publish(msg);
    if (markers) markers->first.publish(markers->second);
  }
};

}  // namespace

MapsPublisher::MapsPublisher() : worker_(*this) {}

MapsPublisher::~MapsPublisher() { worker_.stop(); }

void MapsPublisher::advertise(ros::NodeHandle& nh, bool withGrid, const std::function<void()>& onSubscriber) {
  withGrid_ = withGrid;
  const ros::SubscriberStatusCallback onConnect = [onSubscriber](const ros::SingleSubscriberPublisher&) {
    if (onSubscriber) onSubscriber();
  };
  cloudPub_ = latched<sensor_msgs::PointCloud2>(nh, "cloud_map", onConnect);
  octomapBinaryPub_ = latched<rtabmap_ros::OctoMap>(nh, "octomap_binary", onConnect);
  octomapFullPub_ = latched<rtabmap_ros::OctoMap>(nh, "octomap_full", onConnect);
  occupiedPub_ = latched<sensor_msgs::PointCloud2>(nh, "octomap_occupied_space", onConnect);
  obstaclesPub_ = latched<sensor_msgs::PointCloud2>(nh, "octomap_obstacles", onConnect);
  groundPub_ = latched<sensor_msgs::PointCloud2>(nh, "octomap_ground", onConnect);
  emptyPub_ = latched<sensor_msgs::PointCloud2>(nh, "octomap_empty_space", onConnect);
  occupiedMarkersPub_ = latched<visualization_msgs::MarkerArray>(nh, "occupied_cells_vis_array", onConnect);
  octomapGridPub_ = latched<nav_msgs::OccupancyGrid>(nh, "octomap_grid", onConnect);
  if (withGrid_) gridPub_ = latched<nav_msgs::OccupancyGrid>(nh, "grid_map", onConnect);
}

void MapsPublisher::setParameters(const rtabmap::ParametersMap& parameters) {
  rtabmap_slam_node::MapsAssembler fresh(parameters);  // throws before anything changes
  worker_.clear(std::move(fresh));
  handover_.clear();
}

void MapsPublisher::clear() {
  worker_.clear();
  handover_.clear();
}

bool MapsPublisher::octomapCellsWanted() const {
  return listened(occupiedPub_) || listened(obstaclesPub_) || listened(groundPub_) || listened(emptyPub_) ||
         listened(occupiedMarkersPub_);
}

rtabmap_slam_node::MapsWanted MapsPublisher::wanted() const {
  rtabmap_slam_node::MapsWanted w;
  w.cloud = listened(cloudPub_);
  w.octomap = listened(octomapBinaryPub_) || listened(octomapFullPub_) || listened(octomapGridPub_) ||
              octomapCellsWanted();
  w.grid = withGrid_ && listened(gridPub_);
  return w;
}

void MapsPublisher::submit(const std::map<int, rtabmap::Transform>& poses,
                           const rtabmap_slam_node::MapsAssembler::GridSource& source, const std_msgs::Header& header,
                           bool force) {
  std::optional<rtabmap_slam_node::MapsJob> job = handover_.makeJob(poses, wanted(), force, source);
  if (!job) return;
  job->frameId = header.frame_id;
  job->stampNs = static_cast<std::int64_t>(header.stamp.toNSec());
  worker_.submit(std::move(*job));
}

std::function<void()> MapsPublisher::prepare(const rtabmap_slam_node::MapsAssembler& maps,
                                             const rtabmap_slam_node::MapsUpdateSummary& summary,
                                             const rtabmap_slam_node::MapsJob& job) {
  for (const std::string& why : summary.refused) ROS_WARN("maps: %s; the node is left out of that map.", why.c_str());
  std_msgs::Header header;
  header.frame_id = job.frameId;
  header.stamp.fromNSec(static_cast<std::uint64_t>(job.stampNs));
  // An unchanged map's latched message is still right: not made again.
  const rtabmap::CloudMap* cloud = job.force || summary.cloudChanged ? maps.cloudMap() : nullptr;
  const rtabmap::OctoMap* octomap = job.force || summary.octomapChanged ? maps.octoMap() : nullptr;
  const rtabmap::OccupancyGrid* grid = job.force || summary.gridChanged ? maps.occupancyGrid() : nullptr;
  auto out = std::make_shared<MapsMessages>();
  if (cloud) out->clouds.emplace_back(cloudPub_, rtabmap_slam_node::cloudToMsg(cloud->cloud(), header));
  if (octomap) {
    if (listened(octomapBinaryPub_)) {
      out->octomaps.emplace_back(octomapBinaryPub_,
                                 rtabmap_slam_node::octoMapToMsg(octomap->toMessage(true), header));
    }
    if (listened(octomapFullPub_)) {
      out->octomaps.emplace_back(octomapFullPub_, rtabmap_slam_node::octoMapToMsg(octomap->toMessage(false), header));
    }
    const int depth = maps.octomapTreeDepth();
    if (listened(octomapGridPub_)) {
      const rtabmap::GridMap projected = octomap->projection2D(0.0f, 0.0f, depth);
      if (!projected.empty()) out->grids.emplace_back(octomapGridPub_, rtabmap_slam_node::gridMapToMsg(projected, header));
    }
    if (octomapCellsWanted()) {
      const rtabmap::OctoMapCells cells = octomap->cells(depth, false);
      const std::pair<const ros::Publisher*, const rtabmap::Cloud*> views[] = {
          {&obstaclesPub_, &cells.obstacles}, {&groundPub_, &cells.ground}, {&emptyPub_, &cells.empty}};
      if (listened(occupiedPub_)) {
        out->clouds.emplace_back(occupiedPub_,
                                 rtabmap_slam_node::cloudToMsg(rtabmap_slam_node::occupiedVoxels(cells), header));
      }
      for (const auto& [pub, points] : views) {
        if (listened(*pub)) out->clouds.emplace_back(*pub, rtabmap_slam_node::cloudToMsg(*points, header));
      }
      if (listened(occupiedMarkersPub_)) {
        out->markers.emplace(occupiedMarkersPub_, rtabmap_slam_node::occupiedCellsMarkers(cells, header));
      }
    }
  }
  if (grid) {
    const rtabmap::GridMap map = grid->map();
    if (!map.empty()) out->grids.emplace_back(gridPub_, rtabmap_slam_node::gridMapToMsg(map, header));
  }
  if (out->empty()) return nullptr;
  return [out] { out->publish(); };
}

void MapsPublisher::addStatistics(rtabmap_ros::Info& info) const {
  // The worker's last completed assembly: the update that asked for it may be this one or an
  // earlier one (its job was still under way, or merged into a later one, when info was sent).
  const rtabmap_slam_node::MapsWorkerStats s = worker_.stats();
  const std::pair<const char*, double> entries[] = {
      {"Maps/Assembling_updates/", static_cast<double>(s.assemblingUpdates)},  // since start; 0 while nobody listened
      {"Maps/Coalesced_jobs/", static_cast<double>(s.coalescedJobs)},  // since start: updates merged into a later job
      {"Maps/Graph_nodes/", s.last.graphNodes},  // of the update the assembly was for
      {"Maps/Grids_fetched/", s.last.gridsFetched},
      {"Maps/Cloud_nodes/", s.last.cloudNodes},
      {"Maps/OctoMap_nodes/", s.last.octomapNodes},
      {"Maps/OctoMap_rebuilt/", s.last.octomapRebuilt ? 1.0 : 0.0},
      {"Maps/Time/ms", s.last.timeMs}};  // assembling, making the messages and publishing them
  for (const auto& [key, value] : entries) {
    info.statsKeys.push_back(key);
    info.statsValues.push_back(static_cast<float>(value));
  }
}

}  // namespace rtabmap_ros
