// Localization from a pose given by the user, on the simulator's ring (laser + wheel odometry
// only: no images, so no appearance-based loop closure can find the place by itself and
// localization rests on proximity by space around where the robot is assumed). The map is
// made of most of a lap; the robot is then switched on again far from where that session
// ended, with odometry starting at identity.
#include <gtest/gtest.h>

#include <iostream>
#include <memory>
#include <vector>

#include "SimSlam.h"
#include "rtabmap_core/eval/DatasetReader.h"

namespace rtabmap {
namespace {

struct Frame {
  SensorData data;  // the laser scan only
  Transform odom;
  Transform truth;
};

std::vector<Frame> laserFrames(const std::string& folder) {
  std::unique_ptr<DatasetReader> reader = openDatasetReader("sim", folder);
  std::vector<Frame> frames;
  DatasetRecord record;
  while (reader->next(record)) {
    if (record.kind != DatasetRecord::Kind::kFrame) continue;
    const SensorData& d = record.data;
    frames.push_back({SensorData(d.laserScanRaw(), d.id(), d.stamp()), d.odomPose(), d.groundTruth()});
  }
  return frames;
}

ParametersMap laserParameters(bool mapping, bool globalScanMap = false) {
  ParametersMap p = test::simSlamParameters();
  p["Reg/Strategy"] = "1";        // ICP
  p["Kp/MaxFeatures"] = "-1";     // no visual words
  p["RGBD/CreateOccupancyGrid"] = "false";
  // A small Working Memory: when localization starts, the part of the map where the robot is
  // is in the database only, and comes back because it is near the assumed pose.
  p["Rtabmap/MemoryThr"] = "30";
  p["Mem/IncrementalMemory"] = mapping ? "true" : "false";
  p["RGBD/ProximityGlobalScanMap"] = globalScanMap ? "true" : "false";
  return p;
}

struct Update {
  Transform pose;       // currentPose() after it
  Transform truth;      // in the map frame
  bool localized = false;
};

// Localization from frame `first` on (odometry restarted there), `updates` updates.
std::vector<Update> localize(const std::vector<Frame>& frames, size_t first, int updates, const std::string& db,
                             const Transform& mapFromWorld, const Transform& initialPose, SlamSummary* summary,
                             bool globalScanMap = false) {
  Rtabmap slam;
  slam.init(laserParameters(false, globalScanMap), db);
  if (!initialPose.isNull()) {
    EXPECT_TRUE(slam.setInitialPose(initialPose));
  }
  const Transform odomOrigin = frames[first].odom.inverse();
  std::vector<Update> out;
  for (size_t i = first; i < frames.size() && static_cast<int>(out.size()) < updates; ++i) {
    const int before = slam.summary().updates - slam.summary().skippedRate;
    const bool localized = slam.process(frames[i].data, odomOrigin * frames[i].odom);
    if (slam.summary().updates - slam.summary().skippedRate == before) continue;  // rate limited
    out.push_back({slam.currentPose(), mapFromWorld * frames[i].truth, localized});
  }
  *summary = slam.summary();
  return out;
}

TEST(InitialPoseSim, RobotPlacedByTheUserLocalisesThereByProximity) {
  std::string why;
  const std::string folder = test::simDataset("loop", &why);
  ASSERT_FALSE(folder.empty()) << why;
  const std::vector<Frame> frames = laserFrames(folder);
  ASSERT_GT(frames.size(), 250u);

  // The map: the first 120 s of the lap, at 1 Hz.
  test::TempDir dir("rtabmap_initial_pose_sim");
  const std::string db = dir.file("rtabmap.db");
  constexpr size_t kMapped = 240;
  constexpr size_t kStart = 60;  // 16 m from where the mapping ended, beyond RGBD/LocalRadius
  std::map<size_t, int> nodeOfFrame;
  Transform mapFromWorld;
  {
    Rtabmap slam;
    slam.init(laserParameters(true), db);
    for (size_t i = 0; i < kMapped; ++i) {
      if (slam.process(frames[i].data, frames[i].odom)) nodeOfFrame[i] = slam.statistics().refImageId;
    }
    ASSERT_GT(slam.summary().transferred, 50) << "the map should be mostly in the database";
    // The map frame against the simulator's world, at the node just before the start.
    const std::map<int, Transform> poses = slam.optimizedPoses();
    auto node = nodeOfFrame.upper_bound(kStart);
    ASSERT_NE(node, nodeOfFrame.begin());
    --node;
    ASSERT_TRUE(poses.count(node->second));
    mapFromWorld = poses.at(node->second) * frames[node->first].truth.inverse();
    slam.close();
  }
  const Transform truthAtStart = mapFromWorld * frames[kStart].truth;
  const Transform lastPose = mapFromWorld * frames[kMapped - 1].truth;
  ASSERT_GT(truthAtStart.getDistance(lastPose), 14.0);

  // Without a pose from the user the robot is assumed where the mapping ended: nothing near
  // there is where it is, and it never localises at its true place. Proximity detection still
  // matches its scans on look-alike walls there; the odometry cache (RGBD/MaxOdomCacheSize)
  // applies such a match only when a second one, at a later frame, agrees with it through
  // odometry: without the cache this run "localised" twice, 16 m off; with it, once (two
  // matches on the same look-alike did agree).
  SlamSummary without;
  const std::vector<Update> lost = localize(frames, kStart, 6, db, mapFromWorld, Transform(), &without);
  ASSERT_EQ(lost.size(), 6u);
  EXPECT_GT(lost.front().pose.getDistance(lost.front().truth), 10.0);
  for (const Update& u : lost) EXPECT_GT(u.pose.getDistance(u.truth), 1.0) << "localised without knowing where";
  EXPECT_LE(without.localizations, 1);

  // With the user's pose (0.3 m and 3 degrees off, as a click in rviz is): map -> odom puts
  // the robot there at the first update, the nodes around come back from the database, and
  // proximity detection localises it within a few updates.
  const Transform given = truthAtStart * Transform(0.2, -0.22, 0.0, 0.0, 0.0, 0.05);
  SlamSummary with;
  const std::vector<Update> placed = localize(frames, kStart, 6, db, mapFromWorld, given, &with);
  ASSERT_EQ(placed.size(), 6u);
  EXPECT_LT(placed.front().pose.getDistance(placed.front().truth), 0.35);
  EXPECT_GT(with.retrieved, 0) << "nothing retrieved from the database around the given pose";
  int firstLocalized = -1;
  for (size_t k = 0; k < placed.size(); ++k) {
    if (!placed[k].localized) continue;
    if (firstLocalized < 0) firstLocalized = static_cast<int>(k);
    EXPECT_LT(placed[k].pose.getDistance(placed[k].truth), 0.15) << "update " << k;
  }
  EXPECT_GE(firstLocalized, 0) << "never localised";
  // Update 2 with the wheel odometry's neighbour links, 3 since they are refined by ICP, 4 since
  // the simulator's planner keeps a straight in S-bends (the map differs a little where the
  // first proximity link is found; the errors before it are the same to the micrometre), 5
  // since the first proximity link waits for a second one to confirm it (RGBD/MaxOdomCacheSize).
  EXPECT_LE(firstLocalized, 5);
  EXPECT_LT(placed.back().pose.getDistance(placed.back().truth), 0.15);
  std::cout << "localization from a given pose: first localised at update " << firstLocalized << ", errors (m):";
  for (const Update& u : placed) std::cout << " " << u.pose.getDistance(u.truth) << (u.localized ? "*" : "");
  std::cout << "; without it: " << without.localizations << " localisation(s), errors (m):";
  for (const Update& u : lost) std::cout << " " << u.pose.getDistance(u.truth) << (u.localized ? "*" : "");
  std::cout << std::endl;
  RecordProperty("first_localized_update", firstLocalized);
  RecordProperty("localizations_with", with.localizations);
  RecordProperty("localizations_without", without.localizations);

  // RGBD/ProximityGlobalScanMap: one ICP against the scans of the whole map around where the
  // robot is assumed, the nodes there read from the database once instead of retrieved.
  SlamSummary globalWith, globalWithout;
  const std::vector<Update> global = localize(frames, kStart, 6, db, mapFromWorld, given, &globalWith, true);
  const std::vector<Update> globalLost =
      localize(frames, kStart, 6, db, mapFromWorld, Transform(), &globalWithout, true);
  ASSERT_EQ(global.size(), 6u);
  ASSERT_EQ(globalLost.size(), 6u);
  int globalFirst = -1;
  for (size_t k = 0; k < global.size(); ++k) {
    if (!global[k].localized) continue;
    if (globalFirst < 0) globalFirst = static_cast<int>(k);
    EXPECT_LT(global[k].pose.getDistance(global[k].truth), 0.15) << "update " << k;
  }
  EXPECT_GE(globalFirst, 0) << "never localised on the global scan map";
  EXPECT_LE(globalFirst, firstLocalized);
  EXPECT_LT(global.back().pose.getDistance(global.back().truth), 0.15);
  for (const Update& u : globalLost) EXPECT_GT(u.pose.getDistance(u.truth), 1.0) << "localised without knowing where";
  EXPECT_LE(globalWithout.localizations, 1);
  std::cout << "on the global scan map: first localised at update " << globalFirst << ", errors (m):";
  for (const Update& u : global) std::cout << " " << u.pose.getDistance(u.truth) << (u.localized ? "*" : "");
  std::cout << "; without a pose: " << globalWithout.localizations << " localisation(s)" << std::endl;
}

}  // namespace
}  // namespace rtabmap
