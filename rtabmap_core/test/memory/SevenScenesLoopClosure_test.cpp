// Appearance-based loop closure on real images (issue: "Loop closure on real images"): the
// 600 frames of a hand-held RGB-D sequence over one small 7-Scenes scene, ground truth from its
// KinectFusion poses in three bands: a pair is a true loop when the camera centres are within
// 0.3 m and the viewing directions within 30 degrees, a false one beyond 1 m or 60 degrees,
// neither in between. At default parameters no accepted loop closure may be false.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <map>
#include <vector>

#include "common/TestData.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/eval/LoopClosureEval.h"
#include "rtabmap_core/features/FeatureDetector.h"
#include "rtabmap_core/memory/LoopClosureDetector.h"

namespace rtabmap::memory {
namespace {

// The issue's three bands: a true loop within 0.3 m and 30 degrees between the viewing
// directions, false beyond 1 m or 60 degrees, neither in between. minFrameGap: any earlier frame.
LoopGroundTruth::PoseCriteria issueBands(int minFrameGap) {
  LoopGroundTruth::PoseCriteria c;
  c.maxDistance = 0.3;
  c.maxAngle = 30.0 * M_PI / 180.0;
  c.minFrameGap = minFrameGap;
  c.ambiguousDistance = 1.0;
  c.ambiguousAngle = 60.0 * M_PI / 180.0;
  c.viewingDirectionOnly = true;  // the base frame's x axis: the camera's optical axis
  return c;
}

TEST(SevenScenesLoopClosure, NoFalseLoopClosureAtDefaultParameters) {
  RTABMAP_REQUIRE_DATA(path, "rgbd_7scenes");
  auto reader = openDatasetReader("7scenes", path);
  const ParametersMap defaults;
  auto features = FeatureDetector::create(defaults, FeatureGroup::kKp);
  LoopClosureDetector detector(LoopClosureDetectorOptions::fromParameters(defaults), nullptr);

  std::map<int, int> frameOf;  // location id -> frame index
  std::vector<Transform> frames;
  struct Accepted {
    int frame, other;
  };
  std::vector<Accepted> closures;
  DatasetRecord record;
  while (reader->next(record)) {
    if (record.kind != DatasetRecord::Kind::kFrame) continue;
    const int frame = static_cast<int>(frames.size());
    frames.push_back(record.data.groundTruth());
    ImageFeatures f = features->extract(record.data);
    LocationInput in;
    in.keypoints = std::move(f.keypoints);
    in.descriptors = f.descriptors;
    in.stamp = record.stamp;
    const LoopClosureUpdate u = detector.process(in);
    if (u.id > 0 && !u.merged) frameOf[u.id] = frame;
    if (u.loopClosureId) closures.push_back({frame, frameOf.at(u.loopClosureId)});
  }
  // Image ids of the ground truth are 1-based frame indices.
  const LoopGroundTruth truth = LoopGroundTruth::fromPoses(frames, issueBands(1));
  int falseOnes = 0, trueOnes = 0, longSpan = 0;
  for (const Accepted& c : closures) {
    const bool isTrue = truth.isLoop(c.frame + 1, c.other + 1);
    const bool isFalse = !isTrue && !truth.isAmbiguous(c.frame + 1, c.other + 1);
    falseOnes += isFalse;
    trueOnes += isTrue;
    longSpan += c.frame - c.other > 100;
    EXPECT_FALSE(isFalse) << "frame " << c.frame << " accepted a loop with frame " << c.other;
  }
  // Frames that had a true candidate (a true-band frame more than STM behind).
  const size_t withCandidate = LoopGroundTruth::fromPoses(frames, issueBands(11)).positives();
  const int accepted = static_cast<int>(closures.size());
  std::cout << "[ 7-Scenes ] frames " << frames.size() << ", with a true candidate " << withCandidate
            << ", accepted " << accepted << " (true band " << trueOnes << ", false " << falseOnes
            << "), spanning more than 100 frames " << longSpan << std::endl;
  EXPECT_EQ(frames.size(), 600u);
  EXPECT_EQ(falseOnes, 0);
  EXPECT_GT(accepted, 400);  // the camera revisits the scene all the time (589 frames could close)
}

}  // namespace
}  // namespace rtabmap::memory
