// Loop-closure precision / recall on a small hand-made case.
#include "rtabmap_core/eval/LoopClosureEval.h"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <limits>

#include "common/TestData.h"
#include "eval/EvalTestUtil.h"
#include "rtabmap_core/common/Error.h"

using rtabmap::FormatError;
using rtabmap::LoopDetection;
using rtabmap::LoopGroundTruth;
using rtabmap::Transform;
using rtabmap::test::TempDir;
using rtabmap::test::writeText;

namespace {

// 10 images; 6..8 revisit 1..3 and 10 revisits 5; 9 is new.
cv::Mat groundTruthMatrix() {
  cv::Mat m = cv::Mat::zeros(10, 10, CV_8UC1);
  m.at<uint8_t>(5, 0) = 255;
  m.at<uint8_t>(6, 1) = 255;
  m.at<uint8_t>(7, 2) = 255;
  m.at<uint8_t>(9, 4) = 255;
  return m;
}

const char* kDetections =
    "# query matched confidence\n"
    "1 0 0\n2 0 0\n3 0 0\n4 0 0\n5 0 0\n"
    "6 1 0.9\n"   // true
    "7 2 0.8\n"   // true
    "8 4 0.7\n"   // false: 8 revisits 3, not 4
    "9 3 0.6\n"   // false: 9 is a new place
    "10 5 0.5\n";  // true

}  // namespace

TEST(LoopClosurePR, ByHand) {
  TempDir dir;
  writeText(dir.file("d.txt"), kDetections);
  const auto detections = rtabmap::readLoopDetections(dir.file("d.txt"));
  ASSERT_EQ(detections.size(), 10u);
  const LoopGroundTruth gt = LoopGroundTruth::fromMatrix(groundTruthMatrix());
  EXPECT_EQ(gt.size(), 10);
  EXPECT_EQ(gt.positives(), 4u);
  EXPECT_TRUE(gt.isLoop(6, 1));
  EXPECT_TRUE(gt.isLoop(1, 6));  // read symmetrically
  EXPECT_FALSE(gt.isLoop(8, 4));
  EXPECT_TRUE(gt.hasLoopWithEarlier(10));
  EXPECT_FALSE(gt.hasLoopWithEarlier(1));

  auto r = rtabmap::computeLoopClosurePR(detections, gt);
  EXPECT_EQ(r.queries, 10u);
  EXPECT_EQ(r.positives, 4u);
  EXPECT_EQ(r.detections, 5u);
  EXPECT_EQ(r.truePositives, 3u);
  EXPECT_EQ(r.falsePositives, 2u);
  EXPECT_EQ(r.falseNegatives, 1u);  // image 8
  EXPECT_DOUBLE_EQ(r.precision, 0.6);
  EXPECT_DOUBLE_EQ(r.recall, 0.75);
  // Sweep: 0.9 -> 1/4, 0.8 -> 2/4 (still no false positive), 0.7 -> first false positive.
  EXPECT_DOUBLE_EQ(r.recallAt100Precision, 0.5);
  EXPECT_DOUBLE_EQ(r.thresholdAt100Precision, 0.8);
  ASSERT_EQ(r.curve.size(), 5u);
  EXPECT_DOUBLE_EQ(r.curve[2].precision, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(r.curve[4].recall, 0.75);

  r = rtabmap::computeLoopClosurePR(detections, gt, 0.75);
  EXPECT_EQ(r.truePositives, 2u);
  EXPECT_EQ(r.falsePositives, 0u);
  EXPECT_DOUBLE_EQ(r.precision, 1.0);
  EXPECT_DOUBLE_EQ(r.recall, 0.5);

  // The most confident detection wrong: no recall at 100% precision.
  std::vector<LoopDetection> wrongFirst = detections;
  wrongFirst[8].confidence = 0.95;  // 9 -> 3
  r = rtabmap::computeLoopClosurePR(wrongFirst, gt);
  EXPECT_DOUBLE_EQ(r.recallAt100Precision, 0.0);
  EXPECT_TRUE(std::isinf(r.thresholdAt100Precision));
}

TEST(LoopClosurePR, MatrixAsImageOrTextAndFromPoses) {
  TempDir dir;
  cv::imwrite(dir.file("gt.png"), groundTruthMatrix());
  LoopGroundTruth gt = LoopGroundTruth::readMatrix(dir.file("gt.png"));
  EXPECT_EQ(gt.positives(), 4u);
  EXPECT_TRUE(gt.isLoop(10, 5));
  // Text, upper triangle filled instead, commas.
  std::string text;
  const cv::Mat m = groundTruthMatrix().t();
  for (int r = 0; r < m.rows; ++r) {
    for (int c = 0; c < m.cols; ++c) text += (c ? "," : "") + std::string(m.at<uint8_t>(r, c) ? "1" : "0");
    text += "\n";
  }
  writeText(dir.file("gt.txt"), text);
  gt = LoopGroundTruth::readMatrix(dir.file("gt.txt"));
  EXPECT_EQ(gt.positives(), 4u);
  EXPECT_TRUE(gt.isLoop(8, 3));
  writeText(dir.file("notsquare.txt"), "0 1\n1 0\n0 0\n");
  EXPECT_THROW(LoopGroundTruth::readMatrix(dir.file("notsquare.txt")), FormatError);

  // Poses: out along x (heading 0) over 0..5 m, then back (heading pi) over 4..0 m.
  std::vector<Transform> poses;
  for (int i = 0; i <= 5; ++i) poses.push_back(Transform(i, 0, 0));
  for (int i = 4; i >= 0; --i) poses.push_back(Transform(i, 0, M_PI));
  // Ignoring orientation: image 7 (x = 4) revisits 5 (x = 4), ... image 11 (x = 0) revisits 1.
  gt = LoopGroundTruth::fromPoses(poses, 0.5, 0.0, 2);
  EXPECT_EQ(gt.size(), 11);
  EXPECT_EQ(gt.positives(), 5u);
  EXPECT_TRUE(gt.isLoop(7, 5));
  EXPECT_TRUE(gt.isLoop(11, 1));
  EXPECT_FALSE(gt.isLoop(7, 6));  // 1 m apart
  // Facing the other way, within 30 degrees only: no loop.
  gt = LoopGroundTruth::fromPoses(poses, 0.5, 30 * M_PI / 180, 2);
  EXPECT_EQ(gt.positives(), 0u);
  // The minimum gap excludes neighbours: with 1.1 m, 6->5 would be a loop, not with gap 2.
  gt = LoopGroundTruth::fromPoses(poses, 1.1, 0.0, 2);
  EXPECT_FALSE(gt.isLoop(2, 1));
  EXPECT_FALSE(gt.isLoop(3, 1));
  EXPECT_TRUE(gt.isLoop(7, 4));
}

// Three bands, as the loop-closure issue's 7-Scenes ground truth: a loop within 0.5 m and 30
// degrees, neither within 1.5 m and 60 degrees, false beyond.
TEST(LoopClosurePR, AmbiguousBandIsNeitherTrueNorFalse) {
  using rtabmap::LoopDetection;
  using rtabmap::LoopGroundTruth;
  using rtabmap::Transform;
  std::vector<Transform> poses;
  for (int i = 0; i < 10; ++i) poses.push_back(Transform(i, 0, 0));  // images 1..10 along x
  poses.push_back(Transform(0.3, 0, 0.2));  // 11: back near image 1, turned 11 degrees
  poses.push_back(Transform(1.0, 0, 0.8));  // 12: 1 m from image 1, 46 degrees off
  poses.push_back(Transform(1.0, 0, 1.2));  // 13: 1 m from image 1, 69 degrees off
  poses.push_back(Transform(3.0, 0, 0.0));  // 14: same place as image 4
  LoopGroundTruth::PoseCriteria criteria;
  criteria.maxDistance = 0.5;
  criteria.maxAngle = 30 * M_PI / 180;
  criteria.minFrameGap = 5;
  criteria.ambiguousDistance = 1.5;
  criteria.ambiguousAngle = 60 * M_PI / 180;
  const LoopGroundTruth gt = LoopGroundTruth::fromPoses(poses, criteria);
  EXPECT_TRUE(gt.isLoop(11, 1));
  EXPECT_FALSE(gt.isAmbiguous(11, 1));  // a loop is not also ambiguous
  EXPECT_TRUE(gt.isAmbiguous(11, 2));   // 0.7 m
  EXPECT_TRUE(gt.isAmbiguous(2, 11));   // symmetric
  EXPECT_TRUE(gt.isAmbiguous(12, 1));   // 1 m and 46 degrees
  EXPECT_FALSE(gt.isAmbiguous(13, 1));  // 69 degrees: false
  EXPECT_FALSE(gt.isAmbiguous(11, 3));  // 1.7 m: false
  EXPECT_FALSE(gt.isAmbiguous(14, 9));  // within the gap's reach but 5 m: false
  EXPECT_TRUE(gt.isLoop(14, 4));
  // The two-band ground truth has no ambiguous pair.
  EXPECT_FALSE(LoopGroundTruth::fromPoses(poses, 0.5, 30 * M_PI / 180, 5).isAmbiguous(11, 2));

  // Detections: 11 -> 2 ambiguous (conf 0.9), 12 -> 1 ambiguous (0.8), 13 -> 1 false (0.3),
  // 14 -> 4 true (0.6).
  const std::vector<LoopDetection> detections = {{11, 2, 0.9}, {12, 1, 0.8}, {13, 1, 0.3}, {14, 4, 0.6}};
  const rtabmap::LoopClosurePR at0 = rtabmap::computeLoopClosurePR(detections, gt, 0.0);
  EXPECT_EQ(at0.truePositives, 1u);
  EXPECT_EQ(at0.falsePositives, 1u);
  EXPECT_EQ(at0.ambiguous, 2u);
  EXPECT_DOUBLE_EQ(at0.precision, 0.5);
  EXPECT_EQ(at0.positives, 2u);  // images 11 and 14 have a loop with an earlier one
  EXPECT_DOUBLE_EQ(at0.recall, 0.5);
  // Above the false detection's confidence, precision is 100% although two ambiguous ones are
  // accepted before the true one.
  EXPECT_DOUBLE_EQ(at0.recallAt100Precision, 0.5);
  EXPECT_DOUBLE_EQ(at0.thresholdAt100Precision, 0.6);
  const rtabmap::LoopClosurePR at07 = rtabmap::computeLoopClosurePR(detections, gt, 0.7);
  EXPECT_EQ(at07.ambiguous, 2u);
  EXPECT_EQ(at07.truePositives + at07.falsePositives, 0u);
  // A band narrower than the loop distance is refused.
  criteria.ambiguousDistance = 0.4;
  EXPECT_THROW(LoopGroundTruth::fromPoses(poses, criteria), FormatError);
}

// A hand-held camera rolled about its optical axis sees the same place: with
// viewingDirectionOnly the angle is the one between the viewing directions, so a roll does not
// count and a turn does.
TEST(LoopClosurePR, ViewingDirectionIgnoresRollAboutTheViewingAxis) {
  using rtabmap::LoopGroundTruth;
  using rtabmap::Transform;
  std::vector<Transform> poses;
  for (int i = 0; i < 5; ++i) poses.push_back(Transform(i, 0, 0, 0, 0, 0));  // 1..5 along x, facing +x
  poses.push_back(Transform(0.1, 0, 0, M_PI / 2, 0, 0));                     // 6: at 1, rolled 90 degrees
  poses.push_back(Transform(0.1, 0, 0, 0, 0, M_PI / 4));                     // 7: at 1, turned 45 degrees
  poses.push_back(Transform(0.1, 0, 0, 0, M_PI / 9, 0));                     // 8: at 1, pitched 20 degrees
  LoopGroundTruth::PoseCriteria criteria;
  criteria.maxDistance = 0.3;
  criteria.maxAngle = 30 * M_PI / 180;
  criteria.minFrameGap = 3;
  const LoopGroundTruth whole = LoopGroundTruth::fromPoses(poses, criteria);
  EXPECT_FALSE(whole.isLoop(6, 1));  // a 90-degree relative rotation
  EXPECT_FALSE(whole.isLoop(7, 1));
  EXPECT_TRUE(whole.isLoop(8, 1));
  criteria.viewingDirectionOnly = true;
  const LoopGroundTruth viewing = LoopGroundTruth::fromPoses(poses, criteria);
  EXPECT_TRUE(viewing.isLoop(6, 1));   // same viewing direction
  EXPECT_FALSE(viewing.isLoop(7, 1));  // 45 degrees apart
  EXPECT_TRUE(viewing.isLoop(8, 1));   // 20 degrees apart
  // Another axis: along y, the roll of image 6 turns its y axis by 90 degrees.
  criteria.viewingAxis = Eigen::Vector3d::UnitY();
  EXPECT_FALSE(LoopGroundTruth::fromPoses(poses, criteria).isLoop(6, 1));
  criteria.viewingAxis = Eigen::Vector3d::Zero();
  EXPECT_THROW(LoopGroundTruth::fromPoses(poses, criteria), rtabmap::FormatError);
}

TEST(LoopClosurePR, MalformedDetections) {
  TempDir dir;
  writeText(dir.file("dup.txt"), "1 0 0\n2 1 0.5\n2 1 0.7\n");
  try {
    rtabmap::readLoopDetections(dir.file("dup.txt"));
    ADD_FAILURE();
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("dup.txt:3:"), std::string::npos) << e.what();
  }
  writeText(dir.file("neg.txt"), "1 -1 0\n");
  EXPECT_THROW(rtabmap::readLoopDetections(dir.file("neg.txt")), FormatError);
  writeText(dir.file("two.txt"), "1 0\n2 1\n");
  const auto d = rtabmap::readLoopDetections(dir.file("two.txt"));
  ASSERT_EQ(d.size(), 2u);
  EXPECT_DOUBLE_EQ(d[1].confidence, 1.0);
}
