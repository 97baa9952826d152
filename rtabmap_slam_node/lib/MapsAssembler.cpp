#include "rtabmap_slam_node/MapsAssembler.h"

#include <chrono>
#include <cstring>

namespace rtabmap_slam_node {
namespace {

bool usablePose(const rtabmap::Transform& pose) { return !pose.isNull() && !pose.isInvalid(); }

// Nodes of the graph the map holds a grid of: what it assembles at this update.
template <class Map>
int assembledNodes(const Map& map, const std::map<int, rtabmap::Transform>& poses) {
  int n = 0;
  for (const auto& [id, pose] : poses) n += usablePose(pose) && map.hasLocalGrid(id) ? 1 : 0;
  return n;
}

// Gives the map the grids it lacks (fetched once per update for all maps), then updates it.
template <class Map>
auto feedAndUpdate(Map& map, const std::string& name, const std::map<int, rtabmap::Transform>& poses,
                   const std::map<int, rtabmap::LocalGrid>& fetched, std::set<int>& refused,
                   MapsUpdateSummary& summary) {
  for (const auto& [id, grid] : fetched) {
    if (map.hasLocalGrid(id) || refused.count(id)) continue;
    std::string why;
    if (!map.addLocalGrid(id, grid, &why)) {
      refused.insert(id);
      summary.refused.push_back(name + ": " + why);
    }
  }
  return map.update(poses);
}

}  // namespace

MapsAssembler::MapsAssembler(const rtabmap::ParametersMap& parameters)
    : cloudOptions_(rtabmap::CloudMapOptions::fromParameters(parameters)),
      octomapOptions_(rtabmap::OctoMapOptions::fromParameters(parameters)),
      gridOptions_(rtabmap::GlobalGridOptions::fromParameters(parameters)) {
  // Constructing each map validates its options (ParameterError naming the key).
  rtabmap::CloudMap check(cloudOptions_);
  octomapOptions_.validate();
  gridOptions_.validate();
}

MapsUpdateSummary MapsAssembler::update(const std::map<int, rtabmap::Transform>& poses, const MapsWanted& wanted,
                                        const GridSource& source) {
  MapsUpdateSummary summary;
  if (!wanted.cloud) cloud_.reset();
  if (!wanted.octomap) octomap_.reset();
  if (!wanted.grid) grid_.reset();
  if (!wanted.any()) return summary;
  const auto start = std::chrono::steady_clock::now();
  ++assemblingUpdates_;
  if (wanted.cloud && !cloud_) {
    cloud_ = std::make_unique<rtabmap::CloudMap>(cloudOptions_);
    summary.cloudChanged = true;
  }
  if (wanted.octomap && !octomap_) {
    octomap_ = std::make_unique<rtabmap::OctoMap>(octomapOptions_);
    summary.octomapChanged = true;
  }
  if (wanted.grid && !grid_) {
    grid_ = std::make_unique<rtabmap::OccupancyGrid>(gridOptions_);
    summary.gridChanged = true;
  }

  // The grids some map lacks, each asked once.
  auto lacks = [this](int id) {
    return (cloud_ && !cloud_->hasLocalGrid(id) && !refused_["cloud"].count(id)) ||
           (octomap_ && !octomap_->hasLocalGrid(id) && !refused_["octomap"].count(id)) ||
           (grid_ && !grid_->hasLocalGrid(id) && !refused_["grid"].count(id));
  };
  std::map<int, rtabmap::LocalGrid> fetched;
  for (const auto& [id, pose] : poses) {
    if (!usablePose(pose)) continue;
    ++summary.graphNodes;
    if (withoutGrid_.count(id) || !lacks(id)) continue;
    std::optional<rtabmap::LocalGrid> grid = source ? source(id) : std::nullopt;
    ++summary.gridsFetched;
    if (!grid || grid->isEmpty()) {
      withoutGrid_.insert(id);
    } else {
      fetched.emplace(id, std::move(*grid));
    }
  }

  if (cloud_) {
    const rtabmap::CloudMapUpdateSummary s = feedAndUpdate(*cloud_, "cloud map", poses, fetched, refused_["cloud"], summary);
    summary.cloudChanged |= s.nodesAdded + s.nodesMoved + s.nodesRemoved > 0;
    summary.cloudNodes = assembledNodes(*cloud_, poses);
  }
  if (octomap_) {
    const rtabmap::OctoMapUpdateSummary s =
        feedAndUpdate(*octomap_, "octomap", poses, fetched, refused_["octomap"], summary);
    summary.octomapRebuilt = s.rebuilt;
    summary.octomapChanged |= s.rebuilt || s.nodesInserted + s.nodesMoved + s.nodesRemoved > 0;
    summary.octomapNodes = assembledNodes(*octomap_, poses);
  }
  if (grid_) {
    const rtabmap::GridUpdateSummary s = feedAndUpdate(*grid_, "occupancy grid", poses, fetched, refused_["grid"], summary);
    summary.gridChanged |= s.nodesAdded + s.nodesMoved + s.nodesRemoved > 0;
    summary.gridNodes = static_cast<int>(grid_->assembledPoses().size());
  }
  summary.timeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

void MapsAssembler::invalidate(int nodeId) {
  withoutGrid_.erase(nodeId);
  for (auto& [name, ids] : refused_) ids.erase(nodeId);
  // Removed from the caches: the next update asks the source again, and a map that had the
  // node assembled re-places it with the new grid (or drops it when there is none).
  if (cloud_) cloud_->removeLocalGrid(nodeId);
  if (octomap_) octomap_->removeLocalGrid(nodeId);
  if (grid_) grid_->removeLocalGrid(nodeId);
}

namespace {

bool sameCells(const cv::Mat& a, const cv::Mat& b) {
  if (a.empty() || b.empty()) return a.empty() && b.empty();
  if (a.type() != b.type() || a.size() != b.size()) return false;
  const size_t rowBytes = a.cols * a.elemSize();
  for (int r = 0; r < a.rows; ++r) {
    if (std::memcmp(a.ptr(r), b.ptr(r), rowBytes) != 0) return false;
  }
  return true;
}

}  // namespace

bool sameLocalGrid(const rtabmap::LocalGrid& a, const rtabmap::LocalGrid& b) {
  return a.cellSize == b.cellSize && a.viewPoint == b.viewPoint && sameCells(a.ground, b.ground) &&
         sameCells(a.obstacles, b.obstacles) && sameCells(a.empty, b.empty);
}

bool LocalGridStore::add(int nodeId, const rtabmap::LocalGrid& grid) {
  if (grid.isEmpty()) return false;
  auto it = grids_.find(nodeId);
  if (it != grids_.end() && sameLocalGrid(it->second, grid)) return false;  // sent again: nothing new
  grids_[nodeId] = grid;
  return true;
}

std::optional<rtabmap::LocalGrid> LocalGridStore::get(int nodeId) const {
  auto it = grids_.find(nodeId);
  if (it == grids_.end()) return std::nullopt;
  return it->second;
}

void MapsAssembler::clear() {
  cloud_.reset();
  octomap_.reset();
  grid_.reset();
  withoutGrid_.clear();
  refused_.clear();
}

}  // namespace rtabmap_slam_node
