// Landmarks through the SLAM pipeline (JFR 2019, 3.1): a marker seen when leaving and again
// when coming back closes the loop with no appearance match; markers are detected from the
// images with RGBD/MarkerDetection; landmark links are saved with their nodes; a later session
// is placed on the map by a marker the map saw, in localization mode and by a merge in mapping.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <cmath>

#include "PoseOnlyFrames.h"
#include "common/MarkerScene.h"
#include "common/TestData.h"
#include "rtabmap_core/slam/Rtabmap.h"

namespace rtabmap {
namespace {

using test::Cov;

constexpr int kSteps = 16;
const Transform kLandmark(0.0, -1.0, 0.4, -M_PI / 2, 0, 0);  // a marker on a wall right of the start

// The robot's true pose k steps along a circle of radius 2.5 m that starts and ends at the
// origin heading +x.
Transform truth(int k) {
  const double a = 2.0 * M_PI * k / kSteps;
  return Transform(2.5 * std::sin(a), 2.5 * (1.0 - std::cos(a)), 0, 0, 0, a);
}

Landmarks seen(int k) {
  Landmark l;
  l.id = 7;
  l.size = 0.2f;
  l.pose = truth(k).inverse() * kLandmark;
  l.covariance.setZero();
  l.covariance.diagonal() << 0.001, 0.001, 0.001, 0.01, 0.01, 0.01;
  return {{7, l}};
}

struct Drive {
  std::map<int, Transform> poses, landmarks;
  SlamSummary summary;
  int landmarkIdAtTheEnd = 0;
};

// Odometry that turns 0.03 rad too far and goes 2% too long each step: back at the start it is
// off by half a radian and a metre. The marker is seen from the first two and the last two
// nodes (`withMarkers`).
Drive drive(bool withMarkers, const std::string& database = "") {
  Rtabmap slam;
  slam.init(test::everyFrame(), database);
  Transform odom = Transform::Identity();
  Drive run;
  for (int k = 0; k <= kSteps; ++k) {
    if (k > 0) {
      const Transform step = truth(k - 1).inverse() * truth(k);
      odom = odom * Transform(step.x() * 1.02, step.y() * 1.02, 0, 0, 0, step.yaw() + 0.03);
    }
    SensorData frame = test::frame(k + 1, k + 1.0);
    if (withMarkers && (k <= 1 || k >= kSteps - 1)) frame.setLandmarks(seen(k));
    EXPECT_TRUE(slam.process(frame, odom, Cov::Identity() * 0.0025)) << slam.lastRejection();
  }
  run.poses = slam.optimizedPoses();
  run.landmarks = slam.landmarkPoses();
  run.summary = slam.summary();
  run.landmarkIdAtTheEnd = slam.statistics().landmarkId;
  return run;
}

TEST(Landmarks, AMarkerSeenAgainClosesTheLoop) {
  const Drive odometry = drive(false);
  const Drive markers = drive(true);
  const int last = kSteps + 1;
  const double odometryError = (truth(kSteps).inverse() * odometry.poses.at(last)).getNorm();
  const double markerError = (truth(kSteps).inverse() * markers.poses.at(last)).getNorm();
  EXPECT_GT(odometryError, 0.5) << "the drift the loop must remove";
  EXPECT_LT(markerError, 0.05) << "back where it started, through the marker";
  // The heading: the marker's orientation (sigma 0.1 rad) against 16 odometry steps (0.05 rad
  // each, 0.2 for the chain) leaves a fifth of the drift's 0.48 rad where the weights put it.
  const double odometryTurn = std::fabs((truth(kSteps).inverse() * odometry.poses.at(last)).getAngle());
  EXPECT_GT(odometryTurn, 0.4);
  EXPECT_LT(std::fabs((truth(kSteps).inverse() * markers.poses.at(last)).getAngle()), 0.2 * odometryTurn);
  EXPECT_GE(markers.summary.landmarkClosures, 1);
  EXPECT_EQ(markers.summary.loopClosures, 0) << "no appearance: the marker alone closed it";
  EXPECT_EQ(markers.landmarkIdAtTheEnd, -7);
  ASSERT_TRUE(markers.landmarks.count(-7));
  EXPECT_LT((kLandmark.inverse() * markers.landmarks.at(-7)).getNorm(), 0.05);
  EXPECT_EQ(markers.poses.count(-7), 0u) << "optimizedPoses() holds nodes only";
  EXPECT_TRUE(odometry.landmarks.empty());
}

TEST(Landmarks, LinksAreSavedWithTheirNodes) {
  test::TempDir dir("rtabmap_landmarks");
  const std::string path = dir.file("rtabmap.db");
  drive(true, path);
  Rtabmap slam;
  slam.init({{"Mem/IncrementalMemory", "false"}}, path);
  int landmarkLinks = 0;
  for (const auto& [from, link] : slam.allLinks()) {
    if (link.type() != Link::kLandmark) continue;
    ++landmarkLinks;
    EXPECT_EQ(link.to(), -7);
    EXPECT_NEAR((link.transform().inverse() * seen(link.from() - 1).at(7).pose).getNorm(), 0.0, 1e-5);
  }
  EXPECT_EQ(landmarkLinks, 4) << "nodes 1, 2, 16 and 17 saw the marker";
  // The map the database opens with is optimised with them: the loop stays closed.
  EXPECT_LT((truth(kSteps).inverse() * slam.optimizedPoses().at(kSteps + 1)).getNorm(), 0.05);
}

TEST(Landmarks, LocalizationOnAMarkerTheMapSaw) {
  // A second session in localization mode starts where the map has the marker, its odometry at
  // the identity there: no appearance, no scan, only the marker can place it.
  test::TempDir dir("rtabmap_landmarks_localization");
  const std::string path = dir.file("rtabmap.db");
  drive(true, path);
  for (bool markers : {false, true}) {
    Rtabmap slam;
    slam.init({{"Mem/IncrementalMemory", "false"}, {"Rtabmap/DetectionRate", "0"}}, path);
    int landmarkId = 0;
    for (int k = kSteps - 2; k <= kSteps; ++k) {
      SensorData frame = test::frame(100 + k, 100.0 + k);
      if (markers) frame.setLandmarks(seen(k));
      slam.process(frame, truth(kSteps - 2).inverse() * truth(k), Cov::Identity() * 0.0025);
      landmarkId = std::min(landmarkId, slam.statistics().landmarkId);
    }
    if (!markers) {
      EXPECT_EQ(slam.summary().localizations, 0);
      continue;
    }
    EXPECT_GE(slam.summary().localizations, 1) << "the second sighting confirms the first (RGBD/MaxOdomCacheSize)";
    EXPECT_EQ(landmarkId, -7);
    // The map itself is good to a few centimetres there (AMarkerSeenAgainClosesTheLoop).
    EXPECT_LT((truth(kSteps).inverse() * slam.currentPose()).getNorm(), 0.1) << slam.currentPose().prettyPrint();
  }
}

TEST(Landmarks, AMarkerAnotherSessionSawMergesTheMaps) {
  // Session 1 maps the circle (the marker seen at its start and end). Session 2 starts on the far
  // side, its odometry at the identity there, and drives back to the start: its first sight of
  // the marker puts it in session 1's referential.
  for (bool markers : {false, true}) {
    SCOPED_TRACE(markers ? "with the marker" : "without");
    test::TempDir dir("rtabmap_landmarks_sessions");
    const std::string path = dir.file("rtabmap.db");
    drive(true, path);
    Rtabmap slam;
    slam.init(test::everyFrame(), path);
    const int start = kSteps / 2;
    for (int k = start; k <= kSteps; ++k) {
      SensorData frame = test::frame(100 + k, 100.0 + k);
      if (markers && k >= kSteps - 1) frame.setLandmarks(seen(k));
      EXPECT_TRUE(slam.process(frame, truth(start).inverse() * truth(k), Cov::Identity() * 0.0025)) << slam.lastRejection();
    }
    const std::map<int, Transform> poses = slam.optimizedPoses();
    const int last = slam.lastNodeId();
    if (!markers) {
      EXPECT_EQ(poses.count(1), 0u) << "the first session's map is another referential";
      continue;
    }
    ASSERT_EQ(poses.count(1), 1u) << "merged: one referential";
    EXPECT_GE(slam.summary().loopClosures, 1) << "the merge is a loop closure to the node that saw the marker";
    // Session 2's last node is back at the start, where session 1's map (good to a few cm) has it.
    EXPECT_LT((truth(kSteps).inverse() * poses.at(last)).getNorm(), 0.1) << poses.at(last).prettyPrint();
    EXPECT_LT((truth(start).inverse() * poses.at(last - (kSteps - start))).getNorm(), 0.15)
        << "session 2's first node, placed through its odometry";
  }
}

TEST(Landmarks, ALandmarkOfAFrameSkippedByTheRateGoesToTheNextNode) {
  // Frames at 2 Hz, nodes at 1 Hz: the detector's one sighting came with a frame in between.
  Rtabmap slam;
  slam.init({{"Rtabmap/DetectionRate", "1"}}, "");
  for (int i = 0; i <= 4; ++i) {
    SensorData frame = test::frame(i + 1, 1.0 + 0.5 * i);
    if (i == 1) {
      Landmark l = seen(0).at(7);
      l.pose = Transform(2.0, 0.3, 0.4, 0, 0, 0);
      frame.setLandmarks({{7, l}});
    }
    slam.process(frame, Transform(0.5 * i, 0, 0, 0, 0, 0), Cov::Identity() * 1e-4);
  }
  EXPECT_EQ(slam.summary().skippedRate, 2);
  int links = 0;
  for (const auto& [from, link] : slam.localLinks()) {
    if (link.type() != Link::kLandmark) continue;
    ++links;
    // Seen from 0.5 m, kept by the node at 1.0 m (frame 3, the next update): 1.5 m ahead of it.
    EXPECT_NEAR(link.transform().x(), 1.5, 1e-9);
    EXPECT_NEAR(link.transform().y(), 0.3, 1e-9);
    EXPECT_EQ(link.to(), -7);
  }
  EXPECT_EQ(links, 1) << "given once to the next node, not again";
}

TEST(Landmarks, MarkerDetectionFromTheImages) {
  // One RGB-D frame of a wall with marker 5, 1.2 m ahead: the node links to landmark -5 where the
  // marker was drawn, in the base frame.
  const CameraModel model(525.0, 525.0, 319.5, 239.5, Transform(0, 0, 0.5, 0, 0, 0) * CameraModel::opticalRotation(),
                          0.0, cv::Size(640, 480));
  const Transform drawn = test::markerAhead(1.2, 0.3, 0.1);
  const test::MarkerView view = test::renderMarkers(model, {{5, 0.2f, drawn}}, 0, 2.5f);
  cv::Mat rgb;
  cv::cvtColor(view.grey, rgb, cv::COLOR_GRAY2BGR);
  for (bool enabled : {false, true}) {
    Rtabmap slam;
    slam.init({{"Rtabmap/DetectionRate", "0"}, {"RGBD/MarkerDetection", enabled ? "true" : "false"},
               {"Marker/Length", "0.2"}},
              "");
    ASSERT_TRUE(slam.process(SensorData(rgb, view.depth, model, 1, 1.0), Transform::Identity(), Cov::Identity() * 1e-4))
        << slam.lastRejection();
    const Link* found = nullptr;
    const std::multimap<int, Link> links = slam.localLinks();
    for (const auto& [from, link] : links) {
      if (link.type() == Link::kLandmark) found = &link;
    }
    if (!enabled) {
      EXPECT_EQ(found, nullptr) << "RGBD/MarkerDetection is off by default";
      continue;
    }
    ASSERT_NE(found, nullptr);
    EXPECT_EQ(found->from(), 1);
    EXPECT_EQ(found->to(), -5);
    const Transform error = found->transform().inverse() * (model.localTransform() * drawn);
    EXPECT_LT(error.getNorm(), 0.02);
    EXPECT_LT(std::fabs(error.getAngle()), 0.06);
    EXPECT_EQ(slam.statistics().data().count("Loop/Markers_detected/"), 1u);
  }
}

}  // namespace
}  // namespace rtabmap
