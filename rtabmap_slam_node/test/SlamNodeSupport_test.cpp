#include "rtabmap_slam_node/SlamNodeSupport.h"

#include <gtest/gtest.h>

#include <cstdlib>

namespace rtabmap_slam_node {
namespace {

TEST(GridMapToMsg, CopiesCellsOriginAndResolution) {
  rtabmap::GridMap grid;
  grid.data = cv::Mat(2, 3, CV_8SC1, cv::Scalar(rtabmap::GridMap::kUnknown));
  grid.data.at<int8_t>(0, 2) = rtabmap::GridMap::kOccupied;  // lowest row, last column
  grid.data.at<int8_t>(1, 0) = rtabmap::GridMap::kFree;
  grid.resolution = 0.05f;
  grid.originX = -1.5;
  grid.originY = 2.25;
  std_msgs::Header header;
  header.frame_id = "map";
  header.stamp = ros::Time(12.5);
  const nav_msgs::OccupancyGrid msg = gridMapToMsg(grid, header);
  EXPECT_EQ(msg.header.frame_id, "map");
  EXPECT_EQ(msg.info.width, 3u);
  EXPECT_EQ(msg.info.height, 2u);
  EXPECT_FLOAT_EQ(msg.info.resolution, 0.05f);
  EXPECT_DOUBLE_EQ(msg.info.origin.position.x, -1.5);
  EXPECT_DOUBLE_EQ(msg.info.origin.position.y, 2.25);
  EXPECT_DOUBLE_EQ(msg.info.origin.orientation.w, 1.0);
  // nav_msgs: data[row * width + col], row 0 = lowest y.
  const std::vector<int8_t> expected = {-1, -1, 100, 0, -1, -1};
  EXPECT_EQ(msg.data, expected);
}

TEST(GridMapToMsg, ViewWithStrideIsCopiedRowByRow) {
  cv::Mat big(4, 4, CV_8SC1, cv::Scalar(0));
  big.at<int8_t>(2, 2) = 100;
  rtabmap::GridMap grid;
  grid.data = big(cv::Rect(1, 1, 2, 2));  // not continuous
  grid.resolution = 0.1f;
  const nav_msgs::OccupancyGrid msg = gridMapToMsg(grid, std_msgs::Header());
  EXPECT_EQ(msg.data, (std::vector<int8_t>{0, 0, 0, 100}));
}

TEST(GridMapToMsg, EmptyGrid) {
  const nav_msgs::OccupancyGrid msg = gridMapToMsg(rtabmap::GridMap(), std_msgs::Header());
  EXPECT_EQ(msg.info.width, 0u);
  EXPECT_TRUE(msg.data.empty());
}

Covariance6 diagonal(double x, double y, double z, double roll, double pitch, double yaw) {
  Covariance6 c = Covariance6::Zero();
  c.diagonal() << x, y, z, roll, pitch, yaw;
  return c;
}

TEST(MotionCovariance, IncrementalIsUsedAsIs) {
  const Covariance6 previous = diagonal(0.5, 0.5, 0.5, 0.5, 0.5, 0.5);
  const Covariance6 current = diagonal(0.01, 0.02, 0.03, 0.001, 0.002, 0.003);
  EXPECT_TRUE(motionCovariance(current, &previous, false).isApprox(current));
  EXPECT_TRUE(motionCovariance(current, nullptr, false).isApprox(current));
}

TEST(MotionCovariance, CumulativeTakesTheDifference) {
  Covariance6 previous = diagonal(0.10, 0.20, 1e-6, 1e-6, 1e-6, 0.05);
  Covariance6 current = diagonal(0.13, 0.26, 1e-6, 1e-6, 1e-6, 0.07);
  previous(0, 1) = previous(1, 0) = 0.01;
  current(0, 1) = current(1, 0) = 0.015;
  const Covariance6 c = motionCovariance(current, &previous, true, 1e-9);
  EXPECT_NEAR(c(0, 0), 0.03, 1e-12);
  EXPECT_NEAR(c(1, 1), 0.06, 1e-12);
  EXPECT_NEAR(c(5, 5), 0.02, 1e-12);
  EXPECT_NEAR(c(0, 1), 0.005, 1e-12);
  // z, roll, pitch did not grow: floored, never zero (zero variance = infinite information).
  EXPECT_DOUBLE_EQ(c(2, 2), 1e-9);
  // Without a previous message (first one, or after a reset) the covariance is used as is.
  EXPECT_TRUE(motionCovariance(current, nullptr, true, 1e-9).isApprox(current));
}

TEST(MotionCovariance, UnobservedAxesKeepTheirVariance) {
  const Covariance6 previous = diagonal(0.1, 0.1, 99999, 99999, 99999, 0.1);
  const Covariance6 current = diagonal(0.2, 0.2, 99999, 99999, 99999, 0.3);
  const Covariance6 c = motionCovariance(current, &previous, true);
  EXPECT_DOUBLE_EQ(c(2, 2), 99999);
  EXPECT_DOUBLE_EQ(c(3, 3), 99999);
  EXPECT_NEAR(c(0, 0), 0.1, 1e-12);
  EXPECT_NEAR(c(5, 5), 0.2, 1e-12);
}

TEST(MotionCovariance, ShrinkingCovarianceIsFloored) {
  // Wheel odometry reset: the covariance restarts small; no negative variance may reach the core.
  const Covariance6 previous = diagonal(1, 1, 1, 1, 1, 1);
  const Covariance6 current = diagonal(0.01, 0.01, 0.01, 0.01, 0.01, 0.01);
  const Covariance6 c = motionCovariance(current, &previous, true, 1e-6);
  for (int i = 0; i < 6; ++i) EXPECT_DOUBLE_EQ(c(i, i), 1e-6);
  EXPECT_TRUE((c - Covariance6(c.diagonal().asDiagonal())).isZero());
}

TEST(TfOdometryCovariance, Diagonal) {
  const Covariance6 c = tfOdometryCovariance(0.002, 0.005);
  EXPECT_TRUE(c.isApprox(diagonal(0.002, 0.002, 0.002, 0.005, 0.005, 0.005)));
}

TEST(NodeArguments, DeleteDbFlags) {
  EXPECT_FALSE(parseNodeArguments({}).deleteDbOnStart);
  EXPECT_TRUE(parseNodeArguments({"-d"}).deleteDbOnStart);
  const NodeArguments a = parseNodeArguments({"--delete_db_on_start", "--udebug", ""});
  EXPECT_TRUE(a.deleteDbOnStart);
  EXPECT_EQ(a.unknown, std::vector<std::string>{"--udebug"});
}

TEST(ExpandHome, OnlyALeadingTilde) {
  const char* home = std::getenv("HOME");
  ASSERT_NE(home, nullptr);
  EXPECT_EQ(expandHome("~/.ros/rtabmap.db"), std::string(home) + "/.ros/rtabmap.db");
  EXPECT_EQ(expandHome("/tmp/~/x.db"), "/tmp/~/x.db");
  EXPECT_EQ(expandHome("~user/x.db"), "~user/x.db");
  EXPECT_EQ(expandHome(""), "");
}

TEST(MapToOdomStamps, OnAStoppedClockOnlyANewCorrectionGoesOutEachANanosecondLater) {
  MapToOdomStamps stamps;
  // The clock runs: every tick goes out at its own stamp, changed or not.
  EXPECT_EQ(stamps.next(ros::Time(10.3), true), ros::Time(10.3));
  EXPECT_EQ(stamps.next(ros::Time(10.4), false), ros::Time(10.4));
  // The bag ended: the same stamp again, nothing new to say.
  EXPECT_FALSE(stamps.next(ros::Time(10.4), false).has_value());
  // The node, catching up with queued data, corrects again: strictly newer stamps, which tf
  // listeners take (they drop a stamp they already hold).
  const ros::Time first = stamps.next(ros::Time(10.4), true).value();
  EXPECT_GT(first, ros::Time(10.4));
  EXPECT_LT(first, ros::Time(10.4) + ros::Duration(1e-6));
  EXPECT_FALSE(stamps.next(ros::Time(10.4), false).has_value());
  EXPECT_GT(stamps.next(ros::Time(10.4), true).value(), first);
  // The bag restarted (the clock jumped back; listeners clear their buffers): its stamps again.
  EXPECT_EQ(stamps.next(ros::Time(2.0), false), ros::Time(2.0));
  EXPECT_EQ(stamps.next(ros::Time(2.1), false), ros::Time(2.1));
}

}  // namespace
}  // namespace rtabmap_slam_node
