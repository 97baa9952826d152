// Local grid from several stereo cameras side by side: each camera's pair is block-matched on
// its own (never across a camera boundary) and its cloud placed by its own local transform, so
// the grid gets the obstacles every camera sees.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "maps/MapsTestUtil.h"
#include "registration/MultiStereoScene.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/maps/LocalGridMaker.h"
#include "rtabmap_core/maps/LocalGridStages.h"

using namespace rtabmap;
using namespace rtabmap::multistereo_test;
using rtabmap::test::countIn;

TEST(LocalGridMultiStereo, EachCamerasDepthComesFromItsOwnPair) {
  const test::SyntheticRoom room;
  const SensorData data = renderStereoFrame(room, basePose(0.0, 0.0, 0.0));
  const StereoBMOptions bm;
  const cv::Mat depth = depthFromStereoCameras(data.imageRaw(), data.depthOrRightRaw(), data.stereoCameraModels(), bm);
  ASSERT_EQ(depth.size(), data.imageRaw().size());
  const int w = depth.cols / 2;
  for (int c = 0; c < 2; ++c) {
    SCOPED_TRACE("camera " + std::to_string(c));
    const cv::Mat alone = depthFromStereo(data.imageRaw().colRange(c * w, (c + 1) * w).clone(),
                                          data.depthOrRightRaw().colRange(c * w, (c + 1) * w).clone(),
                                          data.stereoCameraModels()[static_cast<size_t>(c)], bm);
    EXPECT_EQ(cv::countNonZero(depth.colRange(c * w, (c + 1) * w) != alone), 0);
    EXPECT_GT(cv::countNonZero(alone > 0.0f), w * depth.rows / 4);
  }
  EXPECT_THROW(depthFromStereoCameras(data.imageRaw().colRange(0, 321).clone(),
                                      data.depthOrRightRaw().colRange(0, 321).clone(), data.stereoCameraModels(), bm),
               FormatError);
}

TEST(LocalGridMultiStereo, ObstaclesFromBothCamerasInTheBaseFrame) {
  // The robot at the centre of the 6 m room: camera 0 sees the wall at x = 3, camera 1 (to the
  // left) the wall at y = 3.
  const test::SyntheticRoom room;
  const SensorData data = renderStereoFrame(room, basePose(0.0, 0.0, 0.0));
  LocalGridOptions o;
  o.depthDecimation = 2;
  const LocalGridResult r = createLocalGrid(data, o);
  ASSERT_TRUE(r.success) << r.why;
  EXPECT_EQ(r.source, "stereo");
  const int east = countIn(r.grid.obstacles, 2.85, -2.0, 3.15, 2.0);
  const int north = countIn(r.grid.obstacles, -2.0, 2.85, 2.0, 3.15);
  EXPECT_GT(east, 50);
  EXPECT_GT(north, 50);
  // Nothing behind the robot or to its right, where no camera looks.
  EXPECT_EQ(countIn(r.grid.obstacles, -3.5, -3.5, -2.0, 3.5), 0);
  EXPECT_EQ(countIn(r.grid.obstacles, -3.5, -3.5, 3.5, -2.0), 0);
  // Nearly all obstacles are on those two walls: a camera's cloud placed by the other's local
  // transform would land on neither.
  const int total = r.grid.obstacles.rows * r.grid.obstacles.cols;
  EXPECT_GE(east + north, total * 9 / 10) << "east " << east << " north " << north << " of " << total;
}
