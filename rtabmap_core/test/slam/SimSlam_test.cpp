// The SLAM pipeline on the simulator (issue 8, "How it is shown"): a visual loop closure that
// lowers the ATE, a reverse lap closed by laser proximity only, three sessions merged into one
// referential, localization that leaves the database untouched.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <set>
#include <sstream>

#include <opencv2/core.hpp>

#include "SimSlam.h"
#include "common/TestData.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/maps/OccupancyGrid.h"

namespace rtabmap {
namespace {

using test::SimSlamRun;

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Every node of `expected` in `actual`, at the same pose to the bit.
void expectSamePoses(const std::map<int, Transform>& expected, const std::map<int, Transform>& actual) {
  for (const auto& [id, pose] : expected) {
    auto it = actual.find(id);
    ASSERT_NE(it, actual.end()) << "node " << id;
    EXPECT_TRUE(it->second.toEigen().isApprox(pose.toEigen(), 0.0)) << "node " << id;
  }
}

TEST(SimSlam, LoopClosesVisuallyThenLocalizesWithoutWriting) {
  REQUIRE_SIM(folder, "loop");
  test::TempDir dir("rtabmap_slam_loop");
  const std::string db = dir.file("rtabmap.db");
  SimSlamRun run;
  test::runSimSlam(folder, test::simSlamParameters(), db, run);
  ASSERT_GT(run.summary.nodesAdded, 100);
  EXPECT_EQ(run.refused, 0);
  // The revisit of the first third of the ring is recognised from the images.
  EXPECT_GE(run.summary.loopClosures, 5);
  int closures = 0;
  const double worst = test::worstLinkError(run.links, run.groundTruth,
                                            {Link::kGlobalClosure, Link::kLocalSpaceClosure}, &closures);
  EXPECT_GE(closures, 5);
  EXPECT_LT(worst, 0.10) << "a loop closure or proximity link is wrong";
  EXPECT_EQ(run.summary.timeLinks, 0) << "RGBD/ProximityByTime is off by default";
  const double odomAte = test::nodeAte(run.odometry, run.groundTruth);
  const double slamAte = test::nodeAte(run.optimized, run.groundTruth);
  RecordProperty("odom_ate", std::to_string(odomAte));
  RecordProperty("slam_ate", std::to_string(slamAte));
  EXPECT_LT(slamAte, 0.5 * odomAte) << "odometry ATE " << odomAte << " m, SLAM " << slamAte << " m";
  // Rtabmap/ComputeRMSE: the last update's statistics say the same (every node is in RAM here).
  EXPECT_NEAR(run.lastGroundTruthRmse, slamAte, 0.05 * slamAte + 1e-3);

  // Localization on the saved map: the same route again, nothing written.
  const std::string before = fileBytes(db);
  ASSERT_FALSE(before.empty());
  ParametersMap loc = test::simSlamParameters();
  loc["Mem/IncrementalMemory"] = "false";
  SimSlamRun again;
  test::runSimSlam(folder, loc, db, again);
  EXPECT_EQ(again.summary.nodesAdded, 0);
  EXPECT_GT(again.summary.localizations, 20);
  EXPECT_EQ(fileBytes(db), before) << "localization modified the database";
  EXPECT_FALSE(std::filesystem::exists(db + "-wal") && std::filesystem::file_size(db + "-wal") > 0);
}

// Rtabmap/CreateIntermediateNodes on the simulator's loop (2 Hz input, 1 Hz updates): every
// other frame becomes an intermediate node; the loop closes as without them, and the optimised
// graph places them as well as the nodes at the update rate (neighbour-link refining spread over
// them, loop closures through them).
TEST(SimSlam, IntermediateNodesAreAsAccurateAsTheUpdates) {
  REQUIRE_SIM(folder, "loop");
  ParametersMap p = test::simSlamParameters();
  p["Rtabmap/CreateIntermediateNodes"] = "true";
  SimSlamRun run;
  test::runSimSlam(folder, p, "", run);
  EXPECT_EQ(static_cast<int>(run.intermediate.size()), run.summary.intermediateNodes);
  EXPECT_GT(run.summary.intermediateNodes, run.summary.nodesAdded / 2);
  EXPECT_GE(run.summary.loopClosures, 5);
  std::map<int, Transform> nodes, intermediate;
  for (const auto& [id, pose] : run.optimized) (run.intermediate.count(id) ? intermediate : nodes).emplace(id, pose);
  ASSERT_EQ(intermediate.size(), run.intermediate.size()) << "intermediate nodes missing from the graph";
  const double odomAte = test::nodeAte(run.odometry, run.groundTruth);
  const double nodesAte = test::nodeAte(nodes, run.groundTruth);
  const double intermediateAte = test::nodeAte(intermediate, run.groundTruth);
  RecordProperty("nodes_ate", std::to_string(nodesAte));
  RecordProperty("intermediate_ate", std::to_string(intermediateAte));
  EXPECT_LT(nodesAte, 0.5 * odomAte);
  EXPECT_LT(intermediateAte, 1.25 * nodesAte + 0.01)
      << "odometry " << odomAte << " m, nodes " << nodesAte << " m, intermediate nodes " << intermediateAte << " m";
}

// RGBD/ProximityByTime: the new node is registered against the Short-Term Memory nodes it is not
// linked to; the links found are right (ground truth) and join nodes that were in Short-Term
// Memory together.
TEST(SimSlam, ProximityByTimeLinksRecentNodesCorrectly) {
  REQUIRE_SIM(folder, "loop");
  ParametersMap p = test::simSlamParameters();
  p["RGBD/ProximityByTime"] = "true";
  SimSlamRun run;
  test::runSimSlam(folder, p, "", run);
  int count = 0;
  std::string which;
  const double worst = test::worstLinkError(run.links, run.groundTruth, {Link::kLocalTimeClosure}, &count, &which);
  RecordProperty("time_links", count);
  EXPECT_GT(count, 20);
  EXPECT_EQ(count, run.summary.timeLinks);
  EXPECT_LT(worst, 0.10) << "proximity link by time " << which;
  const int stm = Parameters::defaultMemSTMSize();
  for (const auto& [from, link] : run.links) {
    if (link.type() != Link::kLocalTimeClosure) continue;
    EXPECT_GT(std::abs(link.from() - link.to()), 1) << "consecutive nodes have their odometry link already";
    EXPECT_LE(std::abs(link.from() - link.to()), stm) << link.from() << "->" << link.to();
  }
  EXPECT_LT(test::nodeAte(run.optimized, run.groundTruth), 0.5 * test::nodeAte(run.odometry, run.groundTruth));
}

// RGBD/LoopClosureReextractFeatures: with 60 visual words a node, appearance still finds the
// revisits, but no registration of the words can reach Vis/MinInliers 70; features extracted
// again from the images (Vis/MaxFeatures) can.
TEST(SimSlam, LoopClosuresFromFeaturesExtractedAgainWhenWordsAreFew) {
  REQUIRE_SIM(folder, "loop");
  ParametersMap p = test::simSlamParameters();
  p["Kp/MaxFeatures"] = "60";
  p["Vis/MinInliers"] = "70";
  p["Reg/Strategy"] = "0";  // visual only: ICP would not need the features
  p["RGBD/ProximityBySpace"] = "false";
  SimSlamRun words, again;
  test::runSimSlam(folder, p, "", words);
  p["RGBD/LoopClosureReextractFeatures"] = "true";
  test::runSimSlam(folder, p, "", again);
  RecordProperty("closures_from_words", words.summary.loopClosures);
  RecordProperty("closures_from_features", again.summary.loopClosures);
  EXPECT_EQ(words.summary.loopClosures, 0);
  EXPECT_GT(words.summary.rejectedLinks, 0) << "appearance found no revisit to verify";
  EXPECT_GE(again.summary.loopClosures, 3);
  EXPECT_LT(test::worstLinkError(again.links, again.groundTruth, {Link::kGlobalClosure}), 0.10);
}

// Reproducible runs: the same input and parameters give the same map, to the bit (the
// vocabulary's kd-trees come from a fixed seed; nothing else may draw from the clock or
// std::random_device). A user comparing two parameter sets, and every figure of the benches,
// relies on it.
TEST(SimSlam, TheSameRunTwiceGivesTheSameMap) {
  REQUIRE_SIM(folder, "loop");
  test::TempDir dir("rtabmap_slam_twice");
  SimSlamRun first, second;
  test::runSimSlam(folder, test::simSlamParameters(), dir.file("first.db"), first);
  test::runSimSlam(folder, test::simSlamParameters(), dir.file("second.db"), second);
  ASSERT_GE(first.summary.loopClosures, 5);
  EXPECT_EQ(second.summary.loopClosures, first.summary.loopClosures);
  EXPECT_EQ(second.summary.nodesAdded, first.summary.nodesAdded);
  ASSERT_EQ(second.optimized.size(), first.optimized.size());
  expectSamePoses(first.optimized, second.optimized);
  ASSERT_EQ(second.links.size(), first.links.size());
  for (auto a = first.links.begin(), b = second.links.begin(); a != first.links.end(); ++a, ++b) {
    EXPECT_EQ(a->second.from(), b->second.from());
    EXPECT_EQ(a->second.to(), b->second.to());
    EXPECT_EQ(a->second.type(), b->second.type());
    EXPECT_TRUE(a->second.transform().toEigen().isApprox(b->second.transform().toEigen(), 0.0))
        << a->second.from() << " -> " << a->second.to();
  }
}

// Mem/BinDataKept false: the nodes keep no image, and the map is the same to the bit (loop
// closures are registered from the words, proximity from the scans) from a smaller database:
// the simulator's synthetic images, which compress well, are 45% of it (the words, scans and
// grids the rest); a camera's are more.
TEST(SimSlam, WithoutImagesTheSameMapComesFromASmallerDatabase) {
  REQUIRE_SIM(folder, "loop");
  test::TempDir dir("rtabmap_slam_bin_data");
  ParametersMap p = test::simSlamParameters();
  SimSlamRun full, light;
  test::runSimSlam(folder, p, dir.file("full.db"), full);
  p["Mem/BinDataKept"] = "false";
  test::runSimSlam(folder, p, dir.file("light.db"), light);
  ASSERT_GE(full.summary.loopClosures, 5);
  EXPECT_EQ(light.summary.loopClosures, full.summary.loopClosures);
  ASSERT_EQ(light.optimized.size(), full.optimized.size());
  expectSamePoses(full.optimized, light.optimized);
  const auto fullBytes = std::filesystem::file_size(dir.file("full.db"));
  const auto lightBytes = std::filesystem::file_size(dir.file("light.db"));
  RecordProperty("full_db_bytes", std::to_string(fullBytes));
  RecordProperty("light_db_bytes", std::to_string(lightBytes));
  EXPECT_LT(lightBytes * 10, fullBytes * 7);

  db::DatabaseOptions readOnly;
  readOnly.readOnly = true;
  db::Database db(dir.file("light.db"), readOnly);
  int checked = 0;
  for (int id : db.nodeIds()) {
    const std::optional<Signature> node = db.loadNode(id);
    ASSERT_TRUE(node.has_value());
    const SensorData& data = node->sensorData();
    EXPECT_TRUE(data.imageCompressed().empty()) << "node " << id;
    EXPECT_TRUE(data.depthOrRightCompressed().empty()) << "node " << id;
    EXPECT_FALSE(data.cameraModels().empty() && data.stereoCameraModels().empty()) << "node " << id;
    EXPECT_FALSE(data.laserScanCompressed().empty()) << "node " << id;
    EXPECT_FALSE(data.localGrid().isEmpty()) << "node " << id;
    checked += node->getWords().empty() ? 0 : 1;
  }
  EXPECT_GT(checked, 100) << "nodes with words";
}

// Mem/RawDescriptorsKept false: nodes keep their words without descriptors (in RAM and in the
// database), and loop closures are registered by pairing the words by id.
TEST(SimSlam, LoopClosesFromWordIdsWithoutDescriptors) {
  REQUIRE_SIM(folder, "loop");
  test::TempDir dir("rtabmap_slam_no_descriptors");
  ParametersMap p = test::simSlamParameters();
  p["Mem/RawDescriptorsKept"] = "false";
  SimSlamRun run;
  test::runSimSlam(folder, p, dir.file("rtabmap.db"), run);
  RecordProperty("loop_closures", run.summary.loopClosures);
  RecordProperty("db_bytes", std::to_string(std::filesystem::file_size(dir.file("rtabmap.db"))));
  EXPECT_GE(run.summary.loopClosures, 5);
  EXPECT_LT(test::worstLinkError(run.links, run.groundTruth, {Link::kGlobalClosure, Link::kLocalSpaceClosure}), 0.10);
  EXPECT_LT(test::nodeAte(run.optimized, run.groundTruth), 0.5 * test::nodeAte(run.odometry, run.groundTruth));
  db::DatabaseOptions readOnly;
  readOnly.readOnly = true;
  db::Database db(dir.file("rtabmap.db"), readOnly);
  int withWords = 0;
  for (int id : db.nodeIds()) {
    const std::optional<Signature> node = db.loadNode(id);
    ASSERT_TRUE(node.has_value());
    EXPECT_TRUE(node->getWordsDescriptors().empty()) << "node " << id;
    withWords += node->getWords().empty() ? 0 : 1;
  }
  EXPECT_GT(withWords, 100);
}

// RGBD/LocalBundleOnLoopClosure in the pipeline: visual loop closures (Reg/Strategy 0, no ICP
// after them) registered against the old node's neighbourhood and refined by bundle adjustment
// are as right as those registered from the two nodes alone (measured: 6.7 mm mean error against
// 6.9; on 7-Scenes the gain is larger, see the README).
TEST(SimSlam, LocalBundleLoopClosuresAreRight) {
  REQUIRE_SIM(folder, "loop");
  test::TempDir dir("rtabmap_slam_local_bundle");
  ParametersMap p = test::simSlamParameters();
  p["Reg/Strategy"] = "0";
  SimSlamRun twoNodes, local;
  test::runSimSlam(folder, p, dir.file("two.db"), twoNodes);
  p["RGBD/LocalBundleOnLoopClosure"] = "true";
  test::runSimSlam(folder, p, dir.file("local.db"), local);
  int nTwo = 0, nLocal = 0;
  const double two = test::meanLinkError(twoNodes.links, twoNodes.groundTruth, {Link::kGlobalClosure}, &nTwo);
  const double bundled = test::meanLinkError(local.links, local.groundTruth, {Link::kGlobalClosure}, &nLocal);
  RecordProperty("two_nodes_mm", std::to_string(two * 1000));
  RecordProperty("local_bundle_mm", std::to_string(bundled * 1000));
  EXPECT_GE(nLocal, 5);
  EXPECT_LT(bundled, 0.02);
  EXPECT_LT(test::worstLinkError(local.links, local.groundTruth, {Link::kGlobalClosure}), 0.10);
  // The closures did come from the local maps: a closure of the same two nodes differs.
  int same = 0, different = 0;
  for (const auto& [from, link] : local.links) {
    if (link.type() != Link::kGlobalClosure) continue;
    for (auto [it, end] = twoNodes.links.equal_range(from); it != end; ++it) {
      if (it->second.type() != Link::kGlobalClosure || it->second.to() != link.to()) continue;
      (it->second.transform().getDistance(link.transform()) > 1e-6 ? different : same) += 1;
    }
  }
  EXPECT_GT(different, 0);
  EXPECT_EQ(same, 0) << "closures registered from the two nodes alone";
}

TEST(SimSlam, ReverseLapClosesWithLaserProximity) {
  REQUIRE_SIM(folder, "reverse");
  test::TempDir dir("rtabmap_slam_reverse");
  SimSlamRun run;
  test::runSimSlam(folder, test::simSlamParameters(), dir.file("rtabmap.db"), run);
  ASSERT_GT(run.summary.nodesAdded, 100);
  // The camera sees the other side of every place on the way back: laser proximity closes it.
  EXPECT_GE(run.summary.proximityLinks, 5);
  int proximity = 0;
  // Along a corridor ICP leaves some of the drift (low complexity in that direction).
  EXPECT_LT(test::worstLinkError(run.links, run.groundTruth, {Link::kLocalSpaceClosure}, &proximity), 0.25);
  EXPECT_GE(proximity, 5);
  const double odomAte = test::nodeAte(run.odometry, run.groundTruth);
  const double slamAte = test::nodeAte(run.optimized, run.groundTruth);
  EXPECT_LT(slamAte, 0.5 * odomAte) << "odometry ATE " << odomAte << " m, SLAM " << slamAte << " m";
  // RGBD/ScanMatchingIdsSavedInLinks: a link from merged scans names the nodes whose scans it
  // matched, the path around the node it links to.
  int named = 0;
  for (const auto& [from, link] : run.links) {
    if (link.type() != Link::kLocalSpaceClosure || link.userData().empty()) continue;
    const std::string text(link.userData().ptr<char>(), link.userData().total());
    ASSERT_EQ(text.rfind("SCANS:", 0), 0u) << text;
    std::set<int> ids;
    std::stringstream list(text.substr(6));
    for (std::string id; std::getline(list, id, ';');) ids.insert(std::stoi(id));
    EXPECT_TRUE(ids.count(link.from()) || ids.count(link.to())) << link.from() << "->" << link.to() << ": " << text;
    EXPECT_TRUE(run.odometry.count(*ids.begin()) && run.odometry.count(*ids.rbegin())) << text;
    ++named;
  }
  EXPECT_GE(named, 3);
}

// Each session starts somewhere else with odometry reset: a new map, merged into the first
// session's referential by its loop closures with the earlier ones.
//
// The simulator's materials repeat every 4 m and its blocks of rooms are regular: session 3
// finds an aliased place 11 m off (camera and laser agree) before any true one and merges
// there. A first link between two maps has no common referential to check it against; the
// true closures that follow are refused for their jump, agree with each other, outvote the
// wrong merge and merge the session again at the right place (MergeArbiter).
TEST(SimSlam, SessionsMergeIntoTheFirstSessionsReferential) {
  REQUIRE_SIM(folder, "multisession");
  const ParametersMap parameters = test::simSlamParameters();
  test::TempDir dir("rtabmap_slam_multisession");
  const std::string db = dir.file("rtabmap.db");
  SimSlamRun run;
  std::vector<int> maps;
  std::vector<double> odomAte;
  for (int s = 1; s <= 3; ++s) {
    SimSlamRun session;
    test::runSimSlam(folder + "/session" + std::to_string(s), parameters, db, session);
    odomAte.push_back(test::nodeAte(session.odometry, session.groundTruth));
    run.summary.mapsStarted += session.summary.mapsStarted;
    run.odometry.insert(session.odometry.begin(), session.odometry.end());
    run.groundTruth.insert(session.groundTruth.begin(), session.groundTruth.end());
    run.optimized = session.optimized;
    run.links = session.links;
    run.lastMapId = session.lastMapId;
    maps.push_back(run.lastMapId);
    // Every node so far is in the current referential: the maps merged.
    size_t known = 0;
    for (const auto& [id, gt] : run.groundTruth) {
      (void)gt;
      known += run.optimized.count(id);
    }
    EXPECT_EQ(known, run.groundTruth.size()) << "session " << s << " not merged with the earlier ones";
    if (s >= 2) {
      const double merged = test::nodeAte(run.optimized, run.groundTruth);
      const double worstOdom = *std::max_element(odomAte.begin(), odomAte.end());
      std::cout << "sessions 1-" << s << " merged: ATE " << merged << " m over " << run.groundTruth.size()
                << " nodes (worst odometry ATE of a session in its own frame: " << worstOdom
                << "); merges redone: " << session.summary.remerges << std::endl;
      // A wrong merge puts a session metres away; a right one leaves each session's own drift
      // (session 1 has no loop of its own to correct it).
      EXPECT_LT(merged, 1.25 * worstOdom + 0.05) << "ATE of sessions 1 to " << s << " in one referential";
      // The goal for the merged map.
      EXPECT_LT(merged, 0.10) << "ATE of sessions 1 to " << s << " in one referential";
      std::string which;
      EXPECT_LT(test::worstLinkError(run.links, run.groundTruth, {Link::kGlobalClosure, Link::kLocalSpaceClosure},
                                     nullptr, &which),
                0.25)
          << which;
    }
  }
  EXPECT_EQ(run.summary.mapsStarted, 3);
  EXPECT_LT(maps[0], maps[1]);
  EXPECT_LT(maps[1], maps[2]);

  // The database alone says the same: the undone merge links are gone from it, so a new
  // process rebuilds one referential from the links left.
  Rtabmap reopened;
  reopened.init(parameters, db);
  const std::map<int, Transform> poses = reopened.optimizedPoses();
  EXPECT_EQ(poses.size(), run.groundTruth.size()) << "every session in the reopened map's referential";
  EXPECT_LT(test::nodeAte(poses, run.groundTruth), 1.25 * *std::max_element(odomAte.begin(), odomAte.end()) + 0.05);
  EXPECT_LT(test::worstLinkError(reopened.allLinks(), run.groundTruth, {Link::kGlobalClosure}), 0.25);
  reopened.close();
}

// Without RGBD/MaxLoopClosureDistance the true closures after session 3's wrong merge are
// refused by the graph (RGBD/OptimizeMaxError) instead of for their jump: they vote the same.
// (Only the global closures are checked: without a jump limit session 2 also keeps an aliased
// closure 4 m off, and laser proximity an aliased link 4 m off in the corridors, where the
// materials repeat every 4 m: the reason the simulator's robot sets one.)
TEST(SimSlam, AMergeRefusedByTheGraphIsRedoneToo) {
  REQUIRE_SIM(folder, "multisession");
  test::TempDir dir("rtabmap_slam_multisession_nojump");
  ParametersMap p = test::simSlamParameters();
  p[Parameters::kRGBDMaxLoopClosureDistance()] = "0";
  std::map<int, Transform> groundTruth;
  SimSlamRun last;
  for (int s = 1; s <= 3; ++s) {
    last = SimSlamRun();
    test::runSimSlam(folder + "/session" + std::to_string(s), p, dir.file("rtabmap.db"), last);
    if (s < 3) groundTruth.insert(last.groundTruth.begin(), last.groundTruth.end());
  }
  // Session 3 usually first merges 11 m off (an aliased closure) and the refused true closures
  // redo it; since the simulator's floors vary per tile the alias is not certain in every run
  // (FLANN's trees are random), 1 run in 4 or so merges right at once. Either way what must hold
  // is below: session 3 ends merged through its true closures only. The vote itself is tested
  // deterministically in MergeArbiter_test.
  if (last.summary.remerges == 0) std::cout << "session 3 merged right at once: no merge to redo" << std::endl;
  RecordProperty("remerges", last.summary.remerges);
  // Session 3's loop closures to the earlier sessions, as the database keeps them.
  std::multimap<int, Link> between;
  for (const auto& [from, link] : last.links) {
    const bool a = last.groundTruth.count(link.from()) != 0, b = last.groundTruth.count(link.to()) != 0;
    if (a != b) between.emplace(from, link);
  }
  groundTruth.insert(last.groundTruth.begin(), last.groundTruth.end());
  int count = 0;
  std::string which;
  EXPECT_LT(test::worstLinkError(between, groundTruth, {Link::kGlobalClosure}, &count, &which), 0.25) << which;
  EXPECT_GE(count, 3) << "session 3 is merged through its true closures";
}

// Every node assembled at its pose of the graph, to the bit, with a sensor model whose updates
// never reach the clamping bounds (where the order of updates would matter; 0.04 a hit, 0.04 a
// miss: 170 updates to a bound): the grid SLAM assembled is then the one built from scratch.
void useOrderFreeGridModel(ParametersMap& p) {
  p["GridGlobal/UpdateError"] = "0";
  p["GridGlobal/ProbHit"] = "0.51";
  p["GridGlobal/ProbMiss"] = "0.49";
  p["GridGlobal/ProbClampingMin"] = "0.001";
  p["GridGlobal/ProbClampingMax"] = "0.999";
}

// The grid of slam's optimised graph built from scratch, every node's local grid in RAM.
void buildMapOfTheGraph(const Rtabmap& slam, const ParametersMap& p, GridMap& out) {
  OccupancyGrid fresh(GlobalGridOptions::fromParameters(p));
  const std::map<int, Transform> poses = slam.optimizedPoses();
  for (const auto& [id, pose] : poses) {
    const std::optional<Signature> n = slam.node(id);
    ASSERT_TRUE(n) << id;
    if (!n->sensorData().localGrid().isEmpty()) {
      ASSERT_TRUE(fresh.addLocalGrid(id, n->sensorData().localGrid()));
    }
  }
  fresh.update(poses);
  out = fresh.map();
}

// Issue 10: with Working Memory bounded, the global grid keeps in RAM the cells of Working Memory
// nodes only; the loop closure's re-assemblies read those of Long-Term Memory nodes back from the
// database, or start from the tiles' Long-Term Memory layers. With a sensor model whose updates
// never reach the clamping bounds (where the order of updates would matter), the grid is then
// the one built with every node's local grid in RAM at the same poses.
TEST(SimSlam, GridReassembliesReadLongTermMemoryCellsBackAndGiveTheSameMap) {
  REQUIRE_SIM(folder, "loop");
  test::TempDir dir("rtabmap_slam_grid_ltm");
  ParametersMap p = test::simSlamParameters();
  p["Rtabmap/MemoryThr"] = "30";
  p["GridGlobal/LtmCacheSize"] = "0.05";  // 50 KB: most replays of LTM nodes read them back
  useOrderFreeGridModel(p);
  std::unique_ptr<DatasetReader> reader = openDatasetReader("sim", folder);
  Rtabmap slam;
  slam.init(p, dir.file("rtabmap.db"));
  DatasetRecord record;
  float readBack = 0.0f, notReadBack = 0.0f, inLayers = 0.0f, maxResident = 0.0f;
  while (reader->next(record)) {
    if (record.kind != DatasetRecord::Kind::kFrame || !slam.process(record.data)) continue;
    const auto& d = slam.statistics().data();
    auto get = [&d](const char* key) { return d.count(key) ? d.at(key) : 0.0f; };
    readBack += get("Memory/Grid_nodes_read_back/");
    notReadBack += get("Memory/Grid_nodes_not_read_back/");
    inLayers += get("Memory/Grid_nodes_in_layers/");
    maxResident = std::max(maxResident, get("Memory/Grid_nodes_resident/"));
  }
  const std::map<int, Transform> poses = slam.optimizedPoses();
  ASSERT_GT(poses.size(), 100u);
  EXPECT_GT(slam.summary().transferred, 50);
  EXPECT_GT(readBack, 0.0f) << "no re-assembly replayed a node of the LTM: the test proves nothing";
  EXPECT_EQ(notReadBack, 0.0f);
  // A short run (the layers pay off over hours): their replays spared still count.
  EXPECT_GT(inLayers, 0.5f * readBack) << "the tiles' layers spared few replays";
  std::cerr << "nodes read back " << readBack << ", re-assembled from the layers " << inLayers << '\n';
  // Working Memory (30) + STM + the nodes retrieved this update, not the map.
  EXPECT_LT(maxResident, 60.0f);
  EXPECT_GT(maxResident, 0.0f);

  GridMap expected;
  ASSERT_NO_FATAL_FAILURE(buildMapOfTheGraph(slam, p, expected));
  const GridMap actual = slam.gridMap();
  ASSERT_FALSE(expected.empty());
  ASSERT_EQ(expected.data.size(), actual.data.size());
  EXPECT_DOUBLE_EQ(expected.originX, actual.originX);
  EXPECT_DOUBLE_EQ(expected.originY, actual.originY);
  EXPECT_EQ(cv::countNonZero(expected.data != actual.data), 0);
  slam.close();
}

// GridGlobal/ReassemblyInterval: the re-assemblies of the loop's corrections wait a few updates
// (new nodes appended at once); when the robot stands still the next frame assembles what waits,
// and the map is then the one of the graph (built from scratch, useOrderFreeGridModel).
TEST(SimSlam, DeferredGridReassembliesCatchUpWhenTheRobotStandsStill) {
  REQUIRE_SIM(folder, "loop");
  test::TempDir dir("rtabmap_slam_grid_deferred");
  ParametersMap p = test::simSlamParameters();
  p["GridGlobal/ReassemblyInterval"] = "4";
  useOrderFreeGridModel(p);
  std::unique_ptr<DatasetReader> reader = openDatasetReader("sim", folder);
  Rtabmap slam;
  slam.init(p, dir.file("rtabmap.db"));
  DatasetRecord record;
  int deferred = 0, longest = 0;
  SensorData last;
  // Up to an update whose changes wait, once the loop has been closed a few times.
  while (reader->next(record)) {
    if (record.kind != DatasetRecord::Kind::kFrame || !slam.process(record.data)) continue;
    const auto& d = slam.statistics().data();
    const int waiting = d.count("Memory/Grid_updates_deferred/") ? static_cast<int>(d.at("Memory/Grid_updates_deferred/")) : 0;
    deferred += waiting > 0;
    longest = std::max(longest, waiting);
    last = record.data;
    if (deferred >= 10 && waiting > 0 && slam.optimizedPoses().size() > 100) break;
  }
  ASSERT_GE(deferred, 10) << "too few corrections deferred: the test proves nothing";
  EXPECT_EQ(longest, 3);  // never more than N - 1 updates late

  auto mapOfTheGraph = [&] {
    GridMap m;
    buildMapOfTheGraph(slam, p, m);
    return m;
  };
  auto differingCells = [](const GridMap& a, const GridMap& b) {
    if (a.data.size() != b.data.size() || a.originX != b.originX || a.originY != b.originY) return -1;
    return cv::countNonZero(a.data != b.data);
  };
  EXPECT_NE(differingCells(mapOfTheGraph(), slam.gridMap()), 0) << "the waiting changes do not show";
  // The robot stands: the same odometry two seconds later.
  SensorData still = last;
  still.setStamp(last.stamp() + 2.0);
  const int stillBefore = slam.summary().skippedStill;
  slam.process(still);
  EXPECT_EQ(slam.summary().skippedStill, stillBefore + 1);
  EXPECT_EQ(differingCells(mapOfTheGraph(), slam.gridMap()), 0);
  slam.close();
}

}  // namespace
}  // namespace rtabmap
