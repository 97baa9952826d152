// RGBD/LocalBundleOnLoopClosure (src/slam/LocalBundle.h): the local feature map around a node
// of memory, and a new view registered against it then refined by bundle adjustment.
#include <gtest/gtest.h>

#include <set>

#include "../../src/slam/LinkRegistration.h"
#include "../../src/slam/LocalBundle.h"
#include "odometry/SyntheticRoom.h"
#include "rtabmap_core/features/FeatureDetector.h"
#include "rtabmap_core/memory/Memory.h"
#include "rtabmap_core/memory/Signature.h"
#include "rtabmap_core/registration/RegistrationVis.h"

namespace rtabmap {
namespace {

using test::SyntheticRoom;

// Three nodes along a short path in the room (their links exact: the poses are the truth), and
// a later view near the middle one, as a loop closure would find it.
const Transform kPath[3] = {Transform(-0.3, 0.0, 1.2, 0.0, 0.0, 0.35), Transform(0.0, 0.0, 1.2, 0.0, 0.0, 0.0),
                            Transform(0.3, 0.05, 1.2, 0.0, 0.0, -0.35)};
const Transform kRevisit(0.08, -0.1, 1.25, 0.0, 0.02, 0.12);

struct Place {
  SyntheticRoom room;
  CameraModel camera = SyntheticRoom::camera();
  FeatureDetector detector{FeatureOptions()};

  memory::LocationInput location(const Transform& pose, int id) const {
    memory::LocationInput in;
    in.data = room.rgbd(pose, camera, id, id);
    const ImageFeatures f = detector.extract(in.data);
    in.keypoints = f.keypoints;
    in.descriptors = f.descriptors;
    in.points3D = f.points3D;
    in.pose = pose;
    in.stamp = id;
    return in;
  }
};

memory::MemoryOptions keepEveryNode() {
  memory::MemoryOptions o;
  o.stmSize = 10;
  o.rehearsalSimilarity = 1.0f;  // the views overlap: no merging
  return o;
}

TEST(LocalBundle, TheMapHoldsTheNodesAndItsNeighboursWordsInItsFrame) {
  const Place place;
  memory::Memory memory(keepEveryNode());
  int ids[3];
  for (int i = 0; i < 3; ++i) ids[i] = memory.addLocation(place.location(kPath[i], i + 1)).id;
  const LocalFeatureMap map = localFeatureMap(memory, ids[1]);
  ASSERT_TRUE(map.problem.empty()) << map.problem;
  ASSERT_EQ(map.views.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(map.views.count(ids[i]));
    EXPECT_LT(map.views.at(ids[i]).pose.getDistance(kPath[1].inverse() * kPath[i]), 1e-6) << "node " << ids[i];
  }
  // Ids are unique; the center's words keep its own points; the neighbours add words.
  const std::set<int> unique(map.frame.ids.begin(), map.frame.ids.end());
  EXPECT_EQ(unique.size(), map.frame.ids.size());
  ASSERT_EQ(map.frame.points3D.size(), map.frame.ids.size());
  ASSERT_EQ(map.frame.descriptors.rows, static_cast<int>(map.frame.ids.size()));
  const Signature& center = *memory.signature(ids[1]);
  size_t own = 0;
  for (size_t k = 0; k < map.frame.ids.size(); ++k) {
    const int wordId = map.frame.ids[k];
    if (center.getWords().count(wordId) != 1) continue;
    const cv::Point3f& p = center.getWords3()[static_cast<size_t>(center.getWords().find(wordId)->second)];
    if (!std::isfinite(p.x)) continue;
    EXPECT_LT(cv::norm(map.frame.points3D[k] - p), 1e-6) << "word " << wordId;
    ++own;
  }
  EXPECT_GT(own, 50u);
  // A word the center did not see has the point of the first neighbour that did, through its link.
  size_t placed = 0;
  for (size_t k = 0; k < map.frame.ids.size(); ++k) {
    const int wordId = map.frame.ids[k];
    if (center.getWords().count(wordId) != 0) continue;
    const Signature& first = *memory.signature(ids[0]);
    if (first.getWords().count(wordId) != 1) continue;
    const cv::Point3f& p = first.getWords3()[static_cast<size_t>(first.getWords().find(wordId)->second)];
    const Eigen::Vector3d expected = map.views.at(ids[0]).pose.toEigen() * Eigen::Vector3d(p.x, p.y, p.z);
    const cv::Point3f& q = map.frame.points3D[k];
    EXPECT_LT((expected - Eigen::Vector3d(q.x, q.y, q.z)).norm(), 1e-5) << "word " << wordId;
    ++placed;
  }
  EXPECT_GT(placed, 10u);
  EXPECT_GT(map.frame.ids.size(), own + 20) << "the neighbours add the words the center did not see";
  // The center's observations of its words, for the adjustment.
  EXPECT_GE(map.observations.size(), own);
  for (const BundleAdjustmentObservation& o : map.observations) {
    EXPECT_EQ(o.frame, ids[1]);
    ASSERT_TRUE(unique.count(o.point));
  }
}

TEST(LocalBundle, ARevisitRegisteredToTheMapIsTheTruth) {
  const Place place;
  memory::Memory memory(keepEveryNode());
  int ids[3];
  for (int i = 0; i < 3; ++i) ids[i] = memory.addLocation(place.location(kPath[i], i + 1)).id;
  Signature current(place.room.rgbd(kRevisit, place.camera, 10, 10.0));
  const RegistrationVis visual;
  RegistrationInfo info;
  const Transform t = registerToLocalMap(localFeatureMap(memory, ids[1]), current, visual, true, Transform(), &info);
  ASSERT_FALSE(t.isNull()) << info.rejectedMsg;
  const Transform truth = kRevisit.inverse() * kPath[1];  // current -> center, the link's direction
  // The room's rendering leaves both registrations about 1 cm off (the two nodes' alone too).
  EXPECT_LT(t.getDistance(truth), 0.015) << t.prettyPrint() << " vs " << truth.prettyPrint();
  EXPECT_LT((truth.inverse() * t).getAngle(), 0.01);
  EXPECT_GE(info.inliers, visual.options().minInliers);
  EXPECT_EQ(static_cast<size_t>(info.inliers), info.inliersIDs.size());
  EXPECT_TRUE(info.covariance.allFinite());
  EXPECT_GT(info.covariance(0, 0), 0.0);

  // The two nodes alone find fewer correspondences: the neighbours saw what the center missed.
  Signature again(place.room.rgbd(kRevisit, place.camera, 10, 10.0));
  Signature center = *memory.signature(ids[1]);
  RegistrationInfo pair;
  const Transform two = visual.computeTransform(again, center, Transform(), &pair);
  ASSERT_FALSE(two.isNull()) << pair.rejectedMsg;
  EXPECT_LT(two.getDistance(truth), 0.015);
  EXPECT_GT(info.matches, pair.matches);
  EXPECT_GT(info.inliers, pair.inliers);
}

TEST(LocalBundle, NoMapWithoutNeighboursOrDescriptors) {
  const Place place;
  memory::Memory alone(keepEveryNode());
  const int id = alone.addLocation(place.location(kPath[1], 1)).id;
  EXPECT_NE(localFeatureMap(alone, id).problem.find("no neighbour"), std::string::npos);
  EXPECT_NE(localFeatureMap(alone, id + 5).problem.find("not in memory"), std::string::npos);

  memory::MemoryOptions noDescriptors = keepEveryNode();
  noDescriptors.rawDescriptorsKept = false;
  memory::Memory bare(noDescriptors);
  int ids[2];
  for (int i = 0; i < 2; ++i) ids[i] = bare.addLocation(place.location(kPath[i], i + 1)).id;
  EXPECT_NE(localFeatureMap(bare, ids[1]).problem.find("no word descriptors"), std::string::npos);

  // And registration against a map that has a problem says so instead of registering.
  Signature current(place.room.rgbd(kRevisit, place.camera, 10, 10.0));
  RegistrationInfo info;
  EXPECT_TRUE(registerToLocalMap(localFeatureMap(alone, id), current, RegistrationVis(), true, Transform(), &info)
                  .isNull());
  EXPECT_NE(info.rejectedMsg.find("local feature map"), std::string::npos);
}

}  // namespace
}  // namespace rtabmap
