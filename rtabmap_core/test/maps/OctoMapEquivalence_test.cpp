// The fast OctoMap insertion (batched descent, stamped ray casting, parallel rays) computes
// exactly what the straightforward liboctomap insertion computes: a reference written here with
// nothing but liboctomap calls (computeRayKeys into a KeySet per node, occupied wins, then
// updateNode per voxel with lazy evaluation and one updateInnerOccupancy per node, as
// OccupancyOcTreeBase::insertPointCloud does) must give the same tree, byte for byte (every
// node's log-odds and colour, inner nodes included), and the same ground / obstacle / free sets,
// on a synthetic scene and on real 7-Scenes depth frames.
#include <gtest/gtest.h>

#include <octomap/ColorOcTree.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "common/TestData.h"
#include "maps/MapsTestUtil.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/maps/LocalGridMaker.h"
#include "rtabmap_core/maps/OctoMap.h"

using namespace rtabmap;
using rtabmap::test::DepthScene;

namespace {

// The straightforward insertion of the local grids, node after node.
class ReferenceOctoMap {
 public:
  explicit ReferenceOctoMap(const OctoMapOptions& o) : o_(o), tree_(o.cellSize) {
    tree_.setProbHit(o.probHit);
    tree_.setProbMiss(o.probMiss);
    tree_.setClampingThresMin(o.probClampingMin);
    tree_.setClampingThresMax(o.probClampingMax);
    tree_.setOccupancyThres(o.occupancyThr);
  }

  void insert(const LocalGrid& g, const Transform& pose) {
    const Eigen::Isometry3f t = pose.toEigen().cast<float>();
    auto world = [&](const cv::Point3f& p) {
      const Eigen::Vector3f w = t * Eigen::Vector3f(p.x, p.y, p.z);
      return octomap::point3d(w.x(), w.y(), w.z());
    };
    // Occupied: obstacles first (they win over ground), the first point of a voxel gives its colour.
    octomap::KeySet occupied;
    std::vector<octomap::point3d> ends;
    struct Hit {
      octomap::OcTreeKey key;
      bool ground;
      bool colored;
      cv::Vec3b color;
    };
    std::vector<Hit> hits;
    for (const bool ground : {false, true}) {
      const Cloud c = cloudFromCells(ground ? g.ground : g.obstacles);
      for (size_t i = 0; i < c.size(); ++i) {
        const octomap::point3d q = world(c.points[i]);
        octomap::OcTreeKey k;
        if (!tree_.coordToKeyChecked(q, k)) continue;
        ends.push_back(q);
        if (occupied.insert(k).second) hits.push_back({k, ground, c.hasColors(), c.hasColors() ? c.colors[i] : cv::Vec3b()});
      }
    }
    // Free: the grid's empty cells, or the rays' voxels (a ray cut at the range keeps its last voxel).
    octomap::KeySet free;
    const Cloud empty = cloudFromCells(g.empty);
    if (!empty.empty()) {
      for (const cv::Point3f& p : empty.points) {
        octomap::OcTreeKey k;
        if (tree_.coordToKeyChecked(world(p), k)) free.insert(k);
      }
    } else if (o_.rayTracing) {
      const Eigen::Vector3f v = t * g.viewPoint;
      const octomap::point3d origin(v.x(), v.y(), v.z());
      octomap::OcTreeKey originKey;
      if (tree_.coordToKeyChecked(origin, originKey)) {
        octomap::KeyRay ray;
        for (const octomap::point3d& e : ends) {
          octomap::point3d end = e;
          bool cut = false;
          const octomap::point3d d = e - origin;
          const double len = d.norm();
          if (o_.rangeMax > 0.0f && len > o_.rangeMax) {
            end = origin + d * static_cast<float>(o_.rangeMax / len);
            cut = true;
          }
          octomap::OcTreeKey endKey;
          if (!tree_.coordToKeyChecked(end, endKey) || !tree_.computeRayKeys(origin, end, ray)) continue;
          free.insert(ray.begin(), ray.end());
          if (cut) free.insert(endKey);
        }
      }
    }
    for (const octomap::OcTreeKey& k : free) {
      if (!occupied.count(k)) tree_.updateNode(k, false, true);
    }
    for (const Hit& h : hits) {
      tree_.updateNode(h.key, true, true);
      if (h.colored) tree_.averageNodeColor(h.key, h.color[0], h.color[1], h.color[2]);
      if (h.ground) ground_.insert(h.key);
      else ground_.erase(h.key);
    }
    tree_.updateInnerOccupancy();
  }

  std::string bytes() const {
    std::stringstream s(std::ios::in | std::ios::out | std::ios::binary);
    tree_.writeData(s);
    return s.str();
  }
  const octomap::ColorOcTree& tree() const { return tree_; }
  const octomap::KeySet& ground() const { return ground_; }

 private:
  OctoMapOptions o_;
  octomap::ColorOcTree tree_;
  octomap::KeySet ground_;
};

// A key set as sorted packed keys (liboctomap's KeySet has no ==).
std::vector<uint64_t> sorted(const octomap::KeySet& keys) {
  std::vector<uint64_t> out;
  for (const octomap::OcTreeKey& k : keys) out.push_back((uint64_t(k[0]) << 32) | (uint64_t(k[1]) << 16) | k[2]);
  std::sort(out.begin(), out.end());
  return out;
}

// The first node whose log-odds or colour differ (leaves first, then inner nodes), for the
// failure message.
std::string firstDifference(const OctoMapMessage& message, const octomap::ColorOcTree& ref) {
  octomap::ColorOcTree got(message.resolution);
  std::stringstream s(std::string(message.data.begin(), message.data.end()));
  got.readData(s);
  if (got.size() != ref.size()) return "node counts " + std::to_string(got.size()) + " vs " + std::to_string(ref.size());
  for (const bool leaves : {true, false}) {
    for (auto a = got.begin_tree(), b = ref.begin_tree(); a != got.end_tree() && b != ref.end_tree(); ++a, ++b) {
      if (a.isLeaf() != leaves) continue;
      const octomap::ColorOcTreeNode::Color ca = a->getColor(), cb = b->getColor();
      if (a.getKey() != b.getKey() || a.getDepth() != b.getDepth() || a->getLogOdds() != b->getLogOdds() ||
          !(ca == cb)) {
        std::ostringstream o;
        o << (leaves ? "leaf" : "inner node") << " at depth " << a.getDepth() << " (" << a.getCoordinate()
          << "): log-odds " << a->getLogOdds() << " vs " << b->getLogOdds() << ", colour " << ca << " vs " << cb;
        return o.str();
      }
    }
  }
  return "same nodes";
}

// Same tree bytes, and the same voxels by kind.
void expectSameMap(const OctoMap& map, const ReferenceOctoMap& ref) {
  const OctoMapMessage full = map.toMessage(false);
  const std::string bytes = ref.bytes();
  ASSERT_EQ(full.data.size(), bytes.size());
  EXPECT_TRUE(std::equal(full.data.begin(), full.data.end(), bytes.begin(),
                         [](int8_t a, char b) { return a == static_cast<int8_t>(b); }))
      << "the trees differ " << firstDifference(full, ref.tree());
  octomap::KeySet obstacles, ground, empty;
  const octomap::ColorOcTree& t = ref.tree();
  for (auto it = t.begin_leafs(), end = t.end_leafs(); it != end; ++it) {
    if (!t.isNodeOccupied(*it)) empty.insert(it.getKey());
    else (ref.ground().count(it.getKey()) ? ground : obstacles).insert(it.getKey());
  }
  const OctoMapCells c = map.cells(16, false);
  auto keys = [&](const Cloud& cloud) {
    octomap::KeySet out;
    for (const cv::Point3f& p : cloud.points) out.insert(t.coordToKey(octomap::point3d(p.x, p.y, p.z)));
    return out;
  };
  EXPECT_TRUE(sorted(keys(c.obstacles)) == sorted(obstacles)) << c.obstacles.size() << " vs " << obstacles.size();
  EXPECT_TRUE(sorted(keys(c.ground)) == sorted(ground)) << c.ground.size() << " vs " << ground.size();
  EXPECT_TRUE(sorted(keys(c.empty)) == sorted(empty)) << c.empty.size() << " vs " << empty.size();
  // Not a trivial agreement: the map has all three kinds, and more free voxels than occupied.
  EXPECT_GT(obstacles.size(), 100u);
  EXPECT_GT(empty.size(), obstacles.size() + ground.size());
}

// Inserts the grids one update at a time, then moves every node (a rebuild), checking both.
// *fewestRays: the fewest rays the OctoMap cast for one node.
void checkAgainstReference(const OctoMapOptions& o, const std::map<int, LocalGrid>& grids,
                           const std::map<int, Transform>& poses, const Transform& correction,
                           long* fewestRays = nullptr) {
  OctoMap map(o);
  ReferenceOctoMap ref(o);
  std::map<int, Transform> graph;
  long fewest = std::numeric_limits<long>::max();
  for (const auto& [id, g] : grids) {
    ASSERT_TRUE(map.addLocalGrid(id, g));
    graph[id] = poses.at(id);
    fewest = std::min(fewest, map.update(graph).rayTracedPoints);
    ref.insert(g, poses.at(id));
  }
  if (fewestRays) *fewestRays = fewest;
  {
    SCOPED_TRACE("incremental insertion");
    expectSameMap(map, ref);
  }
  std::map<int, Transform> moved;
  for (const auto& [id, p] : graph) moved[id] = correction * p;
  ASSERT_TRUE(map.update(moved).rebuilt);
  ReferenceOctoMap rebuilt(o);
  for (const auto& [id, p] : moved) rebuilt.insert(grids.at(id), p);
  SCOPED_TRACE("rebuild after a loop closure");
  expectSameMap(map, rebuilt);
}

LocalGrid syntheticGrid(bool rayTracing, const Transform& robot) {
  LocalGridOptions o;
  o.depthDecimation = 2;
  o.rayTracing = rayTracing;
  const LocalGridResult r =
      createLocalGrid(DepthScene::floorBoxTable().render(320, 240, 262.5, 1.0, 30.0 * M_PI / 180.0, robot), o);
  EXPECT_TRUE(r.success) << r.why;
  return r.grid;
}

}  // namespace

TEST(OctoMapEquivalence, SyntheticSceneMatchesTheStraightforwardInsertion) {
  // Three views of the coloured floor / box / table scene, overlapping, rotated (so that cells
  // of one node share voxels of the map), one of them with its own empty voxels; rays cut at
  // 2.5 m so that truncated rays occur.
  std::map<int, LocalGrid> grids;
  std::map<int, Transform> poses;
  grids[1] = syntheticGrid(false, Transform::Identity());
  poses[1] = Transform::Identity();
  grids[2] = syntheticGrid(false, Transform(0.3, -0.4, 0.0, 0.0, 0.0, 0.35));
  poses[2] = Transform(0.3, -0.4, 0.0, 0.0, 0.0, 0.35);
  grids[3] = syntheticGrid(true, Transform(-0.2, 0.5, 0.0, 0.0, 0.0, -0.3));
  poses[3] = Transform(-0.2, 0.5, 0.0, 0.0, 0.0, -0.3);
  OctoMapOptions o;
  o.rayTracing = true;
  o.rangeMax = 2.5f;
  checkAgainstReference(o, grids, poses, Transform(0.11, -0.07, 0.02, 0.0, 0.0, 0.05));
}

TEST(OctoMapEquivalence, SevenScenesDepthFramesMatchTheStraightforwardInsertion) {
  RTABMAP_REQUIRE_DATA(dir, "rgbd_7scenes");
  DatasetReaderOptions ro;
  ro.maxFrames = 61;
  std::unique_ptr<DatasetReader> reader = openDatasetReader("7scenes", dir, ro);
  // As the maps bench builds them: 3D local grids without empty voxels (the OctoMap casts the
  // rays), 5 cm, 4 m, world levelled by the first camera's pose.
  const LocalGridOptions lo = LocalGridOptions::fromParameters(
      {{"Grid/Sensor", "1"}, {"Grid/CellSize", "0.05"}, {"Grid/RangeMax", "4"}, {"Grid/MapFrameProjection", "true"},
       {"Grid/DepthDecimation", "4"}, {"Grid/3D", "true"}, {"Grid/RayTracing", "false"}});
  std::map<int, LocalGrid> grids;
  std::map<int, Transform> poses;
  Transform first;
  DatasetRecord rec;
  int index = 0;
  while (reader->next(rec)) {
    if (rec.kind != DatasetRecord::Kind::kFrame || rec.data.groundTruth().isNull()) continue;
    if (first.isNull()) first = rec.data.groundTruth();
    if (index++ % 20 != 0) continue;  // frames 0, 20, 40, 60: the camera moves between them
    rec.data.setOdom(first.inverse() * rec.data.groundTruth(), Eigen::Matrix<double, 6, 6>::Identity());
    const LocalGridResult r = createLocalGrid(rec.data, lo);
    ASSERT_TRUE(r.success) << r.why;
    grids[index] = r.grid;
    poses[index] = rec.data.odomPose();
  }
  ASSERT_EQ(grids.size(), 4u);
  OctoMapOptions o = OctoMapOptions::fromParameters({{"Grid/CellSize", "0.05"}, {"Grid/RayTracing", "true"},
                                                     {"Grid/RangeMax", "4"}});
  long fewestRays = 0;
  checkAgainstReference(o, grids, poses, Transform(0.05, 0.02, -0.03, 0.01, 0.0, 0.04), &fewestRays);
  // Enough rays per frame for the ray casting to be split over two threads (1,024 or more).
  EXPECT_GE(fewestRays, 1024);
  // Rays cut shorter than the frames' depths.
  o.rangeMax = 1.5f;
  checkAgainstReference(o, grids, poses, Transform(0.05, 0.02, -0.03, 0.01, 0.0, 0.04));
}
