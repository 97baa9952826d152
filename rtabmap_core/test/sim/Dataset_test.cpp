// The dataset folder: the reader reads back what the writer wrote, files are the same bytes for
// the same seed, and the sensors agree with each other geometrically (depth vs laser, stereo
// disparity vs depth, lidar on surfaces).
#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "SimTestUtil.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/sim/SimDatasetReader.h"

using namespace rtabmap::sim;
using rtabmap::DatasetReaderOptions;
using rtabmap::DatasetRecord;
using rtabmap::Transform;
namespace fs = std::filesystem;

namespace {

std::vector<char> bytesOf(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::vector<char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Relative path -> contents of every file under dir.
std::map<std::string, std::vector<char>> allFiles(const std::string& dir) {
  std::map<std::string, std::vector<char>> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) files[fs::relative(e.path(), dir).string()] = bytesOf(e.path());
  }
  return files;
}

}  // namespace

TEST(SimDataset, ReaderReadsBackWhatTheWriterWrote) {
  const auto& run = test::loopRun();
  const auto& frames = run.recorded.frames;
  ASSERT_EQ(run.summary.frames, 41);  // 20 s at 2 Hz, both ends included
  ASSERT_EQ(static_cast<int>(frames.size()), run.summary.frames);
  SimDatasetReader reader(run.dir->path());
  EXPECT_EQ(reader.format(), "sim");
  EXPECT_EQ(reader.totalFrames(), 41);
  EXPECT_EQ(reader.frameCount(), 41);
  EXPECT_EQ(reader.meta().scenario, "loop");
  EXPECT_EQ(reader.meta().seed, 7u);
  EXPECT_EQ(reader.meta().simulatorVersion, kSimulatorVersion);
  EXPECT_TRUE(reader.meta().rgb && reader.meta().stereo && reader.meta().urg && reader.meta().utm && reader.meta().lidar &&
              reader.meta().depth32);
  EXPECT_EQ(reader.rgbModel().imageWidth(), 320);
  EXPECT_NEAR(reader.stereoModel().baseline(), 0.12, 1e-12);
  EXPECT_TRUE(reader.rgbModel().localTransform() == run.config.camera.baseToOptical);
  for (int i : {0, 17, 40}) {
    SCOPED_TRACE(i);
    const SimFrame& f = frames[static_cast<size_t>(i)];
    const SimFrameRecord r = reader.readFrame(i);
    EXPECT_NEAR(r.stamp, f.stamp, 1e-6);
    EXPECT_EQ(cv::norm(r.rgb, f.bgr, cv::NORM_INF), 0.0);  // PNG is lossless
    EXPECT_EQ(cv::norm(r.right, f.right, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(r.depth32, f.depth, cv::NORM_INF), 0.0);
    cv::Mat mm;
    f.depth.convertTo(mm, CV_16UC1, 1000.0);
    EXPECT_EQ(cv::norm(r.depth, mm, cv::NORM_INF), 0.0);
    EXPECT_NEAR(r.groundTruth.x(), f.groundTruth.x, 1e-8);
    EXPECT_NEAR(r.groundTruth.y(), f.groundTruth.y, 1e-8);
    EXPECT_NEAR(r.groundTruth.yaw(), f.groundTruth.yaw, 1e-8);
    EXPECT_NEAR(r.odometry.x(), f.odometry.x, 1e-8);
    EXPECT_NEAR(r.odometry.yaw(), f.odometry.yaw, 1e-8);
    // Scans: every finite range comes back as the point range * (cos, sin) of its beam.
    const LaserSpec& spec = run.config.urg;
    int k = 0;
    for (int b = 0; b < spec.beams; ++b) {
      const float range = f.urg.ranges[static_cast<size_t>(b)];
      if (!std::isfinite(range)) continue;
      ASSERT_LT(k, r.urg.size());
      const Eigen::Vector3f p = r.urg.point(k++);
      const double a = spec.angleMin + b * spec.angleIncrement;
      EXPECT_NEAR(p.x(), range * std::cos(a), 1e-5);
      EXPECT_NEAR(p.y(), range * std::sin(a), 1e-5);
    }
    EXPECT_EQ(k, r.urg.size());
    EXPECT_EQ(r.urg.maxPoints(), 683);
    EXPECT_EQ(r.utm.maxPoints(), 1081);
    EXPECT_EQ(r.lidar.size(), f.lidar.cols);
    EXPECT_EQ(r.lidar.format(), rtabmap::LaserScan::kXYZI);
  }
}

TEST(SimDataset, StreamIsInTimeOrderWithImuAndOdometryBeforeTheirFrame) {
  const auto& run = test::loopRun();
  SimDatasetReader reader(run.dir->path());
  DatasetRecord rec;
  int frames = 0, imu = 0, odometry = 0;
  double lastStamp = -1.0;
  int lastKind = -1;
  while (reader.next(rec)) {
    const int kind = static_cast<int>(rec.kind);
    ASSERT_GE(rec.stamp, lastStamp);
    if (rec.stamp == lastStamp) {
      // kFrame (0) after kOdometry (2) after kImu (1) at the same stamp.
      const int rank = rec.kind == DatasetRecord::Kind::kImu ? 0 : (rec.kind == DatasetRecord::Kind::kOdometry ? 1 : 2);
      const int lastRank = lastKind == 1 ? 0 : (lastKind == 2 ? 1 : 2);
      ASSERT_GE(rank, lastRank);
    }
    lastStamp = rec.stamp;
    lastKind = kind;
    EXPECT_EQ(rec.stamp, rec.data.stamp());
    if (rec.kind == DatasetRecord::Kind::kFrame) {
      ++frames;
      EXPECT_EQ(rec.data.id(), frames);
      EXPECT_FALSE(rec.data.imageRaw().empty());
      EXPECT_EQ(rec.data.depthOrRightRaw().type(), CV_16UC1);
      EXPECT_EQ(rec.data.laserScanRaw().maxPoints(), 683);  // urg by default
      EXPECT_FALSE(rec.data.odomPose().isNull());
      EXPECT_FALSE(rec.data.groundTruth().isNull());
      EXPECT_GT(rec.data.odomCovariance()(0, 0), 0.0);
      EXPECT_EQ(rec.data.odomCovariance()(2, 2), 1e-6);
    } else if (rec.kind == DatasetRecord::Kind::kImu) {
      ++imu;
      EXPECT_NEAR(rec.data.imu().linearAcceleration.z(), kGravity, 1.0);
      EXPECT_GT(rec.data.imu().angularVelocityCovariance(0, 0), 0.0);
      EXPECT_NEAR(rec.data.imu().localTransform.z(), 0.15, 1e-12);
    } else {
      ++odometry;
      EXPECT_FALSE(rec.data.odomPose().isNull());
    }
  }
  EXPECT_EQ(frames, 41);
  // The stream ends with the last frame (at 20 s): IMU at 200 Hz and odometry at 50 Hz up to it.
  EXPECT_EQ(imu, 4000);
  EXPECT_EQ(odometry, 1001);
  EXPECT_EQ(lastKind, static_cast<int>(DatasetRecord::Kind::kFrame));
}

TEST(SimDataset, WindowAndSensorChoices) {
  const auto& run = test::loopRun();
  DatasetReaderOptions options;
  options.startFrame = 5;
  options.maxFrames = 3;
  options.imu = false;
  SimDatasetReader reader(run.dir->path(), options);
  EXPECT_EQ(reader.frameCount(), 3);
  DatasetRecord rec;
  std::vector<int> ids;
  double firstAux = 0.0;
  while (reader.next(rec)) {
    if (rec.kind == DatasetRecord::Kind::kFrame) ids.push_back(rec.data.id());
    else if (firstAux == 0.0) firstAux = rec.stamp;
    EXPECT_NE(rec.kind, DatasetRecord::Kind::kImu);
  }
  EXPECT_EQ(ids, std::vector<int>({6, 7, 8}));
  EXPECT_GT(firstAux, run.recorded.frames[4].stamp);  // odometry after the last skipped frame

  // Through the registry, with the query form: stereo pair and the long-range scan.
  auto stereo = rtabmap::openDatasetReader("sim", run.dir->path() + "?camera=stereo&scan=utm");
  ASSERT_TRUE(stereo->next(rec));
  while (rec.kind != DatasetRecord::Kind::kFrame) ASSERT_TRUE(stereo->next(rec));
  EXPECT_TRUE(rec.data.isStereo());
  EXPECT_EQ(rec.data.imageRaw().type(), CV_8UC1);
  EXPECT_EQ(rec.data.depthOrRightRaw().type(), CV_8UC1);
  EXPECT_EQ(rec.data.laserScanRaw().maxPoints(), 1081);
  auto lidar = rtabmap::openDatasetReader("sim", run.dir->path() + "?camera=none&scan=lidar&depth32=1");
  DatasetReaderOptions noAux;
  noAux.imu = noAux.odometry = false;
  SimReaderOptions floatDepth;
  floatDepth.depth32 = true;
  SimDatasetReader f32(run.dir->path(), noAux, floatDepth);
  ASSERT_TRUE(f32.next(rec));
  EXPECT_EQ(rec.data.depthOrRightRaw().type(), CV_32FC1);
  EXPECT_THROW(rtabmap::openDatasetReader("sim", run.dir->path() + "?camera=fisheye"), rtabmap::FormatError);
  EXPECT_THROW(rtabmap::openDatasetReader("sim", run.dir->path() + "?colour=1"), rtabmap::FormatError);
}

TEST(SimDataset, ClearErrorsForWhatIsNotASimDataset) {
  rtabmap::test::TempDir empty("rtabmap_sim_empty");
  try {
    SimDatasetReader reader(empty.path());
    FAIL() << "expected FormatError";
  } catch (const rtabmap::FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("info.yaml"), std::string::npos) << e.what();
  }
  SimDatasetInfo info;
  info.scenario = "multisession";
  writeSimScenarioInfo(empty.path(), info, {"session1", "session2"});
  try {
    SimDatasetReader reader(empty.path());
    FAIL() << "expected FormatError";
  } catch (const rtabmap::FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("session1"), std::string::npos) << e.what();
  }
  // A truncated scan file is named in the error.
  rtabmap::test::TempDir copy("rtabmap_sim_copy");
  fs::copy(test::loopRun().dir->path(), copy.path(), fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  fs::resize_file(fs::path(copy.path()) / "scan_urg" / "000003.bin", 100);
  SimDatasetReader reader(copy.path());
  try {
    reader.readFrame(3);
    FAIL() << "expected FormatError";
  } catch (const rtabmap::FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("000003.bin"), std::string::npos) << e.what();
  }
}

TEST(SimDataset, SameSeedSameBytesOtherSeedOtherBytes) {
  const Building& building = test::loopBuilding();
  SimulationConfig config = test::smallConfig(96, 72);
  rtabmap::test::TempDir a("rtabmap_sim_a"), b("rtabmap_sim_b"), c("rtabmap_sim_c");
  test::writeRun(building, config, a.path(), 3, nullptr, 6.0);
  test::writeRun(building, config, b.path(), 3, nullptr, 6.0);
  test::writeRun(building, config, c.path(), 4, nullptr, 6.0);
  const auto fa = allFiles(a.path());
  const auto fb = allFiles(b.path());
  const auto fc = allFiles(c.path());
  ASSERT_GT(fa.size(), 40u);
  ASSERT_EQ(fa.size(), fb.size());
  for (const auto& [name, bytes] : fa) {
    ASSERT_TRUE(fb.count(name)) << name;
    EXPECT_TRUE(bytes == fb.at(name)) << name << " differs between two runs of the same seed";
  }
  // Another seed: other noise (the building is shared here, so images at rest match; odometry,
  // IMU and the info file do not).
  for (const char* name : {"imu.txt", "odometry.txt", "info.yaml"}) EXPECT_FALSE(fa.at(name) == fc.at(name)) << name;
}

// A depth pixel back-projected with the ground-truth pose lands on the laser's hit of the same
// wall: pixels that see the laser plane's height, against the segment between the two nearest
// laser points, within 1 cm.
TEST(SimDataset, DepthPixelsLandOnTheLaserHits) {
  const auto& run = test::loopRun();
  SimDatasetReader reader(run.dir->path());
  const double laserHeight = run.config.urg.baseToLaser.z();
  int checked = 0, within = 0;
  std::vector<double> errors;
  for (int i = 10; i < reader.totalFrames(); i += 6) {
    const SimFrameRecord f = reader.readFrame(i);
    const Transform camera = f.groundTruth * reader.rgbModel().localTransform();
    std::vector<Eigen::Vector2d> hits;
    const Transform laser = f.groundTruth * f.urg.localTransform();
    for (int k = 0; k < f.urg.size(); ++k) {
      const Eigen::Vector3d p = laser * f.urg.point(k).cast<double>();
      hits.emplace_back(p.x(), p.y());
    }
    ASSERT_GT(hits.size(), 100u);
    for (int v = 0; v < f.depth.rows; v += 2) {
      for (int u = 0; u < f.depth.cols; u += 2) {
        const float z = rtabmap::SensorData::depthAt(f.depth, u, v);
        if (z <= 0.0f || z > 5.0f) continue;
        double x, y, zz;
        reader.rgbModel().project(u, v, z, x, y, zz);
        const Eigen::Vector3d p = camera * Eigen::Vector3d(x, y, zz);
        if (std::fabs(p.z() - laserHeight) > 0.01) continue;
        // The two laser points nearest to the pixel's point, and the wall segment between them.
        size_t a = 0, b = 1;
        double da = 1e9, db = 1e9;
        for (size_t k = 0; k < hits.size(); ++k) {
          const double d = (hits[k] - p.head<2>()).norm();
          if (d < da) {
            b = a;
            db = da;
            a = k;
            da = d;
          } else if (d < db) {
            b = k;
            db = d;
          }
        }
        // Only where the laser samples the surface densely (not across an occlusion edge).
        if (da > 0.05 || (hits[a] - hits[b]).norm() > 0.06) continue;
        const Eigen::Vector2d ab = hits[b] - hits[a];
        const double t = std::clamp((p.head<2>() - hits[a]).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
        const double error = (hits[a] + t * ab - p.head<2>()).norm();
        errors.push_back(error);
        ++checked;
        within += error < 0.01;
      }
    }
  }
  ASSERT_GT(checked, 200);
  std::sort(errors.begin(), errors.end());
  EXPECT_LT(errors[errors.size() / 2], 0.003);
  EXPECT_GT(within, 0.97 * checked) << within << " of " << checked << " within 1 cm";
}

// Block matching on textured patches at one depth: the disparity found between the left (the
// RGB image in grey) and right images is fx * baseline / depth within half a pixel. Views from
// inside the rooms of the loop building, where posters, shelves and accent walls give texture.
TEST(SimStereo, DisparityMatchesDepth) {
  const Building& building = test::loopBuilding();
  SimulationConfig config = test::smallConfig(320, 240);
  config.scanUrg = config.scanUtm = false;
  const Simulator simulator(*building.world, config);
  const rtabmap::StereoCameraModel model = config.camera.stereoModel();
  const double fx = model.left().fx();
  const double baseline = model.baseline();
  int tested = 0, good = 0;
  const int r = 6;  // 13 x 13 windows
  for (const NavNode& node : building.nav.nodes()) {
    if (node.kind != NavNodeKind::kRoom) continue;
    for (int k = 0; k < 4; ++k) {
      const SimFrame f = simulator.capture({node.position.x(), node.position.y(), k * M_PI / 2.0});
      cv::Mat left, right;
      cv::cvtColor(f.bgr, left, cv::COLOR_BGR2GRAY);
      left.convertTo(left, CV_32F);
      f.right.convertTo(right, CV_32F);
      for (int v = 20; v < left.rows - 20; v += 12) {
        for (int u = 80; u < left.cols - 20; u += 12) {
          const float z = f.depth.at<float>(v, u);
          if (z <= 0.5f || z > 4.0f) continue;
          double zMin, zMax;
          cv::minMaxLoc(f.depth(cv::Rect(u - r, v - r, 2 * r + 1, 2 * r + 1)), &zMin, &zMax);
          if (zMax - zMin > 0.01 * z) continue;
          const cv::Mat patch = left(cv::Rect(u - r, v - r, 2 * r + 1, 2 * r + 1));
          cv::Scalar mean, sd;
          cv::meanStdDev(patch, mean, sd);
          if (sd[0] < 8.0) continue;
          const double expected = fx * baseline / z;
          // Zero-mean normalised cross-correlation over integer disparities, then a parabola.
          // One matchTemplate over the whole search strip: result column j is disparity maxD - j.
          const int maxD = std::min(60, u - r - 1);
          cv::Mat result;
          cv::matchTemplate(right(cv::Rect(u - maxD - r, v - r, maxD + 2 * r + 1, 2 * r + 1)), patch, result, cv::TM_CCOEFF_NORMED);
          std::vector<double> score(static_cast<size_t>(maxD) + 1);
          for (int d = 0; d <= maxD; ++d) score[static_cast<size_t>(d)] = result.at<float>(0, maxD - d);
          const int best = static_cast<int>(std::max_element(score.begin(), score.end()) - score.begin());
          if (best == 0 || best == maxD || score[static_cast<size_t>(best)] < 0.8) continue;
          const double s0 = score[static_cast<size_t>(best - 1)], s1 = score[static_cast<size_t>(best)],
                       s2 = score[static_cast<size_t>(best + 1)];
          const double disparity = best + 0.5 * (s0 - s2) / (s0 - 2 * s1 + s2);
          // Uniqueness: repeated patterns (bricks, tiles, wallpaper) match one period away almost
          // as well; a matcher cannot tell, so such patches say nothing about the renderer.
          double second = -1.0;
          for (int d = 0; d <= maxD; ++d) {
            if (std::abs(d - best) > 2) second = std::max(second, score[static_cast<size_t>(d)]);
          }
          if (s1 - second < 0.1) continue;
          ++tested;
          good += std::fabs(disparity - expected) < 0.5;
        }
      }
    }
  }
  ASSERT_GT(tested, 100);
  EXPECT_GT(good, 0.9 * tested) << good << " of " << tested << " within 0.5 px";
}

// Every lidar point lies on a surface: the floor, the ceiling, or a face of a solid.
TEST(SimDataset, LidarPointsLieOnSurfaces) {
  const auto& run = test::loopRun();
  const World& world = *test::loopBuilding().world;
  SimDatasetReader reader(run.dir->path());
  const SimFrameRecord f = reader.readFrame(30);
  const Transform lidar = f.groundTruth * f.lidar.localTransform();
  ASSERT_GT(f.lidar.size(), 5000);
  int off = 0;
  for (int k = 0; k < f.lidar.size(); k += 7) {
    const Eigen::Vector3d p = lidar * f.lidar.point(k).cast<double>();
    const bool floorOrCeiling = std::fabs(p.z()) < 1e-3 || std::fabs(p.z() - world.ceilingHeight()) < 1e-3;
    bool onFace = false;
    if (!floorOrCeiling) onFace = world.clearance(p.head<2>()) < 1e-3;
    bool onTop = false;
    if (!floorOrCeiling && !onFace) onTop = world.insideSolid(p.head<2>()) && std::fabs(p.z() - 0.0) > 0.1;
    off += !(floorOrCeiling || onFace || onTop);
  }
  EXPECT_EQ(off, 0);
}
