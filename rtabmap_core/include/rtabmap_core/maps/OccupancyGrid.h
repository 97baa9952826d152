#pragma once
// The global 2D occupancy grid (JFR 2019, 4.3.6, Figure 4.8): assembled from the nodes' local
// grids with the graph's poses, probabilistic (log-odds, OctoMap's sensor model), updated
// incrementally when a node is added and re-assembled when optimisation moves the graph.
//
//   OccupancyGrid grid(GlobalGridOptions::fromParameters(parameters));
//   grid.addLocalGrid(id, data.localGrid());           // once per node
//   GridUpdateSummary s = grid.update(optimisedPoses);   // after every map update
//   GridMap map = grid.map();                            // -> nav_msgs/OccupancyGrid
//
// Cell update. Each node updates each cell at most once: occupied if one of its obstacle cells
// falls in it, else free if one of its ground cells (or 2D empty cells) does. A cell's log-odds L
// starts unknown; an update adds logit(ProbHit) or logit(ProbMiss) to L (0 for the first one)
// and clamps it to [logit(ProbClampingMin), logit(ProbClampingMax)], so a cell can change its
// mind after a bounded number of contrary observations. Nodes update in increasing id order,
// except for the Long-Term Memory layers below. A cell is occupied when L > logit(OccupancyThr).
// 3D local grids are projected: obstacles and ground by their x y; their empty voxels are not
// used (free space at some height says nothing about the floor under it).
//
// Re-assembly after optimisation. Clamping makes a cell depend on the order of its updates, so
// a moved node's old contribution cannot be subtracted. Both paths below give exactly the same
// map:
//  - full: clear the map, replay every node;
//  - region: mark the tiles (32 x 32 cells) touched by the moved / removed / out-of-order nodes
//    at their old and new poses, clear only those tiles, replay (in id order) the nodes whose
//    bounds overlap them, writing only inside them.
// update() picks the cheaper path per update from the work each needs (cells to replay and to
// clear, cells to read back, see below) and the time per unit each path has taken so far
// (measured; both start from the same prior), unless GridGlobal/FullUpdate is false, which
// forces the region path. The summary says which path ran and why.
//
// Deferred re-assembly (GridGlobal/ReassemblyInterval N > 1). On a route driven lap after lap,
// most updates add a loop closure or a proximity link, and the optimisation then moves a few
// nodes by a centimetre or two: each re-assembly replays every node writing in their tiles,
// hundreds of long-range scans (the simulator's 2-hour tour offline: 60-120 ms an update in its
// second half, growing with the map). With N > 1 such changes wait, and add up, for up to N - 1
// updates (new nodes are still appended at once, on top, as they come last in the id order);
// the N-th update, or the first that brings no new node (the robot stands still, a link added by
// hand), re-assembles them all together. That re-assembly is larger than one update's
// (the moves of N updates cover more of the map), so the mean cost falls less than N times and
// the tail grows: on that tour with N = 5, Map_assembling mean 117 -> 75 ms and update median
// 209 -> 140 ms, but update p95 518 -> 697 ms (from update 6,000 on). The map is then exactly the
// one of the graph given last. pendingUpdates() says how many updates' changes wait (Rtabmap
// calls update() on a frame it skips because the robot did not move, to assemble them).
//
// Memory (issue 10). A re-assembly may replay any node of the map, so every node's cells are
// needed; kept in RAM they cost a few KB per node for the whole map, Long-Term Memory included.
// With a loader (setGridLoader: Rtabmap reads the local grid stored with the node in the
// database), evictLocalGrid() drops a node's cells from RAM when it leaves the Working Memory;
// what deciding a re-assembly needs (bounds, cell count, the tiles it was applied to) stays,
// about 100 bytes a node besides the pose it is assembled at. A re-assembly reads the cells of
// the evicted nodes it replays back in batches. The cells of the evicted nodes used last (just
// evicted, or read back) stay in RAM up to a fixed budget (GridGlobal/LtmCacheSize, 4 MB:
// ~1,200 nodes of a 30 m laser).
//
// Long-Term Memory layers. After hours in the same building a tile is covered by hundreds of
// old nodes, all in the LTM, and every re-assembly of it (a loop closure moving the few Working
// Memory nodes there) would read them all back. So when a tile is re-assembled, the evicted
// nodes in it are composed first, in id order, onto the tile's layer (2 bytes a cell), and the
// other nodes on top of it, in id order; the next re-assembly of the tile starts from its layer
// and replays (and reads back) only the nodes evicted since and those still in the Working
// Memory. A node leaves the layers it is in when its cells change (moved beyond UpdateError,
// replaced, removed: a retrieved node optimised with the Working Memory, typically); those
// layers are dropped and rebuilt at their tile's next re-assembly, and the node is replayed
// until it is evicted again. Below the clamping bounds updates commute and the map is the one
// of the id order to the bit; a cell that reaches a bound may differ from it by the order of the
// last few updates (the LTM nodes' before the Working Memory's).

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/maps/GridMap.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {

// GridGlobal/* (and Grid/CellSize) for the global maps.
struct GlobalGridOptions {
  float cellSize = 0.05f;         // Grid/CellSize: must match the local grids'
  float minSize = 0.0f;           // GridGlobal/MinSize (m)
  float probHit = 0.7f;           // GridGlobal/ProbHit
  float probMiss = 0.4f;          // GridGlobal/ProbMiss
  float probClampingMin = 0.1192f;// GridGlobal/ProbClampingMin
  float probClampingMax = 0.971f; // GridGlobal/ProbClampingMax
  float occupancyThr = 0.5f;      // GridGlobal/OccupancyThr
  bool fullUpdate = true;         // GridGlobal/FullUpdate: allow the full rebuild path
  float updateError = 0.01f;      // GridGlobal/UpdateError (m)
  int reassemblyInterval = 1;     // GridGlobal/ReassemblyInterval (updates), see update()
  float footprintRadius = 0.0f;   // GridGlobal/FootprintRadius (m)
  bool eroded = false;            // GridGlobal/Eroded
  int maxNodes = 0;               // GridGlobal/MaxNodes
  float altitudeDelta = 0.0f;     // GridGlobal/AltitudeDelta (m)
  float ltmCacheSize = 4.0f;      // GridGlobal/LtmCacheSize (MB), see setGridLoader()

  static GlobalGridOptions fromParameters(const ParametersMap& parameters);
  // Reasons name the key: cell size <= 0, ProbHit <= 0.5, ProbMiss >= 0.5, clamping bounds out of
  // order, ...
  bool IsValid(std::string* why = nullptr) const;
  void validate() const;  // throws ParameterError
};

// What one update() did.
struct GridUpdateSummary {
  enum class Path { kNone, kIncremental, kRegion, kFull };
  Path path = Path::kNone;
  std::string why;           // in words: what changed and why this path
  int nodesInGraph = 0;      // poses given with a local grid cached
  int nodesAssembled = 0;    // in the map after the update
  int nodesAdded = 0;        // appended incrementally
  int nodesMoved = 0;        // moved by more than GridGlobal/UpdateError
  int nodesRemoved = 0;      // no longer in the graph (or filtered by MaxNodes / AltitudeDelta)
  int nodesReplayed = 0;     // region / full: nodes applied again
  int nodesWithoutGrid = 0;  // poses given for nodes without a cached local grid
  long cellUpdates = 0;      // cell updates applied
  double estimatedRegionUnits = 0.0;  // the work estimates the choice compared
  double estimatedFullUnits = 0.0;
  int nodesLoaded = 0;        // evicted nodes whose cells were read back through the loader
  int nodesNotLoaded = 0;     // evicted nodes the loader did not give back (left out of the map)
  int nodesInLayers = 0;      // region / full: nodes re-assembled from the layers of all their tiles
                              // there, not replayed (see Long-Term Memory layers)
  int updatesDeferred = 0;    // updates whose graph changes wait for a re-assembly, this one
                              // included (0: the map matches the graph given)
  double loadMs = 0.0;        // time reading them back (part of timeMs)
  double timeMs = 0.0;
};
const char* pathName(GridUpdateSummary::Path path);

class OccupancyGrid {
 public:
  // Throws ParameterError for invalid options.
  explicit OccupancyGrid(const GlobalGridOptions& options = GlobalGridOptions());
  ~OccupancyGrid();
  OccupancyGrid(OccupancyGrid&&) noexcept;
  OccupancyGrid& operator=(OccupancyGrid&&) noexcept;

  const GlobalGridOptions& options() const;

  // Caches a node's local grid (replacing a previous one, which then counts as moved at the
  // next update). Returns false, with the reason in *why, for a grid the map cannot use: a cell
  // size different from the map's, cells that are not CV_32FC2/3/4, non-finite cells, or an
  // empty grid (which would add nothing and hide a failure upstream).
  bool addLocalGrid(int nodeId, const LocalGrid& grid, std::string* why = nullptr);
  bool hasLocalGrid(int nodeId) const;  // cached, in RAM or evicted
  void removeLocalGrid(int nodeId);  // and its cells, at the next update
  size_t cachedNodes() const;        // in RAM or evicted
  size_t residentNodes() const;      // not evicted (evicted ones may have theirs among the recent)

  // Where evicted nodes' cells come back from: the local grids of the ids asked for (ids not
  // found may be left out: those nodes are then missing from the re-assembled map, counted in
  // GridUpdateSummary::nodesNotLoaded). Called from update() only, with at most a few hundred
  // ids at a time. The grids must be the ones given to addLocalGrid().
  using GridLoader = std::function<std::map<int, LocalGrid>(const std::vector<int>& ids)>;
  // The RAM for the cells of evicted nodes used last is options().ltmCacheSize (0: every replay
  // reads back).
  void setGridLoader(GridLoader loader);
  // Drops a node's cells from RAM (see Memory above); it joins the layers of its tiles at their
  // next re-assembly (see Long-Term Memory layers). Call it again when a node retrieved from the
  // LTM goes back there. False, and nothing done, for a node not cached or without a loader set.
  bool evictLocalGrid(int nodeId);

  // Brings the map to the given graph (node id -> pose, e.g. the optimised poses): appends new
  // nodes, re-assembles for moved or removed ones (or defers that while new nodes come, see
  // Deferred re-assembly). Null or non-finite poses are ignored as absent.
  GridUpdateSummary update(const std::map<int, Transform>& poses);
  // Updates whose graph changes wait for a re-assembly (0: none).
  int pendingUpdates() const;
  // Forces one path for the next re-assembly (benchmarks and tests measure both); kNone = choose.
  void forceNextPath(GridUpdateSummary::Path path);

  // The map: -1 / 0 / 100 cells over the bounding box of known cells, padded to
  // GridGlobal/MinSize, with footprint clearing and erosion applied. Empty before any update.
  GridMap map() const;
  // Occupancy probability of the cell at (x, y): -1 when unknown or outside.
  float probability(double x, double y) const;
  // Nodes currently assembled, with the pose each was assembled at.
  const std::map<int, Transform>& assembledPoses() const;
  // Bytes held: the log-odds map, its bookkeeping and the cached local grids.
  size_t memoryUsed() const;
  void clear();  // map and cache

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rtabmap
