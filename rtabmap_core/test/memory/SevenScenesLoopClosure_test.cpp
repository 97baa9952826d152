// Appearance-based loop closure on real images (issue: "Loop closure on real images"): the
// 600 frames of a hand-held RGB-D sequence over one small 7-Scenes scene, ground truth from its
// KinectFusion poses in three bands: a pair is a true loop when the camera centres are within
// 0.3 m and the viewing directions within 30 degrees, a false one beyond 1 m or 60 degrees,
// neither in between. At default parameters no accepted loop closure may be false.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <map>

#include "common/TestData.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/features/FeatureDetector.h"
#include "rtabmap_core/memory/LoopClosureDetector.h"

namespace rtabmap::memory {
namespace {

enum class Band { kTrue, kFalse, kNeither };

Band classify(const Transform& a, const Transform& b) {
  const Eigen::Vector3d ca = a.toEigen().translation(), cb = b.toEigen().translation();
  // The base frame has ROS body axes: the camera looks along x.
  const Eigen::Vector3d da = a.toEigen().linear() * Eigen::Vector3d::UnitX();
  const Eigen::Vector3d db = b.toEigen().linear() * Eigen::Vector3d::UnitX();
  const double distance = (ca - cb).norm();
  const double angle = std::acos(std::clamp(da.dot(db), -1.0, 1.0)) * 180.0 / M_PI;
  if (distance <= 0.3 && angle <= 30.0) return Band::kTrue;
  if (distance > 1.0 || angle > 60.0) return Band::kFalse;
  return Band::kNeither;
}

TEST(SevenScenesLoopClosure, NoFalseLoopClosureAtDefaultParameters) {
  RTABMAP_REQUIRE_DATA(path, "rgbd_7scenes");
  auto reader = openDatasetReader("7scenes", path);
  const ParametersMap defaults;
  auto features = FeatureDetector::create(defaults, FeatureGroup::kKp);
  LoopClosureDetector detector(LoopClosureDetectorOptions::fromParameters(defaults), nullptr);

  std::map<int, Transform> groundTruth;  // location id -> pose
  std::map<int, int> frameOf;            // location id -> frame index
  std::vector<Transform> frames;
  int accepted = 0, falseOnes = 0, trueOnes = 0, longSpan = 0;
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
    if (!u.loopClosureId) continue;
    ++accepted;
    const int other = frameOf.at(u.loopClosureId);
    const Band band = classify(frames[frame], frames[other]);
    falseOnes += band == Band::kFalse;
    trueOnes += band == Band::kTrue;
    longSpan += frame - other > 100;
    EXPECT_NE(band, Band::kFalse) << "frame " << frame << " accepted a loop with frame " << other;
  }
  // Frames that had a true candidate (a true-band frame more than STM behind).
  int withCandidate = 0;
  for (size_t i = 0; i < frames.size(); ++i) {
    for (size_t j = 0; j + 10 < i; ++j) {
      if (classify(frames[i], frames[j]) == Band::kTrue) {
        ++withCandidate;
        break;
      }
    }
  }
  std::cout << "[ 7-Scenes ] frames " << frames.size() << ", with a true candidate " << withCandidate
            << ", accepted " << accepted << " (true band " << trueOnes << ", false " << falseOnes
            << "), spanning more than 100 frames " << longSpan << std::endl;
  EXPECT_EQ(frames.size(), 600u);
  EXPECT_EQ(falseOnes, 0);
  EXPECT_GT(accepted, 400);  // the camera revisits the scene all the time (589 frames could close)
}

}  // namespace
}  // namespace rtabmap::memory
