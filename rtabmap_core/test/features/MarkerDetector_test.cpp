// Fiducial markers as landmarks (RGBD/MarkerDetection, Marker/*): poses from synthetic views
// rendered at known poses, the side measured from depth, and what is skipped and why.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include <cmath>

#include "common/MarkerScene.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/features/MarkerDetector.h"
#include "rtabmap_core/geometry/SensorData.h"

namespace rtabmap {
namespace {

using test::MarkerInView;
using test::markerAhead;
using test::renderMarkers;

constexpr int kAruco4x4_50 = 0;
constexpr int kAprilTag36h11 = 20;

CameraModel camera(const Transform& local = CameraModel::opticalRotation()) {
  return CameraModel(525.0, 525.0, 319.5, 239.5, local, 0.0, cv::Size(640, 480));
}

SensorData frameOf(const CameraModel& model, const std::vector<MarkerInView>& markers, int dictionary,
                   bool withDepth = true) {
  const test::MarkerView v = renderMarkers(model, markers, dictionary, 2.5f);
  return SensorData(v.grey, withDepth ? v.depth : cv::Mat(), model, 1, 1.0);
}

MarkerDetectorOptions withLength(float length, int dictionary = kAruco4x4_50) {
  MarkerDetectorOptions o;
  o.dictionary = dictionary;
  o.length = length;
  return o;
}

void expectNear(const Transform& a, const Transform& b, double metres, double radians) {
  const Transform d = a.inverse() * b;
  EXPECT_LT(d.getNorm(), metres) << a.prettyPrint() << " vs " << b.prettyPrint();
  EXPECT_LT(std::fabs(d.getAngle()), radians) << a.prettyPrint() << " vs " << b.prettyPrint();
}

TEST(MarkerDetector, PoseInTheBaseFrameMatchesWhereTheMarkerWasDrawn) {
  const CameraModel model = camera(Transform(0.1, 0.0, 0.3, 0, 0, 0) * CameraModel::opticalRotation());
  const std::vector<MarkerInView> drawn = {{3, 0.2f, markerAhead(1.2, 0.4, 0.15, -0.05)},
                                           {9, 0.2f, markerAhead(1.6, -0.2, -0.35, 0.1)}};
  const SensorData frame = frameOf(model, drawn, kAruco4x4_50);
  for (int refinement : {0, 1, 2, 3}) {
    SCOPED_TRACE("Marker/CornerRefinementMethod " + std::to_string(refinement));
    MarkerDetectorOptions o = withLength(0.2f);
    o.cornerRefinementMethod = refinement;
    MarkerDetector detector(o);
    MarkerDetectionInfo info;
    const Landmarks seen = detector.detect(frame, &info);
    EXPECT_EQ(info.detected, 2);
    ASSERT_EQ(seen.size(), 2u);
    for (const MarkerInView& m : drawn) {
      ASSERT_TRUE(seen.count(m.id)) << m.id;
      const Landmark& l = seen.at(m.id);
      EXPECT_EQ(l.id, m.id);
      EXPECT_FLOAT_EQ(l.size, 0.2f);
      const Transform truth = model.localTransform() * m.cameraToMarker;
      // Unrefined (and by contour lines), aruco's corners sit on the pixels just inside the
      // marker's edge: it looks smaller, so farther (2% at 1.6 m, 65 pixels wide). Sub-pixel and
      // AprilTag refinement put them within a fraction of a pixel: a centimetre.
      const double range = m.cameraToMarker.getNorm();
      const bool subpixel = refinement == 1 || refinement == 3;
      expectNear(l.pose, truth, subpixel ? 0.01 : 0.025 * range, 0.05);
      EXPECT_DOUBLE_EQ(l.covariance(0, 0), 0.001f);
      EXPECT_DOUBLE_EQ(l.covariance(5, 5), 0.01f);
      EXPECT_DOUBLE_EQ(l.covariance(0, 5), 0.0);
    }
  }
}

TEST(MarkerDetector, WrongLengthScalesTheDistance) {
  // The pose's scale is Marker/Length's: a marker printed 0.2 m wide declared 0.1 m wide looks
  // twice as near (what a user who measured wrong sees).
  const CameraModel model = camera();
  MarkerDetector detector(withLength(0.1f));
  const Landmarks seen = detector.detect(frameOf(model, {{4, 0.2f, markerAhead(1.4)}}, kAruco4x4_50));
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_NEAR(seen.at(4).pose.getNorm(), 0.7, 0.02);
}

TEST(MarkerDetector, AprilTagDictionary) {
  const CameraModel model = camera();
  MarkerDetector april(withLength(0.16f, kAprilTag36h11));
  const SensorData f = frameOf(model, {{12, 0.16f, markerAhead(0.9, 0.3)}}, kAprilTag36h11);
  const Landmarks seen = april.detect(f);
  ASSERT_EQ(seen.size(), 1u);
  expectNear(seen.at(12).pose, model.localTransform() * markerAhead(0.9, 0.3), 0.02, 0.06);
  // The same view through the 4x4 ArUco dictionary decodes nothing.
  MarkerDetector aruco(withLength(0.16f));
  EXPECT_TRUE(aruco.detect(f).empty());
}

TEST(MarkerDetector, LengthZeroIsMeasuredFromDepthWhenFacingThenKept) {
  const CameraModel model = camera();
  MarkerDetector detector(withLength(0.0f));
  // Seen at an angle first: the corners' depths differ by centimetres, no length yet.
  MarkerDetectionInfo info;
  EXPECT_TRUE(detector.detect(frameOf(model, {{5, 0.18f, markerAhead(1.0, 0.6)}}, kAruco4x4_50), &info).empty());
  EXPECT_EQ(info.detected, 1);
  EXPECT_EQ(info.withoutLength, 1);
  EXPECT_TRUE(detector.measuredLengths().empty());
  // Facing the camera: measured.
  const Landmarks facing = detector.detect(frameOf(model, {{5, 0.18f, markerAhead(1.0, 0.02)}}, kAruco4x4_50), &info);
  ASSERT_EQ(facing.size(), 1u);
  ASSERT_TRUE(detector.measuredLengths().count(5));
  EXPECT_NEAR(detector.measuredLengths().at(5), 0.18, 0.005);
  EXPECT_NEAR(facing.at(5).size, 0.18, 0.005);
  // Then at an angle again, without depth: the measured side gives the pose.
  const Landmarks later = detector.detect(frameOf(model, {{5, 0.18f, markerAhead(1.3, 0.6)}}, kAruco4x4_50, false));
  ASSERT_EQ(later.size(), 1u);
  expectNear(later.at(5).pose, model.localTransform() * markerAhead(1.3, 0.6), 0.04, 0.06);
}

TEST(MarkerDetector, RangesAndIdZeroAreSkipped) {
  const CameraModel model = camera();
  const SensorData f = frameOf(model, {{0, 0.2f, markerAhead(1.0, 0.0, -0.3)}, {2, 0.2f, markerAhead(1.5, 0.0, 0.3)}},
                               kAruco4x4_50);
  MarkerDetectorOptions o = withLength(0.2f);
  MarkerDetectionInfo info;
  Landmarks seen = MarkerDetector(o).detect(f, &info);
  EXPECT_EQ(info.detected, 2);
  EXPECT_EQ(info.idZero, 1);
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_TRUE(seen.count(2));
  o.maxRange = 1.2f;  // marker 2 is ~1.53 m away
  seen = MarkerDetector(o).detect(f, &info);
  EXPECT_TRUE(seen.empty());
  EXPECT_EQ(info.outOfRange, 1);
  o.maxRange = 0.0f;
  o.minRange = 1.6f;
  EXPECT_TRUE(MarkerDetector(o).detect(f).empty());
}

TEST(MarkerDetector, SeveralCamerasEachWithItsModel) {
  // Two cameras side by side in one image: the marker is in the right-hand one, which looks to
  // the robot's left; its pose must come through that camera's local transform.
  const CameraModel front = camera();
  const CameraModel left = camera(Transform(0, 0, 0, 0, 0, M_PI / 2) * CameraModel::opticalRotation());
  const test::MarkerView empty = renderMarkers(front, {}, kAruco4x4_50, 2.5f);
  const test::MarkerView seen = renderMarkers(left, {{6, 0.2f, markerAhead(1.1, 0.2)}}, kAruco4x4_50, 2.5f);
  cv::Mat grey, depth;
  cv::hconcat(empty.grey, seen.grey, grey);
  cv::hconcat(empty.depth, seen.depth, depth);
  const SensorData f(grey, depth, std::vector<CameraModel>{front, left}, 1, 1.0);
  const Landmarks found = MarkerDetector(withLength(0.2f)).detect(f);
  ASSERT_EQ(found.size(), 1u);
  expectNear(found.at(6).pose, left.localTransform() * markerAhead(1.1, 0.2), 0.02, 0.06);
  EXPECT_GT(found.at(6).pose.y(), 1.0) << "to the robot's left";
}

TEST(MarkerDetector, NoImageOrModelSaysSo) {
  MarkerDetector detector(withLength(0.2f));
  MarkerDetectionInfo info;
  EXPECT_TRUE(detector.detect(SensorData(LaserScan(), 1, 1.0), &info).empty());
  EXPECT_FALSE(info.problem.empty());
}

TEST(MarkerDetectorOptions, IsValidNamesTheParameter) {
  std::string why;
  EXPECT_TRUE(MarkerDetectorOptions().IsValid(&why)) << why;
  MarkerDetectorOptions o;
  o.dictionary = 21;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("Marker/Dictionary"), std::string::npos);
  o = MarkerDetectorOptions();
  o.cornerRefinementMethod = 4;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("Marker/CornerRefinementMethod"), std::string::npos);
  o = MarkerDetectorOptions();
  o.length = -0.1f;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("Marker/Length"), std::string::npos);
  o = MarkerDetectorOptions();
  o.varianceAngular = 0.0f;
  EXPECT_FALSE(o.IsValid(&why));
  o = MarkerDetectorOptions();
  o.minRange = 2.0f;
  o.maxRange = 1.0f;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("Marker/MinRange"), std::string::npos);
  EXPECT_THROW(MarkerDetector{o}, ParameterError);
  // From parameters: the declared defaults, and values through.
  const MarkerDetectorOptions p = MarkerDetectorOptions::fromParameters(
      {{"Marker/Dictionary", "20"}, {"Marker/Length", "0.15"}, {"Marker/CornerRefinementMethod", "1"}});
  EXPECT_EQ(p.dictionary, 20);
  EXPECT_FLOAT_EQ(p.length, 0.15f);
  EXPECT_EQ(p.cornerRefinementMethod, 1);
  EXPECT_FLOAT_EQ(p.maxDepthError, 0.01f);
}

}  // namespace
}  // namespace rtabmap
