// The global OctoMap (see OctoMap.h). liboctomap stays in this file and in RayCaster.h.
#include "rtabmap_core/maps/OctoMap.h"

#include <octomap/ColorOcTree.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <deque>
#include <fstream>
#include <set>
#include <sstream>

#include "GraphChanges.h"
#include "LocalGridCheck.h"
#include "OctreeBatch.h"
#include "RayCaster.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"

namespace rtabmap {

namespace {

using Clock = std::chrono::steady_clock;
constexpr unsigned kMaxDepth = 16;

struct NodeVoxels {
  Cloud obstacles;  // base frame
  Cloud ground;
  std::vector<cv::Point3f> empty;
  Eigen::Vector3f viewPoint = Eigen::Vector3f::Zero();
  float radius = 0.0f;
  size_t bytes() const {
    return (obstacles.size() + ground.size() + empty.size()) * sizeof(cv::Point3f) +
           (obstacles.colors.size() + ground.colors.size()) * sizeof(cv::Vec3b);
  }
};

bool finite(const Cloud& c) {
  for (const cv::Point3f& p : c.points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
  }
  return true;
}

}  // namespace

class OctoMap::Impl {
 public:
  explicit Impl(const OctoMapOptions& options) : o(options) {
    o.validate();
    reset();
  }

  OctoMapOptions o;
  std::unique_ptr<octomap::ColorOcTree> tree;
  octomap::KeySet groundKeys;  // occupied voxels whose last occupied observation was ground
  std::map<int, NodeVoxels> cache;
  std::set<int> replaced;
  std::map<int, Transform> assembled;
  maps_detail::RayCaster caster;
  maps_detail::OctreeBatch batch;
  // Buffers reused between nodes.
  std::vector<maps_detail::VoxelUpdate> updates;
  std::vector<octomap::OcTreeKey> occupied, free, keys;
  maps_detail::VoxelBitset emptyBits;
  std::vector<octomap::point3d> ends;
  bool colored = false;

  void reset() {
    tree = std::make_unique<octomap::ColorOcTree>(o.cellSize);
    tree->setProbHit(o.probHit);
    tree->setProbMiss(o.probMiss);
    tree->setClampingThresMin(o.probClampingMin);
    tree->setClampingThresMax(o.probClampingMax);
    tree->setOccupancyThres(o.occupancyThr);
    groundKeys.clear();
    colored = false;
  }

  unsigned depthOf(int depth) const { return depth <= 0 ? unsigned(o.treeDepth) : unsigned(std::min(depth, 16)); }

  // The keys of a node's empty voxels, deduplicated and in Morton code order into `free` through
  // a bitset over their box, or as updates to sort when the box is too large.
  void emptyVoxels(const std::vector<cv::Point3f>& empty, const Eigen::Isometry3f& t) {
    keys.clear();
    octomap::OcTreeKey lo, hi;
    for (const cv::Point3f& p : empty) {
      const Eigen::Vector3f w = t * Eigen::Vector3f(p.x, p.y, p.z);
      octomap::OcTreeKey k;
      if (!tree->coordToKeyChecked(octomap::point3d(w.x(), w.y(), w.z()), k)) continue;
      if (keys.empty()) lo = hi = k;
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], k[a]);
        hi[a] = std::max(hi[a], k[a]);
      }
      keys.push_back(k);
    }
    if (keys.empty()) return;
    if (emptyBits.reset(lo, hi)) {
      for (const octomap::OcTreeKey& k : keys) emptyBits.set(k);
      maps_detail::VoxelBitset::collect(emptyBits, nullptr, nullptr, free);
      return;
    }
    for (const octomap::OcTreeKey& k : keys) {
      maps_detail::VoxelUpdate u;
      u.key = k;
      updates.push_back(u);
    }
  }

  // One node: its free space first, then its occupied voxels, each voxel updated once (lazily:
  // the inner nodes are updated once per batch).
  void insert(const NodeVoxels& n, const Transform& pose, OctoMapUpdateSummary& s) {
    const Eigen::Isometry3f t = pose.toEigen().cast<float>();
    updates.clear();
    occupied.clear();
    ends.clear();
    auto addOccupied = [&](const Cloud& cloud, maps_detail::VoxelUpdate::Kind kind) {
      for (size_t i = 0; i < cloud.size(); ++i) {
        const cv::Point3f& p = cloud.points[i];
        const Eigen::Vector3f w = t * Eigen::Vector3f(p.x, p.y, p.z);
        const octomap::point3d q(w.x(), w.y(), w.z());
        maps_detail::VoxelUpdate u;
        if (!tree->coordToKeyChecked(q, u.key)) continue;
        ends.push_back(q);
        occupied.push_back(u.key);
        u.kind = kind;
        if (cloud.hasColors()) {
          u.hasColor = true;
          u.r = cloud.colors[i][0];
          u.g = cloud.colors[i][1];
          u.b = cloud.colors[i][2];
        }
        updates.push_back(u);
      }
    };
    addOccupied(n.obstacles, maps_detail::VoxelUpdate::kObstacle);
    addOccupied(n.ground, maps_detail::VoxelUpdate::kGround);

    free.clear();
    if (!n.empty.empty()) {
      emptyVoxels(n.empty, t);
    } else if (o.rayTracing) {
      const Eigen::Vector3f v = t * n.viewPoint;
      s.rayTracedPoints += static_cast<long>(
          caster.cast(*tree, octomap::point3d(v.x(), v.y(), v.z()), ends, occupied, o.rangeMax, free));
    }
    batch.apply(*tree, updates, free, tree->getProbHitLog(), tree->getProbMissLog());
    long points = 0, freeUpdates = 0;
    for (const maps_detail::VoxelUpdate& u : updates) {
      if (u.kind == maps_detail::VoxelUpdate::kFree) {
        ++freeUpdates;
        continue;
      }
      ++points;
      if (u.kind == maps_detail::VoxelUpdate::kGround) groundKeys.insert(u.key);
      else groundKeys.erase(u.key);
    }
    s.pointsInserted += points;
    s.freeVoxelUpdates += freeUpdates;
    ++s.nodesInserted;
  }

  // Kind of an occupied node found at `depth` (key of that node): obstacle if any occupied leaf
  // voxel inside is not ground.
  bool isGround(const octomap::OcTreeKey& key, unsigned depth, const octomap::KeySet* nonGroundCoarse) const {
    if (depth >= kMaxDepth) return groundKeys.count(key) > 0;
    return !nonGroundCoarse->count(octomap::computeIndexKey(kMaxDepth - depth, key));
  }
  octomap::KeySet nonGroundAt(unsigned depth) const {
    octomap::KeySet out;
    if (depth >= kMaxDepth) return out;
    for (auto it = tree->begin_leafs(), end = tree->end_leafs(); it != end; ++it) {
      if (tree->isNodeOccupied(*it) && !groundKeys.count(it.getKey())) {
        out.insert(octomap::computeIndexKey(kMaxDepth - depth, it.getKey()));
      }
    }
    return out;
  }
  VoxelState stateOf(const octomap::ColorOcTreeNode* node, const octomap::OcTreeKey& key, unsigned depth,
                     const octomap::KeySet* nonGround) const {
    if (!node) return VoxelState::kUnknown;
    if (!tree->isNodeOccupied(node)) return VoxelState::kFree;
    return isGround(key, depth, nonGround) ? VoxelState::kGround : VoxelState::kObstacle;
  }

  // GridGlobal/FloodFillDepth: free voxels (at that depth) connected to where the robot has been.
  octomap::KeySet reachableFree() const {
    octomap::KeySet visited;
    const unsigned d = unsigned(o.floodFillDepth);
    std::deque<octomap::OcTreeKey> queue;
    const int step = 1 << (kMaxDepth - d);
    for (const auto& [id, pose] : assembled) {
      const Eigen::Vector3f v = pose.toEigen().cast<float>() * cache.at(id).viewPoint;
      octomap::OcTreeKey k;
      if (!tree->coordToKeyChecked(octomap::point3d(v.x(), v.y(), v.z()), k)) continue;
      const octomap::OcTreeKey coarse = octomap::computeIndexKey(kMaxDepth - d, k);
      if (visited.insert(coarse).second) queue.push_back(coarse);
    }
    while (!queue.empty()) {
      const octomap::OcTreeKey k = queue.front();
      queue.pop_front();
      for (int axis = 0; axis < 3; ++axis) {
        for (int sign : {-1, 1}) {
          octomap::OcTreeKey n = k;
          const int v = int(n[axis]) + sign * step;
          if (v < 0 || v > 65535) continue;
          n[axis] = static_cast<octomap::key_type>(v);
          if (visited.count(n)) continue;
          const octomap::ColorOcTreeNode* node = tree->search(n, d);
          if (!node || tree->isNodeOccupied(node)) continue;
          visited.insert(n);
          queue.push_back(n);
        }
      }
    }
    return visited;
  }

  OctoMapUpdateSummary update(const std::map<int, Transform>& poses);
};

OctoMapUpdateSummary OctoMap::Impl::update(const std::map<int, Transform>& poses) {
  const Clock::time_point start = Clock::now();
  OctoMapUpdateSummary s;
  const maps_detail::GraphChanges ch = maps_detail::diffGraph(
      poses, assembled, [this](int id) { return cache.count(id) > 0; },
      [this](int id) { return cache.at(id).radius; }, o.updateError, replaced);
  replaced.clear();
  s.nodesMoved = static_cast<int>(ch.moved.size());
  s.nodesRemoved = static_cast<int>(ch.removed.size());
  s.nodesWithoutGrid = ch.withoutGrid;
  const int last = assembled.empty() ? std::numeric_limits<int>::min() : assembled.rbegin()->first;
  const bool outOfOrder = !ch.added.empty() && ch.added.front() < last;
  if (ch.graphChanged() || outOfOrder) {
    // An octree cannot move or subtract what it holds: rebuild from the cached local grids.
    reset();
    for (const auto& [id, pose] : ch.target) insert(cache.at(id), pose, s);
    s.rebuilt = true;
    s.why = ch.describe() + ": rebuilt";
  } else {
    for (int id : ch.added) insert(cache.at(id), ch.target.at(id), s);
    s.why = ch.describe();
  }
  if (s.nodesInserted > 0) {
    // No updateInnerOccupancy(): the batched descent refreshed the inner nodes it passed.
    colored = colored || std::any_of(cache.begin(), cache.end(), [](const auto& e) {
      return e.second.obstacles.hasColors() || e.second.ground.hasColors();
    });
  }
  assembled = ch.target;
  s.timeMs = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  return s;
}

// -------------------------------------------------------------------- public API

OctoMap::OctoMap(const OctoMapOptions& options) : impl_(std::make_unique<Impl>(options)) {}
OctoMap::~OctoMap() = default;
OctoMap::OctoMap(OctoMap&&) noexcept = default;
OctoMap& OctoMap::operator=(OctoMap&&) noexcept = default;

const OctoMapOptions& OctoMap::options() const { return impl_->o; }

bool OctoMap::addLocalGrid(int nodeId, const LocalGrid& grid, std::string* why) {
  auto fail = [&](const std::string& reason) {
    if (why) *why = "node " + std::to_string(nodeId) + ": " + reason;
    return false;
  };
  const std::string problem = maps_detail::localGridProblem(grid, impl_->o.cellSize, "the OctoMap");
  if (!problem.empty()) return fail(problem);
  NodeVoxels n;
  n.obstacles = cloudFromCells(grid.obstacles);
  n.ground = cloudFromCells(grid.ground);
  const Cloud empty = cloudFromCells(grid.empty);
  if (!finite(n.obstacles) || !finite(n.ground) || !finite(empty) || !grid.viewPoint.allFinite()) {
    return fail("its local grid has NaN or infinite cells");
  }
  n.empty = empty.points;
  n.viewPoint = grid.viewPoint;
  for (const Cloud* c : std::array<const Cloud*, 3>{&n.obstacles, &n.ground, &empty}) {
    for (const cv::Point3f& p : c->points) n.radius = std::max(n.radius, std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z));
  }
  if (impl_->assembled.count(nodeId)) impl_->replaced.insert(nodeId);
  impl_->cache[nodeId] = std::move(n);
  return true;
}

bool OctoMap::hasLocalGrid(int nodeId) const { return impl_->cache.count(nodeId) > 0; }
void OctoMap::removeLocalGrid(int nodeId) { impl_->cache.erase(nodeId); }
size_t OctoMap::cachedNodes() const { return impl_->cache.size(); }
OctoMapUpdateSummary OctoMap::update(const std::map<int, Transform>& poses) { return impl_->update(poses); }

VoxelState OctoMap::state(const Eigen::Vector3f& p, int depth) const {
  const Impl& m = *impl_;
  const unsigned d = m.depthOf(depth);
  octomap::OcTreeKey key;
  if (!m.tree->coordToKeyChecked(octomap::point3d(p.x(), p.y(), p.z()), key)) return VoxelState::kUnknown;
  const octomap::ColorOcTreeNode* node = m.tree->search(key, d);
  const octomap::KeySet nonGround = m.nonGroundAt(d);
  return m.stateOf(node, key, d, &nonGround);
}

OctoMapCells OctoMap::cells(int depth, bool withFrontiers) const {
  const Impl& m = *impl_;
  OctoMapCells out;
  const unsigned d = m.depthOf(depth);
  out.voxelSize = static_cast<float>(m.tree->getNodeSize(d));
  if (m.tree->size() == 0) return out;
  const octomap::KeySet nonGround = m.nonGroundAt(d);
  const bool flood = m.o.floodFillDepth > 0 && !m.assembled.empty();
  const octomap::KeySet reachable = flood ? m.reachableFree() : octomap::KeySet();
  for (auto it = m.tree->begin_leafs(d), end = m.tree->end_leafs(); it != end; ++it) {
    const octomap::OcTreeKey key = it.getKey();
    const octomap::point3d c = it.getCoordinate();
    const cv::Point3f p(c.x(), c.y(), c.z());
    const VoxelState st = m.stateOf(&*it, key, it.getDepth(), &nonGround);
    if (st == VoxelState::kFree) {
      if (flood && !reachable.count(octomap::computeIndexKey(kMaxDepth - m.o.floodFillDepth, key))) continue;
      out.empty.push_back(p);
      if (!withFrontiers) continue;
      // A frontier: a face neighbour (same size) is unknown.
      const int step = 1 << (kMaxDepth - it.getDepth());
      bool frontier = false;
      for (int axis = 0; axis < 3 && !frontier; ++axis) {
        for (int sign : {-1, 1}) {
          octomap::OcTreeKey n = key;
          const int v = int(n[axis]) + sign * step;
          if (v < 0 || v > 65535) continue;
          n[axis] = static_cast<octomap::key_type>(v);
          if (!m.tree->search(n, it.getDepth())) {
            frontier = true;
            break;
          }
        }
      }
      if (frontier) out.frontiers.push_back(p);
      continue;
    }
    const octomap::ColorOcTreeNode::Color col = it->getColor();
    Cloud& target = st == VoxelState::kGround ? out.ground : out.obstacles;
    if (m.colored) target.push_back(p, cv::Vec3b(col.r, col.g, col.b));
    else target.push_back(p);
  }
  return out;
}

GridMap OctoMap::projection2D(float minZ, float maxZ, int depth) const {
  GridMap map;
  const OctoMapCells c = cells(depth, false);
  if (c.obstacles.empty() && c.ground.empty()) return map;
  const float res = c.voxelSize;
  auto inBand = [&](const cv::Point3f& p) {
    return (minZ == 0.0f && maxZ == 0.0f) || (p.z >= minZ && p.z <= maxZ);
  };
  int c0 = INT32_MAX, r0 = INT32_MAX, c1 = INT32_MIN, r1 = INT32_MIN;
  auto extend = [&](const Cloud& cloud) {
    for (const cv::Point3f& p : cloud.points) {
      if (!inBand(p)) continue;
      const int col = int(std::floor(p.x / res)), row = int(std::floor(p.y / res));
      c0 = std::min(c0, col); c1 = std::max(c1, col);
      r0 = std::min(r0, row); r1 = std::max(r1, row);
    }
  };
  extend(c.obstacles);
  extend(c.ground);
  if (c1 < c0) return map;
  map.resolution = res;
  map.originX = double(c0) * res;
  map.originY = double(r0) * res;
  map.data = cv::Mat(r1 - r0 + 1, c1 - c0 + 1, CV_8SC1, cv::Scalar(GridMap::kUnknown));
  for (const cv::Point3f& p : c.ground.points) {
    if (!inBand(p)) continue;
    int8_t& v = map.data.at<int8_t>(int(std::floor(p.y / res)) - r0, int(std::floor(p.x / res)) - c0);
    if (v != GridMap::kOccupied) v = GridMap::kFree;
  }
  for (const cv::Point3f& p : c.obstacles.points) {
    if (!inBand(p)) continue;
    map.data.at<int8_t>(int(std::floor(p.y / res)) - r0, int(std::floor(p.x / res)) - c0) = GridMap::kOccupied;
  }
  return map;
}

namespace {
// The header of OctoMap's .bt files, naming the plain occupancy tree type so that every tool
// (octovis, octomap_server, OcTree::readBinary) reads it: the binary data is the same for any
// occupancy tree, colours are not part of it.
void writeBinaryHeader(std::ostream& s, const octomap::ColorOcTree& tree) {
  s << "# Octomap OcTree binary file\n# written by rtabmap_ros (occupancy of its ColorOcTree)\n";
  s << "id OcTree\n";
  s << "size " << tree.size() << "\n";
  s << "res " << tree.getResolution() << "\n";
  s << "data\n";
}
}  // namespace

bool OctoMap::writeBinary(const std::string& path) const {
  if (empty()) {
    RTABMAP_WARN("OctoMap: nothing to write to " << path << " (the map is empty)");
    return false;
  }
  std::ofstream f(path, std::ios::binary);
  if (!f) {
    RTABMAP_ERROR("OctoMap: cannot write " << path);
    return false;
  }
  writeBinaryHeader(f, *impl_->tree);
  impl_->tree->writeBinaryData(f);
  return static_cast<bool>(f);
}

bool OctoMap::write(const std::string& path) const {
  if (empty()) {
    RTABMAP_WARN("OctoMap: nothing to write to " << path << " (the map is empty)");
    return false;
  }
  std::ofstream f(path, std::ios::binary);
  if (!f) {
    RTABMAP_ERROR("OctoMap: cannot write " << path);
    return false;
  }
  return impl_->tree->write(f) && static_cast<bool>(f);
}

OctoMapMessage OctoMap::toMessage(bool binary) const {
  OctoMapMessage msg;
  msg.binary = binary;
  msg.resolution = impl_->tree->getResolution();
  msg.id = binary ? "OcTree" : impl_->tree->getTreeType();
  std::stringstream s(std::ios::in | std::ios::out | std::ios::binary);
  if (binary) impl_->tree->writeBinaryData(s);
  else impl_->tree->writeData(s);
  const std::string bytes = s.str();
  msg.data.assign(bytes.begin(), bytes.end());
  return msg;
}

size_t OctoMap::leafCount() const { return impl_->tree->getNumLeafNodes(); }
size_t OctoMap::memoryUsed() const {
  size_t bytes = impl_->tree->memoryUsage() + impl_->groundKeys.size() * (sizeof(octomap::OcTreeKey) + 16);
  for (const auto& [id, n] : impl_->cache) bytes += n.bytes();
  return bytes;
}
bool OctoMap::hasColor() const { return impl_->colored; }
bool OctoMap::empty() const { return impl_->tree->size() == 0; }
void OctoMap::clear() {
  impl_->reset();
  impl_->cache.clear();
  impl_->assembled.clear();
  impl_->replaced.clear();
}

}  // namespace rtabmap
