// Trajectory type and file formats.
#include "rtabmap_core/eval/Trajectory.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/TestData.h"
#include "eval/EvalTestUtil.h"
#include "rtabmap_core/common/Error.h"

using rtabmap::FormatError;
using rtabmap::Trajectory;
using rtabmap::TrajectoryFormat;
using rtabmap::Transform;
using rtabmap::test::TempDir;
using rtabmap::test::writeText;

namespace {

Trajectory randomTrajectory(size_t n, bool planar, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  Trajectory t;
  double stamp = 1403715273.262142976;
  for (size_t i = 0; i < n; ++i) {
    stamp += 0.05 + 0.001 * static_cast<double>(i % 7);
    if (planar) {
      t.add(stamp, Transform{u(rng), u(rng), u(rng)});  // braces: drawn in order
    } else {
      t.add(stamp, Transform{u(rng), u(rng), u(rng), u(rng), u(rng) / 3.0, u(rng)});
    }
  }
  return t;
}

double maxDifference(const Transform& a, const Transform& b) {
  return (a.toMatrix4d() - b.toMatrix4d()).cwiseAbs().maxCoeff();
}

}  // namespace

TEST(Trajectory, NearestAndInterpolate) {
  Trajectory t;
  t.add(1.0, Transform(0, 0, 0));
  t.add(2.0, Transform(2, 0, M_PI / 2));
  t.add(2.0, Transform(5, 5, 0));  // duplicate stamp: the first one wins
  t.add(4.0, Transform());         // null
  ASSERT_TRUE(t.isSorted());
  EXPECT_EQ(t.nearest(1.4, 0.5), 0);
  EXPECT_EQ(t.nearest(1.6, 0.5), 1);
  EXPECT_EQ(t.nearest(1.5, 0.5), 0);  // tie: the earlier pose
  EXPECT_EQ(t.nearest(3.0, 0.5), -1);
  EXPECT_EQ(t.nearest(0.0, 0.5), -1);
  const Transform mid = t.interpolate(1.5);
  EXPECT_NEAR(mid.x(), 1.0, 1e-12);
  EXPECT_NEAR(mid.theta(), M_PI / 4, 1e-12);
  EXPECT_TRUE(t.interpolate(1.5, 0.5).isNull());  // samples 1 s apart > maxGap
  EXPECT_NEAR(t.interpolate(2.0).x(), 2.0, 1e-12);
  EXPECT_TRUE(t.interpolate(3.0).isNull());  // towards a null pose
  EXPECT_TRUE(t.interpolate(0.5).isNull());
  EXPECT_TRUE(t.interpolate(5.0).isNull());
  EXPECT_NEAR(t.pathLength(), 2.0 + std::sqrt(9.0 + 25.0), 1e-12);
  Trajectory u;
  u.add(2.0, Transform::Identity());
  u.add(1.0, Transform::Identity());
  EXPECT_FALSE(u.isSorted());
  EXPECT_THROW(u.nearest(1.0, 1.0), std::logic_error);
  u.sortByStamp();
  EXPECT_TRUE(u.isSorted());
}

TEST(Trajectory, RoundTripsInEveryFormat) {
  TempDir dir;
  const Trajectory t3 = randomTrajectory(50, false, 7);
  // TUM keeps stamps and poses.
  rtabmap::writeTrajectory(dir.file("t.txt"), t3, TrajectoryFormat::kTum);
  EXPECT_EQ(rtabmap::detectTrajectoryFormat(dir.file("t.txt")), TrajectoryFormat::kTum);
  Trajectory back = rtabmap::readTrajectory(dir.file("t.txt"));
  ASSERT_EQ(back.size(), t3.size());
  for (size_t i = 0; i < t3.size(); ++i) {
    EXPECT_EQ(back[i].stamp, t3[i].stamp);  // exact: shortest round-trip printing
    EXPECT_LT(maxDifference(back[i].pose, t3[i].pose), 1e-12);
  }
  // KITTI keeps poses exactly; stamps become row indices.
  rtabmap::writeTrajectory(dir.file("k.txt"), t3, TrajectoryFormat::kKitti);
  EXPECT_EQ(rtabmap::detectTrajectoryFormat(dir.file("k.txt")), TrajectoryFormat::kKitti);
  back = rtabmap::readTrajectory(dir.file("k.txt"), TrajectoryFormat::kKitti);
  ASSERT_EQ(back.size(), t3.size());
  for (size_t i = 0; i < t3.size(); ++i) {
    EXPECT_EQ(back[i].stamp, static_cast<double>(i));
    EXPECT_EQ(back[i].pose, t3[i].pose);
  }
  // g2o: VERTEX_SE3:QUAT; non-integer stamps become row ids, integer stamps are kept as ids.
  rtabmap::writeTrajectory(dir.file("g.g2o"), t3, TrajectoryFormat::kG2o);
  EXPECT_EQ(rtabmap::detectTrajectoryFormat(dir.file("g.g2o")), TrajectoryFormat::kG2o);
  back = rtabmap::readTrajectory(dir.file("g.g2o"));
  ASSERT_EQ(back.size(), t3.size());
  for (size_t i = 0; i < t3.size(); ++i) {
    EXPECT_EQ(back[i].stamp, static_cast<double>(i));
    EXPECT_LT(maxDifference(back[i].pose, t3[i].pose), 1e-12);
  }
  Trajectory ids;
  ids.add(3, Transform(1, 2, 0.5));
  ids.add(10, Transform(2, 3, 0.25));
  ids.add(11, Transform());  // null: skipped
  rtabmap::writeTrajectory(dir.file("ids.g2o"), ids, TrajectoryFormat::kG2o);
  back = rtabmap::readTrajectory(dir.file("ids.g2o"));
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[1].stamp, 10.0);
  EXPECT_LT(maxDifference(back[1].pose, ids[1].pose), 1e-12);
  EXPECT_THROW(rtabmap::writeTrajectory(dir.file("x"), t3, TrajectoryFormat::kEuroc), FormatError);
  EXPECT_THROW(rtabmap::writeTrajectory(dir.path() + "/no/such/dir/x.txt", t3, TrajectoryFormat::kTum),
               rtabmap::Error);
}

TEST(Trajectory, ReadsG2oVerticesEurocCsvAndCommaTum) {
  TempDir dir;
  writeText(dir.file("se2.g2o"),
            "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1.5 -0.5 0.3\nEDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\nFIX 0\n");
  Trajectory t = rtabmap::readTrajectory(dir.file("se2.g2o"));
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[1].stamp, 1.0);
  EXPECT_NEAR(t[1].pose.x(), 1.5, 1e-15);
  EXPECT_NEAR(t[1].pose.y(), -0.5, 1e-15);
  EXPECT_NEAR(t[1].pose.theta(), 0.3, 1e-15);
  writeText(dir.file("edges.g2o"), "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n");
  EXPECT_THROW(rtabmap::readTrajectory(dir.file("edges.g2o")), FormatError);

  // EuRoC's state_groundtruth_estimate0/data.csv: p then q in w x y z order, more columns after.
  writeText(dir.file("data.csv"),
            "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z [], v_x\n"
            "1403715273262142976,0.878612,2.142470,0.947262,0.060514,-0.828459,-0.058956,-0.553641,0.01\n");
  EXPECT_EQ(rtabmap::detectTrajectoryFormat(dir.file("data.csv")), TrajectoryFormat::kEuroc);
  t = rtabmap::readTrajectory(dir.file("data.csv"));
  ASSERT_EQ(t.size(), 1u);
  EXPECT_DOUBLE_EQ(t[0].stamp, 1403715273.262142976);
  const Eigen::Matrix3d expected =
      Eigen::Quaterniond(0.060514, -0.828459, -0.058956, -0.553641).normalized().toRotationMatrix();
  EXPECT_LT((t[0].pose.rotationMatrix() - expected).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(t[0].pose.y(), 2.142470, 1e-12);

  writeText(dir.file("comma.txt"), "# t x y z qx qy qz qw\n1.5,1,2,3,0,0,0,1\n");
  t = rtabmap::readTrajectory(dir.file("comma.txt"));
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].pose.z(), 3.0);
}

TEST(Trajectory, MalformedFilesNameFileAndLine) {
  TempDir dir;
  writeText(dir.file("tum.txt"), "# header\n1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n");
  try {
    rtabmap::readTrajectory(dir.file("tum.txt"), TrajectoryFormat::kTum);
    ADD_FAILURE();
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("tum.txt:3:"), std::string::npos) << e.what();
  }
  writeText(dir.file("quat.txt"), "1 0 0 0 0 0 0 0\n");
  try {
    rtabmap::readTrajectory(dir.file("quat.txt"));
    ADD_FAILURE();
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("quat.txt:1:"), std::string::npos) << e.what();
  }
  writeText(dir.file("kitti.txt"), "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 zero\n");
  try {
    rtabmap::readTrajectory(dir.file("kitti.txt"));
    ADD_FAILURE();
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("kitti.txt:2:"), std::string::npos) << e.what();
  }
  writeText(dir.file("five.txt"), "1 2 3 4 5\n");
  EXPECT_THROW(rtabmap::detectTrajectoryFormat(dir.file("five.txt")), FormatError);
  writeText(dir.file("empty.txt"), "# nothing\n\n");
  EXPECT_THROW(rtabmap::readTrajectory(dir.file("empty.txt")), FormatError);
  EXPECT_THROW(rtabmap::readTrajectory(dir.file("missing.txt")), FormatError);
  EXPECT_THROW(rtabmap::trajectoryFormatFromName("ply"), FormatError);
  EXPECT_EQ(rtabmap::trajectoryFormatFromName("KITTI"), TrajectoryFormat::kKitti);
}
