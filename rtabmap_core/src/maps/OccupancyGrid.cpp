// The global 2D occupancy grid: what to apply when the graph changes, and which re-assembly path
// to take (see OccupancyGrid.h). The cell operations are in GridStorage.
#include "rtabmap_core/maps/OccupancyGrid.h"

#include <time.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>

#include "GraphChanges.h"
#include "LocalGridCheck.h"
#include "GridStorage.h"
#include "SensorModel.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/maps/Cloud.h"

namespace rtabmap {

const char* pathName(GridUpdateSummary::Path path) {
  switch (path) {
    case GridUpdateSummary::Path::kNone: return "none";
    case GridUpdateSummary::Path::kIncremental: return "incremental";
    case GridUpdateSummary::Path::kRegion: return "region";
    case GridUpdateSummary::Path::kFull: return "full";
  }
  return "?";
}

namespace {

using maps_detail::CellBox;
using maps_detail::GridStorage;
using maps_detail::NodeCells;
using Path = GridUpdateSummary::Path;

// Work units of the cost model: a cell of a node applied (transformed, maybe written) or a cell
// of the map cleared. Both paths start from the same prior time per unit; measurements then
// replace it.
constexpr double kPriorNsPerUnit = 4.0;
// When the moved, removed and inserted nodes hold more than this share of all cells, the region
// would be most of the map: the full path is taken without computing the region.
constexpr double kMostlyMoved = 0.5;

// CPU time of this thread (ns): the cost model measures the work, not the time other processes
// took the core.
double threadCpuNs() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e9 + ts.tv_nsec;
}

bool finiteCells(const Cloud& c) {
  for (const cv::Point3f& p : c.points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
  }
  return true;
}

}  // namespace

class OccupancyGrid::Impl {
 public:
  explicit Impl(const GlobalGridOptions& options)
      : o((options.validate(), options)),
        storage(o.cellSize, maps_detail::logit(o.probHit), maps_detail::logit(o.probMiss),
                maps_detail::logit(o.probClampingMin), maps_detail::logit(o.probClampingMax),
                o.footprintRadius > 0.0f) {
    thrL = o.occupancyThr <= 0.0f ? -std::numeric_limits<float>::infinity()
           : o.occupancyThr >= 1.0f ? std::numeric_limits<float>::infinity()
                                    : maps_detail::logit(o.occupancyThr);
  }

  GlobalGridOptions o;
  float thrL;
  std::map<int, NodeCells> cache;
  std::set<int> replaced;
  std::map<int, Transform> assembled;            // node -> pose it is assembled at
  std::map<int, std::vector<int64_t>> tilesOf;   // node -> world tiles its cells fall in there
  GridStorage storage;
  double nsFull = kPriorNsPerUnit, nsRegion = kPriorNsPerUnit;
  int fullRuns = 0, regionRuns = 0;
  Path forced = Path::kNone;

  CellBox nodeBox(int id, const Transform& pose) const {
    CellBox b = storage.boxAt(cache.at(id), pose);
    if (o.footprintRadius > 0.0f) b.unite(storage.diskBox(pose, o.footprintRadius));
    return b;
  }
  void learn(double& rate, int& runs, double ns, double units) {
    if (units <= 0) return;
    rate = (rate * runs + ns / units) / (runs + 1);
    runs = std::min(runs + 1, 20);  // a running mean that keeps following the machine
  }

  bool appendOnly(const std::map<int, Transform>& poses, std::vector<int>& appended, int& withoutGrid) const;
  GridUpdateSummary update(const std::map<int, Transform>& poses);
};

// The common update: every assembled node still there and not moved beyond UpdateError, new
// nodes after the last assembled one. Found in one pass over both sorted maps, building none
// (diffGraph builds the whole selection and target, O(nodes) allocations per update: with
// hours of mapping, thousands of nodes, most of Map_assembling). False when anything else
// changed (nothing is done then: diffGraph decides).
bool OccupancyGrid::Impl::appendOnly(const std::map<int, Transform>& poses, std::vector<int>& appended,
                                     int& withoutGrid) const {
  if (!replaced.empty() || o.maxNodes > 0 || o.altitudeDelta > 0.0f) return false;
  const int last = assembled.empty() ? std::numeric_limits<int>::min() : assembled.rbegin()->first;
  auto a = assembled.begin();
  for (const auto& [id, pose] : poses) {
    if (a != assembled.end() && a->first < id) return false;  // an assembled node left the graph
    if (a != assembled.end() && a->first == id) {
      // Same pose to the bit (nodes out of the optimised local map: most), else diffGraph's test.
      if (!(a->second == pose) && (pose.isNull() || pose.isInvalid() ||
                                   maps_detail::cellDisplacement(a->second, pose, cache.at(id).radius) > o.updateError)) {
        return false;
      }
      ++a;
      continue;
    }
    if (pose.isNull() || pose.isInvalid()) continue;  // ignored as absent
    if (!cache.count(id)) {
      ++withoutGrid;
      continue;
    }
    if (id < last) return false;  // before the last assembled: a re-assembly
    appended.push_back(id);
  }
  return a == assembled.end();
}

GridUpdateSummary OccupancyGrid::Impl::update(const std::map<int, Transform>& poses) {
  const auto start = std::chrono::steady_clock::now();
  GridUpdateSummary s;
  std::vector<int> fresh;
  int withoutGrid = 0;
  if (appendOnly(poses, fresh, withoutGrid)) {
    // Incremental: new nodes come last in the update order.
    CellBox need;
    for (int id : fresh) need.unite(nodeBox(id, poses.at(id)));
    storage.ensureCovers(need);
    std::vector<int64_t> tiles;
    for (int id : fresh) {
      const Transform& pose = poses.at(id);
      s.cellUpdates += storage.apply(cache.at(id), pose, false, &tiles);
      tilesOf[id] = tiles;
      storage.addFootprint(pose, o.footprintRadius, +1);
      assembled.emplace_hint(assembled.end(), id, pose);
    }
    s.path = fresh.empty() ? Path::kNone : Path::kIncremental;
    s.why = fresh.empty() ? "nothing changed" : std::to_string(fresh.size()) + " new node(s) appended";
    s.nodesAdded = static_cast<int>(fresh.size());
    s.nodesWithoutGrid = withoutGrid;
    s.nodesInGraph = s.nodesAssembled = static_cast<int>(assembled.size());
    s.timeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return s;
  }
  const maps_detail::GraphChanges ch = maps_detail::diffGraph(
      poses, assembled, [this](int id) { return cache.count(id) > 0; },
      [this](int id) { return cache.at(id).radius; }, o.updateError, replaced, o.maxNodes, o.altitudeDelta);
  replaced.clear();
  s.nodesInGraph = ch.selected;
  s.nodesWithoutGrid = ch.withoutGrid;
  s.nodesMoved = static_cast<int>(ch.moved.size());
  s.nodesRemoved = static_cast<int>(ch.removed.size());
  const int last = assembled.empty() ? std::numeric_limits<int>::min() : assembled.rbegin()->first;
  std::vector<int> appended, inserted;  // new nodes after / before the last assembled one
  for (int id : ch.added) (id > last ? appended : inserted).push_back(id);
  s.nodesAdded = static_cast<int>(appended.size());
  long updates = 0;
  std::vector<int64_t> tiles;
  auto applyFull = [&](int id, const Transform& pose) {
    updates += storage.apply(cache.at(id), pose, false, &tiles);
    tilesOf[id] = tiles;
    storage.addFootprint(pose, o.footprintRadius, +1);
  };

  if (!ch.graphChanged() && inserted.empty()) {
    // Incremental: new nodes come last in the update order.
    CellBox need;
    for (int id : appended) need.unite(nodeBox(id, ch.target.at(id)));
    storage.ensureCovers(need);
    for (int id : appended) applyFull(id, ch.target.at(id));
    s.path = appended.empty() ? Path::kNone : Path::kIncremental;
    s.why = appended.empty() ? "nothing changed" : std::to_string(appended.size()) + " new node(s) appended";
  } else {
    std::ostringstream why;
    why << ch.describe() << (inserted.empty() ? "" : " (" + std::to_string(inserted.size()) + " before the last)") << "; ";
    double allCells = 0.0, changedCells = 0.0;
    CellBox all;
    for (const auto& [id, pose] : ch.target) {
      allCells += double(cache.at(id).count());
      all.unite(nodeBox(id, pose));
    }
    for (const std::vector<int>* ids : std::array<const std::vector<int>*, 2>{&ch.moved, &inserted}) {
      for (int id : *ids) changedCells += double(cache.at(id).count());
    }
    for (int id : ch.removed) changedCells += cache.count(id) ? double(cache.at(id).count()) : 0.0;
    const double fullUnits = allCells + (all.empty() ? 0.0 : double(all.c1 - all.c0 + 1 + 2 * maps_detail::kTile) *
                                                                 double(all.r1 - all.r0 + 1 + 2 * maps_detail::kTile));
    s.estimatedFullUnits = fullUnits;

    Path path = Path::kFull;
    std::vector<int> replay;
    std::map<int, std::vector<int64_t>> newTiles;
    const bool forcedPath = forced == Path::kFull || forced == Path::kRegion;
    if (forcedPath && forced == Path::kFull) {
      why << "path forced";
    } else if (!forcedPath && o.fullUpdate && changedCells > kMostlyMoved * allCells) {
      why << "most cells moved";
    } else {
      // The region: the tiles the changed nodes' cells covered and now cover, exactly.
      CellBox need;
      for (const std::vector<int>* ids : std::array<const std::vector<int>*, 2>{&ch.moved, &ch.added}) {
        for (int id : *ids) need.unite(nodeBox(id, ch.target.at(id)));
      }
      storage.ensureCovers(need);
      storage.clearDirty();
      for (const std::vector<int>* ids : std::array<const std::vector<int>*, 2>{&ch.removed, &ch.moved}) {
        for (int id : *ids) for (int64_t t : tilesOf.at(id)) storage.markDirty(t);
      }
      double regionUnits = 0.0;
      for (const std::vector<int>* ids : std::array<const std::vector<int>*, 2>{&ch.moved, &inserted}) {
        for (int id : *ids) {
          newTiles[id] = storage.tilesAt(cache.at(id), ch.target.at(id));
          for (int64_t t : newTiles[id]) storage.markDirty(t);
          regionUnits += double(cache.at(id).count());  // the tile pass
        }
      }
      const std::set<int> appendedSet(appended.begin(), appended.end());
      for (const auto& [id, pose] : ch.target) {
        if (appendedSet.count(id)) continue;
        const std::vector<int64_t>& t = newTiles.count(id) ? newTiles.at(id) : tilesOf.at(id);
        if (std::any_of(t.begin(), t.end(), [&](int64_t k) { return storage.isDirty(k); })) {
          replay.push_back(id);
          regionUnits += double(cache.at(id).count());
        }
      }
      for (int id : appended) regionUnits += double(cache.at(id).count());
      regionUnits += double(storage.dirtyTiles()) * maps_detail::kTile * maps_detail::kTile;
      s.estimatedRegionUnits = regionUnits;
      if (forcedPath) {
        path = forced;
        why << "path forced";
      } else if (!o.fullUpdate) {
        path = Path::kRegion;
        why << "GridGlobal/FullUpdate is false: region path";
      } else {
        const double regionMs = regionUnits * nsRegion / 1e6, fullMs = fullUnits * nsFull / 1e6;
        path = regionMs <= fullMs ? Path::kRegion : Path::kFull;
        why << "estimated region " << regionMs << " ms vs full " << fullMs << " ms";
      }
    }
    forced = Path::kNone;
    const double cpu0 = threadCpuNs();
    if (path == Path::kRegion) {
      storage.clearDirtyCells();
      for (int id : replay) updates += storage.apply(cache.at(id), ch.target.at(id), true, nullptr);
      for (const auto& [id, t] : newTiles) tilesOf[id] = t;
      for (int id : ch.removed) storage.addFootprint(assembled.at(id), o.footprintRadius, -1);
      for (int id : ch.moved) {
        storage.addFootprint(assembled.at(id), o.footprintRadius, -1);
        storage.addFootprint(ch.target.at(id), o.footprintRadius, +1);
      }
      for (int id : inserted) storage.addFootprint(ch.target.at(id), o.footprintRadius, +1);
      for (int id : appended) applyFull(id, ch.target.at(id));
      s.nodesReplayed = static_cast<int>(replay.size() + appended.size());
      learn(nsRegion, regionRuns, threadCpuNs() - cpu0, s.estimatedRegionUnits);
    } else {
      if (all.empty()) storage.release();
      else storage.reset(all);
      for (const auto& [id, pose] : ch.target) applyFull(id, pose);
      s.nodesReplayed = static_cast<int>(ch.target.size());
      learn(nsFull, fullRuns, threadCpuNs() - cpu0, fullUnits);
    }
    for (int id : ch.removed) tilesOf.erase(id);
    s.path = path;
    s.why = why.str();
  }
  assembled = ch.target;
  s.nodesAssembled = static_cast<int>(assembled.size());
  s.cellUpdates = updates;
  s.timeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return s;
}

// -------------------------------------------------------------------- public API

OccupancyGrid::OccupancyGrid(const GlobalGridOptions& options) : impl_(std::make_unique<Impl>(options)) {}
OccupancyGrid::~OccupancyGrid() = default;
OccupancyGrid::OccupancyGrid(OccupancyGrid&&) noexcept = default;
OccupancyGrid& OccupancyGrid::operator=(OccupancyGrid&&) noexcept = default;

const GlobalGridOptions& OccupancyGrid::options() const { return impl_->o; }

bool OccupancyGrid::addLocalGrid(int nodeId, const LocalGrid& grid, std::string* why) {
  auto fail = [&](const std::string& reason) {
    if (why) *why = "node " + std::to_string(nodeId) + ": " + reason;
    return false;
  };
  const std::string problem = maps_detail::localGridProblem(grid, impl_->o.cellSize, "the map");
  if (!problem.empty()) return fail(problem);
  const Cloud obstacles = cloudFromCells(grid.obstacles);
  Cloud free = cloudFromCells(grid.ground);
  if (grid.empty.empty() || grid.empty.channels() == 2) free.append(cloudFromCells(grid.empty));
  if (!finiteCells(obstacles) || !finiteCells(free)) return fail("its local grid has NaN or infinite cells");
  if (obstacles.empty() && free.empty()) {
    return fail("its local grid has only 3D empty cells, which a 2D map does not use");
  }
  NodeCells n(obstacles.points, free.points, impl_->o.cellSize);
  if (impl_->assembled.count(nodeId)) impl_->replaced.insert(nodeId);
  impl_->cache[nodeId] = std::move(n);
  return true;
}

bool OccupancyGrid::hasLocalGrid(int nodeId) const { return impl_->cache.count(nodeId) > 0; }
void OccupancyGrid::removeLocalGrid(int nodeId) { impl_->cache.erase(nodeId); }
size_t OccupancyGrid::cachedNodes() const { return impl_->cache.size(); }
GridUpdateSummary OccupancyGrid::update(const std::map<int, Transform>& poses) { return impl_->update(poses); }
void OccupancyGrid::forceNextPath(GridUpdateSummary::Path path) { impl_->forced = path; }

GridMap OccupancyGrid::map() const {
  const int minCells = static_cast<int>(std::ceil(impl_->o.minSize / impl_->o.cellSize));
  return impl_->storage.toMap(impl_->thrL * maps_detail::kLogOddsScale, minCells, impl_->o.eroded);
}

float OccupancyGrid::probability(double x, double y) const {
  const float l = impl_->storage.logOddsAt(x, y);
  return l == maps_detail::kUnknownLogOdds ? -1.0f : 1.0f / (1.0f + std::exp(-l));
}

const std::map<int, Transform>& OccupancyGrid::assembledPoses() const { return impl_->assembled; }

size_t OccupancyGrid::memoryUsed() const {
  size_t bytes = impl_->storage.bytes();
  for (const auto& [id, n] : impl_->cache) bytes += n.bytes();
  for (const auto& [id, t] : impl_->tilesOf) bytes += t.size() * sizeof(int64_t) + sizeof(Transform) + 64;
  return bytes;
}

void OccupancyGrid::clear() {
  const GlobalGridOptions o = impl_->o;
  impl_ = std::make_unique<Impl>(o);
}

}  // namespace rtabmap
