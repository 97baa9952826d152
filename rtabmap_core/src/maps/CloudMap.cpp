// The assembled point-cloud map (see CloudMap.h).
#include "rtabmap_core/maps/CloudMap.h"

#include <chrono>
#include <cmath>
#include <set>
#include <sstream>

#include "GraphChanges.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/maps/LocalGridStages.h"

namespace rtabmap {

CloudMapOptions CloudMapOptions::fromParameters(const ParametersMap& p) {
  CloudMapOptions o;
  o.voxelSize = Parameters::getFloat(p, Parameters::kGridCellSize());
  o.updateError = Parameters::getFloat(p, Parameters::kGridGlobalUpdateError());
  return o;
}

bool CloudMapOptions::IsValid(std::string* why) const {
  std::ostringstream r;
  if (!(std::isfinite(voxelSize) && voxelSize >= 0.0f)) {
    r << "Grid/CellSize (the cloud map's voxel size) must be >= 0 (got " << voxelSize << ")";
  } else if (!ground && !obstacles) {
    r << "the cloud map needs ground or obstacles (both are off)";
  } else if (!(std::isfinite(updateError) && updateError >= 0.0f)) {
    r << "GridGlobal/UpdateError must be >= 0 (got " << updateError << ")";
  }
  const std::string text = r.str();
  if (why) *why = text;
  return text.empty();
}

class CloudMap::Impl {
 public:
  explicit Impl(const CloudMapOptions& options) : o(options) {
    std::string why;
    if (!o.IsValid(&why)) throw ParameterError("invalid cloud map options: " + why);
  }
  CloudMapOptions o;
  struct Node {
    Cloud local;
    float radius = 0.0f;
  };
  std::map<int, Node> cache;
  std::set<int> replaced;
  std::map<int, Transform> assembled;
  std::map<int, Cloud> world;  // each assembled node's points in the map frame
  mutable Cloud filtered;
  mutable bool dirty = true;
};

CloudMap::CloudMap(const CloudMapOptions& options) : impl_(std::make_unique<Impl>(options)) {}
CloudMap::~CloudMap() = default;
CloudMap::CloudMap(CloudMap&&) noexcept = default;
CloudMap& CloudMap::operator=(CloudMap&&) noexcept = default;

bool CloudMap::addLocalGrid(int nodeId, const LocalGrid& grid, std::string* why) {
  auto fail = [&](const std::string& reason) {
    if (why) *why = "node " + std::to_string(nodeId) + ": " + reason;
    return false;
  };
  for (const cv::Mat* m : {&grid.ground, &grid.obstacles}) {
    if (!isCellMatrix(*m)) return fail("its local grid cells are not CV_32FC2/3/4 1xN matrices");
  }
  Impl::Node n;
  if (impl_->o.obstacles) n.local.append(cloudFromCells(grid.obstacles));
  if (impl_->o.ground) n.local.append(cloudFromCells(grid.ground));
  if (n.local.empty()) return fail("its local grid has no obstacle or ground cell");
  for (const cv::Point3f& p : n.local.points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      return fail("its local grid has NaN or infinite cells");
    }
    n.radius = std::max(n.radius, std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z));
  }
  if (impl_->assembled.count(nodeId)) impl_->replaced.insert(nodeId);
  impl_->cache[nodeId] = std::move(n);
  return true;
}

bool CloudMap::hasLocalGrid(int nodeId) const { return impl_->cache.count(nodeId) > 0; }
void CloudMap::removeLocalGrid(int nodeId) { impl_->cache.erase(nodeId); }

CloudMapUpdateSummary CloudMap::update(const std::map<int, Transform>& poses) {
  const auto start = std::chrono::steady_clock::now();
  Impl& m = *impl_;
  CloudMapUpdateSummary s;
  const maps_detail::GraphChanges ch = maps_detail::diffGraph(
      poses, m.assembled, [&m](int id) { return m.cache.count(id) > 0; },
      [&m](int id) { return m.cache.at(id).radius; }, m.o.updateError, m.replaced);
  m.replaced.clear();
  for (int id : ch.removed) m.world.erase(id);
  for (int id : ch.moved) m.world[id] = transformCloud(m.cache.at(id).local, ch.target.at(id));
  for (int id : ch.added) m.world[id] = transformCloud(m.cache.at(id).local, ch.target.at(id));
  s.nodesAdded = static_cast<int>(ch.added.size());
  s.nodesMoved = static_cast<int>(ch.moved.size());
  s.nodesRemoved = static_cast<int>(ch.removed.size());
  s.nodesWithoutGrid = ch.withoutGrid;
  if (s.nodesAdded || s.nodesMoved || s.nodesRemoved) m.dirty = true;
  m.assembled = ch.target;
  s.timeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return s;
}

const Cloud& CloudMap::cloud() const {
  Impl& m = *impl_;
  if (m.dirty) {
    Cloud all;
    size_t n = 0;
    bool colours = true;
    for (const auto& [id, c] : m.world) {
      n += c.size();
      colours = colours && c.hasColors();
    }
    all.reserve(n, colours);
    for (const auto& [id, c] : m.world) all.append(c);
    m.filtered = m.o.voxelSize > 0.0f ? voxelFilter(all, m.o.voxelSize) : all;
    m.dirty = false;
  }
  return m.filtered;
}

size_t CloudMap::rawPoints() const {
  size_t n = 0;
  for (const auto& [id, c] : impl_->world) n += c.size();
  return n;
}

}  // namespace rtabmap
