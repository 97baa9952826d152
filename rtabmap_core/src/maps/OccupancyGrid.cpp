// The global 2D occupancy grid: what to apply when the graph changes, and which re-assembly path
// to take (see OccupancyGrid.h). The cell operations are in GridStorage.
#include "rtabmap_core/maps/OccupancyGrid.h"

#include <time.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <list>
#include <optional>
#include <unordered_map>
#include <set>
#include <sstream>

#include "GraphChanges.h"
#include "LocalGridCheck.h"
#include "GridStorage.h"
#include "SensorModel.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"
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
// Reading an evicted node's cells back (the loader's database read and decompression, then the
// compact encoding), per cell, before any measurement: about 10x applying one.
constexpr double kPriorNsPerLoadedCell = 40.0;
// Evicted nodes read back per loader call: a few hundred KB of local grids in flight.
constexpr size_t kLoadBatch = 64;

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

// A local grid's cells as the map keeps them, or nullopt with the reason: the one conversion
// for grids added and grids read back after eviction, so both give the same cells to the bit.
std::optional<NodeCells> nodeCellsOf(const LocalGrid& grid, float cellSize, std::string& why) {
  why = maps_detail::localGridProblem(grid, cellSize, "the map");
  if (!why.empty()) return std::nullopt;
  const Cloud obstacles = cloudFromCells(grid.obstacles);
  Cloud free = cloudFromCells(grid.ground);
  if (grid.empty.empty() || grid.empty.channels() == 2) free.append(cloudFromCells(grid.empty));
  if (!finiteCells(obstacles) || !finiteCells(free)) {
    why = "its local grid has NaN or infinite cells";
    return std::nullopt;
  }
  if (obstacles.empty() && free.empty()) {
    why = "its local grid has only 3D empty cells, which a 2D map does not use";
    return std::nullopt;
  }
  return NodeCells(obstacles.points, free.points, cellSize);
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
  std::map<int, maps_detail::TileSet> tilesOf;  // node -> world tiles its cells fall in there
  GridStorage storage;
  double nsFull = kPriorNsPerUnit, nsRegion = kPriorNsPerUnit, nsLoad = kPriorNsPerLoadedCell;
  int fullRuns = 0, regionRuns = 0, loadRuns = 0;
  Path forced = Path::kNone;
  int deferred = 0;  // updates whose graph changes wait (GridGlobal/ReassemblyInterval)
  OccupancyGrid::GridLoader loader;
  size_t resident = 0;  // cached nodes with their cells in RAM
  double loadCpuNs = 0.0;  // thread CPU time spent reading cells back in this update
  // Cells of evicted nodes kept anyway (GridGlobal/LtmCacheSize), least recently used first.
  struct Recent {
    NodeCells cells;
    std::list<int>::iterator position;
  };
  std::unordered_map<int, Recent> recent;
  std::list<int> recentOrder;
  size_t recentBytes = 0;
  size_t recentBudget = static_cast<size_t>(double(o.ltmCacheSize) * 1024.0 * 1024.0);
  // Cells read back and remembered during this update: at most half the budget, so that a
  // re-assembly replaying more old nodes than the budget holds (the same ones update after
  // update, in the same order) keeps a part of them rather than pushing each out before its
  // next use.
  size_t rememberedNow = 0;
  // Long-Term Memory layers (see OccupancyGrid.h): per world tile, the log-odds of the nodes in
  // it whose layer key is below `capture`, composed when the tile was last re-assembled.
  struct Layer {
    std::vector<int16_t> cells;  // maps_detail::kTileCells
    uint32_t capture = 0;
  };
  std::unordered_map<int64_t, Layer> layers;
  uint32_t evictions = 0;  // serial of the last eviction: layer keys and captures

  // A node whose cells change (moved, removed, replaced) leaves the layers it is in: they are
  // dropped (their tiles are re-assembled from scratch next), and it is replayed from then on
  // until it is evicted again. A retrieved node optimised with the Working Memory takes this
  // path once, not at every update.
  void leaveLayers(int id) {
    auto c = cache.find(id);
    if (c == cache.end() || c->second.layerKey == maps_detail::kInWorkingMemory) return;
    auto t = tilesOf.find(id);
    if (t != tilesOf.end()) {
      t->second.forEach([&](int64_t k) {
        auto l = layers.find(k);
        if (l != layers.end() && c->second.layerKey < l->second.capture) layers.erase(l);
      });
    }
    c->second.layerKey = maps_detail::kInWorkingMemory;
  }
  // A node evicted before it was assembled is in no layer yet: a key from this update's capture
  // on (see update()).
  void restamp(const std::vector<int>& added) {
    for (int id : added) {
      NodeCells& n = cache.at(id);
      if (n.layerKey != maps_detail::kInWorkingMemory) n.layerKey = ++evictions;
    }
  }
  // Whether a node writes in tile t when t is re-assembled: t has no layer or the node is not in it.
  bool writesIn(int id, int64_t t) const {
    auto l = layers.find(t);
    return l == layers.end() || cache.at(id).layerKey >= l->second.capture;
  }

  const NodeCells* recentCells(int id) {
    auto it = recent.find(id);
    if (it == recent.end()) return nullptr;
    recentOrder.splice(recentOrder.end(), recentOrder, it->second.position);  // used: newest
    return &it->second.cells;
  }
  void forgetRecent(int id) {
    auto it = recent.find(id);
    if (it == recent.end()) return;
    recentBytes -= it->second.cells.bytes();
    recentOrder.erase(it->second.position);
    recent.erase(it);
  }
  void remember(int id, NodeCells&& n) {
    forgetRecent(id);
    const size_t b = n.bytes();
    if (b > recentBudget) return;
    recentBytes += b;
    recentOrder.push_back(id);
    recent.emplace(id, Recent{std::move(n), std::prev(recentOrder.end())});
    while (recentBytes > recentBudget) forgetRecent(recentOrder.front());
  }

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
  // The nodes of `poses` after the last assembled one that can be appended (a usable pose and a
  // cached grid), in id order.
  void newAfterLast(const std::map<int, Transform>& poses, std::vector<int>& appended, int& withoutGrid) const;
  // Applies new nodes on top of the map, the last in the update order (the incremental path).
  void appendNodes(const std::vector<int>& ids, const std::map<int, Transform>& poses, GridUpdateSummary& s);
  GridUpdateSummary update(const std::map<int, Transform>& poses);
  // Re-assembles the dirty tiles: each starts from its layer (or unknown), the evicted nodes not
  // in it yet are applied and the result becomes its layer, then the other nodes. `replay`: the
  // nodes (id order) with a dirty tile they write in; `retiled`: those whose tiles to record.
  long reassembleDirtyTiles(const std::vector<int>& replay, const std::map<int, Transform>& target,
                            const std::set<int>& retiled, uint32_t capture, GridUpdateSummary& s);

  // The cells of evicted nodes, read back through the loader (those it did not give back, or
  // gave back different, are left out and counted).
  std::map<int, NodeCells> load(const std::vector<int>& ids, GridUpdateSummary& s);
  // f(id, cells) for each id, in order. Evicted nodes' cells come from the recent ones or are
  // read back kLoadBatch at a time (then kept among the recent ones); a node not read back gets
  // no cells (it writes nothing).
  template <class F>
  void withCells(const std::vector<int>& ids, GridUpdateSummary& s, F&& f) {
    static const NodeCells kNone;
    size_t i = 0;
    while (i < ids.size()) {
      std::vector<int> toLoad;
      size_t j = i;
      for (; j < ids.size(); ++j) {
        if (!cache.at(ids[j]).evicted() || recent.count(ids[j])) continue;
        if (toLoad.size() == kLoadBatch) break;
        toLoad.push_back(ids[j]);
      }
      std::map<int, NodeCells> loaded = load(toLoad, s);
      for (; i < j; ++i) {
        const NodeCells& n = cache.at(ids[i]);
        if (!n.evicted()) {
          f(ids[i], n);
        } else if (const NodeCells* r = recentCells(ids[i])) {
          f(ids[i], *r);
        } else {
          auto it = loaded.find(ids[i]);
          f(ids[i], it == loaded.end() ? kNone : it->second);
        }
      }
      // Only now: remembering may push out recent cells the batch above used.
      for (auto& [id, n] : loaded) {
        if (rememberedNow + n.bytes() > recentBudget / 2) break;
        rememberedNow += n.bytes();
        remember(id, std::move(n));
      }
    }
  }
  // Cells a path would read back (evicted, not among the recent ones).
  double evictedCells(const std::vector<int>& ids) const {
    double cells = 0.0;
    for (int id : ids) {
      const NodeCells& n = cache.at(id);
      if (n.evicted() && !recent.count(id)) cells += double(n.count());
    }
    return cells;
  }
};

std::map<int, NodeCells> OccupancyGrid::Impl::load(const std::vector<int>& ids, GridUpdateSummary& s) {
  std::map<int, NodeCells> out;
  if (ids.empty()) return out;
  const auto start = std::chrono::steady_clock::now();
  const double cpu0 = threadCpuNs();
  std::map<int, LocalGrid> grids;
  std::string failure;
  try {
    if (loader) grids = loader(ids);
  } catch (const std::exception& e) {
    failure = e.what();
  }
  double cells = 0.0;
  int missing = 0;
  for (int id : ids) {
    auto g = grids.find(id);
    std::string why = g == grids.end() ? "not found" : "";
    std::optional<NodeCells> n;
    if (g != grids.end()) n = nodeCellsOf(g->second, o.cellSize, why);
    if (n && n->count() != cache.at(id).count()) {
      why = "its local grid read back has " + std::to_string(n->count()) + " cells, not " +
            std::to_string(cache.at(id).count());
      n.reset();
    }
    if (!n) {
      if (missing++ == 0) {
        RTABMAP_WARN("global grid: the cells of node " << id << " could not be read back (" << why
                     << (failure.empty() ? "" : ": " + failure) << "); it is left out of the re-assembled map");
      }
      continue;
    }
    cells += double(n->count());
    out.emplace(id, std::move(*n));
  }
  grids.clear();
  s.nodesLoaded += static_cast<int>(out.size());
  s.nodesNotLoaded += missing;
  const double cpu = threadCpuNs() - cpu0;
  loadCpuNs += cpu;
  learn(nsLoad, loadRuns, cpu, cells);
  s.loadMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return out;
}

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
      if (!cache.count(id)) return false;  // its grid was removed: it leaves the map
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

void OccupancyGrid::Impl::newAfterLast(const std::map<int, Transform>& poses, std::vector<int>& appended,
                                       int& withoutGrid) const {
  auto it = assembled.empty() ? poses.begin() : poses.upper_bound(assembled.rbegin()->first);
  for (; it != poses.end(); ++it) {
    if (it->second.isNull() || it->second.isInvalid()) continue;  // ignored as absent
    if (!cache.count(it->first)) {
      ++withoutGrid;
      continue;
    }
    appended.push_back(it->first);
  }
}

void OccupancyGrid::Impl::appendNodes(const std::vector<int>& ids, const std::map<int, Transform>& poses,
                                      GridUpdateSummary& s) {
  restamp(ids);
  CellBox need;
  for (int id : ids) need.unite(nodeBox(id, poses.at(id)));
  storage.ensureCovers(need);
  std::vector<int64_t> tiles;
  withCells(ids, s, [&](int id, const NodeCells& n) {
    const Transform& pose = poses.at(id);
    s.cellUpdates += storage.apply(n, pose, false, &tiles);
    tilesOf[id] = maps_detail::TileSet(tiles);
    storage.addFootprint(pose, o.footprintRadius, +1);
    assembled.emplace_hint(assembled.end(), id, pose);
  });
  s.nodesAdded = static_cast<int>(ids.size());
}

GridUpdateSummary OccupancyGrid::Impl::update(const std::map<int, Transform>& poses) {
  const auto start = std::chrono::steady_clock::now();
  GridUpdateSummary s;
  rememberedNow = 0;
  std::vector<int> fresh;
  int withoutGrid = 0;
  auto finish = [&] {
    s.nodesWithoutGrid = withoutGrid;
    s.nodesInGraph = s.nodesAssembled = static_cast<int>(assembled.size());
    s.timeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return s;
  };
  if (appendOnly(poses, fresh, withoutGrid)) {
    // Incremental: new nodes come last in the update order. Nothing else differs from the
    // graph, so nothing waits either (changes that were deferred have been undone).
    deferred = 0;
    appendNodes(fresh, poses, s);
    s.path = fresh.empty() ? Path::kNone : Path::kIncremental;
    s.why = fresh.empty() ? "nothing changed" : std::to_string(fresh.size()) + " new node(s) appended";
    return finish();
  }
  // Deferred re-assembly (see OccupancyGrid.h): the moved nodes keep the pose they are assembled
  // at, so the next update's difference holds this one's changes too. Only while new nodes come
  // (an update without one: the robot stands, or a link was added by hand), and not with
  // MaxNodes or AltitudeDelta, whose selection changes with every new node.
  fresh.clear();
  withoutGrid = 0;
  newAfterLast(poses, fresh, withoutGrid);
  if (!fresh.empty() && deferred + 1 < o.reassemblyInterval && forced == Path::kNone && o.maxNodes == 0 &&
      o.altitudeDelta <= 0.0f) {
    ++deferred;
    appendNodes(fresh, poses, s);
    s.path = Path::kIncremental;
    s.updatesDeferred = deferred;
    s.why = std::to_string(fresh.size()) + " new node(s) appended; the graph's other changes wait (" +
            std::to_string(deferred) + " update(s) of GridGlobal/ReassemblyInterval " +
            std::to_string(o.reassemblyInterval) + ")";
    return finish();
  }
  deferred = 0;
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
  // The layers this update captures hold the nodes evicted before it; the new ones come after.
  const uint32_t capture = evictions + 1;
  restamp(ch.added);
  long updates = 0;
  std::vector<int64_t> tiles;
  auto applyFullAll = [&](const std::vector<int>& ids) {
    withCells(ids, s, [&](int id, const NodeCells& n) {
      const Transform& pose = ch.target.at(id);
      updates += storage.apply(n, pose, false, &tiles);
      tilesOf[id] = maps_detail::TileSet(tiles);
      storage.addFootprint(pose, o.footprintRadius, +1);
    });
  };
  loadCpuNs = 0.0;

  if (!ch.graphChanged() && inserted.empty()) {
    // Incremental: new nodes come last in the update order.
    CellBox need;
    for (int id : appended) need.unite(nodeBox(id, ch.target.at(id)));
    storage.ensureCovers(need);
    applyFullAll(appended);
    s.path = appended.empty() ? Path::kNone : Path::kIncremental;
    s.why = appended.empty() ? "nothing changed" : std::to_string(appended.size()) + " new node(s) appended";
  } else {
    for (const std::vector<int>* ids : std::array<const std::vector<int>*, 2>{&ch.moved, &ch.removed}) {
      for (int id : *ids) leaveLayers(id);
    }
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
    const std::set<int> appendedSet(appended.begin(), appended.end());
    std::set<int> retiled(ch.moved.begin(), ch.moved.end());
    retiled.insert(inserted.begin(), inserted.end());
    // The full path replays the nodes that write in some tile (all of them but those in the
    // layers of every tile they are in; moved and new nodes are in none).
    std::vector<int> fullReplay;
    double fullCells = 0.0;
    // The lambdas below capture the structured binding `id` by init-capture: C++17 does not let
    // a lambda name a structured binding otherwise (GCC allows it, clang, the sanitizer and fuzz
    // builds' compiler, refuses it).
    for (const auto& [id, pose] : ch.target) {
      if (appendedSet.count(id)) continue;
      const auto t = tilesOf.find(id);
      if (retiled.count(id) || t == tilesOf.end() ||
          t->second.any([&, id = id](int64_t k) { return writesIn(id, k); })) {
        fullReplay.push_back(id);
        fullCells += double(cache.at(id).count());
      }
    }
    for (int id : appended) fullCells += double(cache.at(id).count());
    const double fullUnits = fullCells + (all.empty() ? 0.0 : double(all.c1 - all.c0 + 1 + 2 * maps_detail::kTile) *
                                                                 double(all.r1 - all.r0 + 1 + 2 * maps_detail::kTile));
    s.estimatedFullUnits = fullUnits;

    Path path = Path::kFull;
    std::vector<int> replay;
    int regionInLayers = 0;
    std::map<int, maps_detail::TileSet> newTiles;
    const double fullLoadCells = evictedCells(fullReplay) + evictedCells(appended);
    double regionLoadCells = 0.0;
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
        for (int id : *ids) tilesOf.at(id).forEach([&](int64_t t) { storage.markDirty(t); });
      }
      double regionUnits = 0.0;
      const std::vector<int> retiledIds(retiled.begin(), retiled.end());
      regionLoadCells += evictedCells(retiledIds);
      withCells(retiledIds, s, [&](int id, const NodeCells& n) {
        const std::vector<int64_t> tiles = storage.tilesAt(n, ch.target.at(id));
        for (int64_t t : tiles) storage.markDirty(t);
        newTiles[id] = maps_detail::TileSet(tiles);
        regionUnits += double(n.count());  // the tile pass
      });
      for (const auto& [id, pose] : ch.target) {
        if (appendedSet.count(id)) continue;
        const maps_detail::TileSet& t = newTiles.count(id) ? newTiles.at(id) : tilesOf.at(id);
        if (t.any([&, id = id](int64_t k) { return storage.isDirty(k) && writesIn(id, k); })) {
          replay.push_back(id);
          regionUnits += double(cache.at(id).count());
        } else if (t.any([&](int64_t k) { return storage.isDirty(k); })) {
          ++regionInLayers;  // in the region, but in the layers of all its tiles there
        }
      }
      for (int id : appended) regionUnits += double(cache.at(id).count());
      regionUnits += double(storage.dirtyTiles()) * maps_detail::kTileCells;
      regionLoadCells += evictedCells(replay) + evictedCells(appended);
      s.estimatedRegionUnits = regionUnits;
      if (forcedPath) {
        path = forced;
        why << "path forced";
      } else if (!o.fullUpdate) {
        path = Path::kRegion;
        why << "GridGlobal/FullUpdate is false: region path";
      } else {
        const double regionMs = (regionUnits * nsRegion + regionLoadCells * nsLoad) / 1e6;
        const double fullMs = (fullUnits * nsFull + fullLoadCells * nsLoad) / 1e6;
        path = regionMs <= fullMs ? Path::kRegion : Path::kFull;
        why << "estimated region " << regionMs << " ms vs full " << fullMs << " ms";
      }
    }
    forced = Path::kNone;
    const double cpu0 = threadCpuNs();
    loadCpuNs = 0.0;  // the cost model learns the paths' own work, the reading back apart
    if (path == Path::kRegion) {
      for (const auto& [id, t] : newTiles) tilesOf[id] = t;
      updates += reassembleDirtyTiles(replay, ch.target, {}, capture, s);
      for (int id : ch.removed) storage.addFootprint(assembled.at(id), o.footprintRadius, -1);
      for (int id : ch.moved) {
        storage.addFootprint(assembled.at(id), o.footprintRadius, -1);
        storage.addFootprint(ch.target.at(id), o.footprintRadius, +1);
      }
      for (int id : inserted) storage.addFootprint(ch.target.at(id), o.footprintRadius, +1);
      applyFullAll(appended);
      s.nodesReplayed = static_cast<int>(replay.size() + appended.size());
      s.nodesInLayers = regionInLayers;
      learn(nsRegion, regionRuns, threadCpuNs() - cpu0 - loadCpuNs, s.estimatedRegionUnits);
    } else {
      if (all.empty()) storage.release();
      else storage.reset(all);
      storage.markAllDirty();
      std::vector<int> replayAll = fullReplay;
      replayAll.insert(replayAll.end(), appended.begin(), appended.end());
      std::set<int> newlyTiled = retiled;
      newlyTiled.insert(appended.begin(), appended.end());
      updates += reassembleDirtyTiles(replayAll, ch.target, newlyTiled, capture, s);
      for (const auto& [id, pose] : ch.target) storage.addFootprint(pose, o.footprintRadius, +1);
      s.nodesReplayed = static_cast<int>(replayAll.size());
      s.nodesInLayers = static_cast<int>(ch.target.size()) - s.nodesReplayed;
      learn(nsFull, fullRuns, threadCpuNs() - cpu0 - loadCpuNs, fullUnits);
    }
    if (s.nodesLoaded > 0) why << "; " << s.nodesLoaded << " evicted node(s) read back in " << s.loadMs << " ms";
    if (s.nodesInLayers > 0) why << "; " << s.nodesInLayers << " node(s) in the tiles' Long-Term Memory layers";
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

long OccupancyGrid::Impl::reassembleDirtyTiles(const std::vector<int>& replay, const std::map<int, Transform>& target,
                                               const std::set<int>& retiled, uint32_t capture,
                                               GridUpdateSummary& s) {
  // Nodes evicted before this update (key below `capture`) and not yet in the layer of a tile
  // they write in go into it; the nodes after them (Working Memory, moved, new) stay out of it.
  std::vector<int> intoLayers, onTop;
  for (int id : replay) (cache.at(id).layerKey < capture ? intoLayers : onTop).push_back(id);
  storage.clearDirtyCells();
  std::set<int64_t> layered;
  for (int64_t t : storage.dirtyTileKeys()) {
    auto l = layers.find(t);
    if (l == layers.end()) continue;
    storage.restoreTile(t, l->second.cells);
    storage.setGate(t, l->second.capture);
    layered.insert(t);
  }
  long updates = 0;
  std::vector<int64_t> tiles;
  // On the full path every tile is dirty: a node that every gate lets through (no tile started
  // from a layer, so every gate is open; or a key from the capture on) writes all its cells, and
  // the unmasked apply does that without a gate test per cell (Intel, 1,000 nodes: 70 -> 52 ms).
  const bool everyTileDirty = storage.dirtyTiles() == storage.tiles();
  const bool noLayerRestored = layered.empty();
  auto applyMasked = [&](int id, const NodeCells& n) {
    const uint32_t key = cache.at(id).layerKey;
    const bool open = everyTileDirty && (noLayerRestored || key >= capture);
    updates += storage.apply(n, target.at(id), !open, &tiles, key);
    // Every dirty tile is open to a retiled node: `tiles` are all of its tiles.
    if (retiled.count(id)) tilesOf[id] = maps_detail::TileSet(tiles);
  };
  const int notLoaded = s.nodesNotLoaded;
  withCells(intoLayers, s, [&](int id, const NodeCells& n) {
    applyMasked(id, n);
    layered.insert(tiles.begin(), tiles.end());
  });
  // A node the loader did not give back would be missing from the layer for good: the layers are
  // left as they were (this update's map misses it, the next re-assembly tries again).
  if (s.nodesNotLoaded == notLoaded) {
    for (int64_t t : layered) {
      Layer& l = layers[t];
      storage.captureTile(t, l.cells);
      l.capture = capture;
      storage.setGate(t, capture);
    }
  }
  withCells(onTop, s, applyMasked);
  return updates;
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
  std::string problem;
  std::optional<NodeCells> n = nodeCellsOf(grid, impl_->o.cellSize, problem);
  if (!n) return fail(problem);
  if (impl_->assembled.count(nodeId)) impl_->replaced.insert(nodeId);
  impl_->leaveLayers(nodeId);
  auto [it, inserted] = impl_->cache.try_emplace(nodeId);
  if (inserted || it->second.evicted()) ++impl_->resident;
  it->second = std::move(*n);
  impl_->forgetRecent(nodeId);
  return true;
}

bool OccupancyGrid::hasLocalGrid(int nodeId) const { return impl_->cache.count(nodeId) > 0; }
void OccupancyGrid::removeLocalGrid(int nodeId) {
  auto it = impl_->cache.find(nodeId);
  if (it == impl_->cache.end()) return;
  impl_->leaveLayers(nodeId);
  if (!it->second.evicted()) --impl_->resident;
  impl_->cache.erase(it);
  impl_->forgetRecent(nodeId);
}
size_t OccupancyGrid::cachedNodes() const { return impl_->cache.size(); }
size_t OccupancyGrid::residentNodes() const { return impl_->resident; }
void OccupancyGrid::setGridLoader(GridLoader loader) { impl_->loader = std::move(loader); }

bool OccupancyGrid::evictLocalGrid(int nodeId) {
  auto it = impl_->cache.find(nodeId);
  if (it == impl_->cache.end() || !impl_->loader) return false;
  NodeCells& n = it->second;
  if (!n.evicted()) {
    NodeCells cells = n;  // shares the cells, among the recent ones until others push them out
    n.evict();
    --impl_->resident;
    impl_->remember(nodeId, std::move(cells));
  }
  // Into the layers of its tiles at their next re-assembly (again, for a retrieved node that
  // moved, see leaveLayers).
  if (n.layerKey == maps_detail::kInWorkingMemory) n.layerKey = ++impl_->evictions;
  return true;
}
GridUpdateSummary OccupancyGrid::update(const std::map<int, Transform>& poses) { return impl_->update(poses); }
int OccupancyGrid::pendingUpdates() const { return impl_->deferred; }
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
  size_t bytes = impl_->storage.bytes() + impl_->recentBytes + impl_->recent.size() * 48 +
                 impl_->layers.size() * (maps_detail::kTileCells * sizeof(int16_t) + 64);
  for (const auto& [id, n] : impl_->cache) bytes += n.bytes();
  for (const auto& [id, t] : impl_->tilesOf) bytes += t.bytes() + sizeof(Transform) + 64;
  return bytes;
}

void OccupancyGrid::clear() {
  const GlobalGridOptions o = impl_->o;
  GridLoader loader = std::move(impl_->loader);
  impl_ = std::make_unique<Impl>(o);
  impl_->loader = std::move(loader);
}

}  // namespace rtabmap
