// 3D ICP on a sparse ring lidar (issue 5, 3D clouds): a 16-ring sensor (VLP-16: +-15 degrees,
// 2 degrees apart, 0.75 m above the floor) in a closed room samples the floor on circles 0.5 to
// 2 m apart. The k nearest neighbours of a floor point are then one ring's arc, or an arc and
// the foot of a wall: a normal fitted to them is not the floor's. These tests fail with such
// normals (every neighbourhood fitted blindly) or with pairs of incompatible surfaces kept.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <vector>

#include "../../src/registration/IcpCloud.h"
#include "common/TestData.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/odometry/OdometryS2M.h"
#include "rtabmap_core/registration/IcpRegistration.h"

namespace rtabmap {
namespace {

constexpr double kLidarHeight = 0.75;
constexpr double kCeiling = 2.7;

// A room [0, 12] x [-2, 2] x [0, 2.7] with a pillar [7, 7.6] x [-2, -1.2]: walls, floor and
// ceiling are what a ring lidar sees indoors; the pillar breaks the symmetry along x.
double castRay(const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double best = 1e9;
  const auto plane = [&](int axis, double value, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
    if (std::abs(d(axis)) < 1e-12) return;
    const double t = (value - o(axis)) / d(axis);
    if (t <= 1e-6 || t >= best) return;
    const Eigen::Vector3d p = o + t * d;
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    if (p(a) < lo(0) - 1e-9 || p(a) > hi(0) + 1e-9 || p(b) < lo(1) - 1e-9 || p(b) > hi(1) + 1e-9) return;
    best = t;
  };
  // Planes as (axis, value, bounds over the two other axes in cyclic order: x->(y,z), y->(z,x), z->(x,y)).
  plane(0, 0.0, {-2, 0}, {2, kCeiling});
  plane(0, 12.0, {-2, 0}, {2, kCeiling});
  plane(1, -2.0, {0, 0}, {kCeiling, 12});
  plane(1, 2.0, {0, 0}, {kCeiling, 12});
  plane(2, 0.0, {0, -2}, {12, 2});
  plane(2, kCeiling, {0, -2}, {12, 2});
  // The pillar's faces.
  plane(0, 7.0, {-2, 0}, {-1.2, kCeiling});
  plane(0, 7.6, {-2, 0}, {-1.2, kCeiling});
  plane(1, -1.2, {0, 7.0}, {kCeiling, 7.6});
  return best;
}

// One sweep from the robot at (x, y) with heading 0: 16 rings x 900 azimuths, in the base frame
// (the lidar 0.75 m above the base, on the floor).
LaserScan ringScan(double x, double y) {
  const Eigen::Vector3d origin(x, y, kLidarHeight);
  std::vector<float> xyz;
  constexpr int kRings = 16, kAzimuths = 900;
  for (int a = 0; a < kAzimuths; ++a) {
    const double azimuth = 2.0 * M_PI * a / kAzimuths;
    for (int r = 0; r < kRings; ++r) {
      const double elevation = (-15.0 + 2.0 * r) * M_PI / 180.0;
      const Eigen::Vector3d d(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                              std::sin(elevation));
      const double t = castRay(origin, d);
      if (t > 50.0) continue;
      const Eigen::Vector3d p = origin + t * d - Eigen::Vector3d(x, y, 0.0);
      xyz.insert(xyz.end(), {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())});
    }
  }
  cv::Mat data(1, static_cast<int>(xyz.size() / 3), CV_32FC3);
  std::copy(xyz.begin(), xyz.end(), data.ptr<float>(0));
  return LaserScan(data, kRings * kAzimuths, 0.0, 50.0, LaserScan::kXYZ);
}

// The settings of config/lidar3d.ini that matter here.
ParametersMap ringParameters() {
  return {{Parameters::kRegStrategy(), "1"},
          {Parameters::kIcpPointToPlane(), "true"},
          {Parameters::kIcpPointToPlaneK(), "20"},
          {Parameters::kIcpVoxelSize(), "0.1"},
          {Parameters::kIcpMaxCorrespondenceDistance(), "1"},
          {Parameters::kIcpIterations(), "30"},
          {Parameters::kIcpEpsilon(), "0.001"},
          {Parameters::kIcpCorrespondenceRatio(), "0.2"},
          {Parameters::kIcpMaxTranslation(), "2"},
          {Parameters::kOdomF2MScanMaxSize(), "30000"}};
}

TEST(IcpRingLidar, FloorNormalsAreVerticalOrAbsent) {
  const IcpOptions options = IcpOptions::fromParameters(ringParameters());
  icp::IcpCloud cloud;
  std::string why;
  ASSERT_TRUE(icp::prepareIcpCloud(ringScan(3.0, 0.3), options, true, "ring", &cloud, &why)) << why;
  int floor = 0, tilted = 0;
  for (const auto& p : *cloud.cloud) {
    if (p.z > 0.005f) continue;  // exactly on the floor (a voxel averaging a wall's foot is above)
    ++floor;
    if (std::abs(p.normal_z) < std::cos(10.0 * M_PI / 180.0)) ++tilted;
  }
  // Measured 89 of 221 (a floor ring beside the foot of a wall fits one tilted plane); the
  // ring arcs alone, linear, get none.
  ASSERT_GT(floor, 50);
  EXPECT_LT(tilted, 0.5 * floor) << tilted << " of " << floor << " floor normals tilted more than 10 degrees";
}

TEST(IcpRingLidar, ShapeOfNeighbourhoods) {
  // A line, a plane, a blob (eigenvalues ascending).
  EXPECT_FALSE(icp::neighbourhoodShape(Eigen::Vector3d(1e-6, 1e-4, 1.0)).isPlanar());
  EXPECT_TRUE(icp::neighbourhoodShape(Eigen::Vector3d(1e-6, 0.5, 1.0)).isPlanar());
  EXPECT_FALSE(icp::neighbourhoodShape(Eigen::Vector3d(0.8, 0.9, 1.0)).isPlanar());
}

TEST(IcpRingLidar, ScanToMapKeepsHeightAndAttitude) {
  // Driving 0.25 m per scan along the room with the exact motion as guess (wheel odometry of a
  // planar robot): the ICP corrections must not tilt or lift the robot. With normals fitted to
  // single rings and floor rings paired with walls, z and pitch drifted within a few scans.
  OdometryS2M odometry(ringParameters());
  Transform previous;
  for (int i = 0; i < 20; ++i) {
    const double x = 1.5 + 0.25 * i;
    SensorData data(ringScan(x, 0.3), i, 0.5 * i);
    const Transform truth(x, 0.3, 0.0, 0.0, 0.0, 0.0);
    const Transform guess = previous.isNull() ? Transform() : previous.inverse() * truth;
    previous = truth;
    OdometryInfo info;
    const Transform pose = odometry.process(data, guess, &info);
    ASSERT_FALSE(pose.isNull()) << "scan " << i << ": " << info.lostReason;
    const Transform error = Transform(1.5, 0.3, 0.0, 0.0, 0.0, 0.0).inverse() * truth;
    const Transform drift = error.inverse() * pose;
    // Measured: at most 0.13 m and 1.1 degrees; with floor rings paired with walls
    // (Icp/PointToPlaneMaxNormalAngle 0) 1.43 m and 14.5 degrees. Not yet centimetres: a
    // floor ring next to the foot of a wall still fits one tilted plane (two parallel lines
    // always do), which no neighbourhood test can tell from a surface.
    EXPECT_LT(std::abs(drift.z()), 0.2) << "scan " << i;
    EXPECT_LT(drift.getNorm(), 0.25) << "scan " << i;
    EXPECT_LT(std::abs(drift.pitch()) + std::abs(drift.roll()), 2.0 * M_PI / 180.0) << "scan " << i;
  }
}

TEST(IcpRingLidar, FloorIsNotPairedWithAWall) {
  // A floor (source, normals +z) in front of the foot of a wall (target, normals +x): every
  // floor point is within reach of the wall, and none is of the same surface.
  ParametersMap p = ringParameters();
  icp::IcpCloud target, source;
  for (int i = 0; i < 40; ++i) {
    for (int j = 0; j < 40; ++j) {
      icp::Point wall;
      wall.x = 0.0f;
      wall.y = 0.05f * i;
      wall.z = 0.05f * j;
      wall.normal_x = 1.0f;
      wall.normal_y = wall.normal_z = 0.0f;
      target.cloud->push_back(wall);
      icp::Point floor;
      floor.x = 0.05f + 0.05f * j;
      floor.y = 0.05f * i;
      floor.z = -0.05f;
      floor.normal_z = 1.0f;
      floor.normal_x = floor.normal_y = 0.0f;
      source.cloud->push_back(floor);
    }
  }
  for (icp::IcpCloud* c : {&target, &source}) {
    c->is2d = false;
    c->hasNormals = true;
    c->expectedPoints = c->size();
    c->normalMoment = icp::normalMomentSum(*c->cloud, false, &c->normalCount);
  }
  p[Parameters::kIcpCorrespondenceRatio()] = "0";
  p[Parameters::kIcpPointToPlaneMinComplexity()] = "0";
  const IcpOptions strict = IcpOptions::fromParameters(p);
  target.buildIndex(strict.maxCorrespondenceDistance);
  RegistrationInfo info;
  icp::registerClouds(target, source, Transform::Identity(), strict, &info);
  EXPECT_FALSE(info.success);
  EXPECT_EQ(info.icpCorrespondences, 0) << "a floor paired with a wall";
}

TEST(IcpRingLidar, KittiVelodynePairsStayRight) {
  // Real HDL-64 scans: the normal and pair tests must not cost the dense lidar its accuracy
  // (issue 5 goal: under 5 cm and 0.2 degree from the identity, settings of the bench).
  const std::string dir = test::sharedDataPath("kitti00_velodyne");
  if (dir.empty()) GTEST_SKIP() << "../shared/data/kitti00_velodyne absent";
  test::TempDir tmp("rtabmap_kitti_calib");
  // The Tr line of KITTI odometry sequence 00's calib.txt (velodyne -> cam0), as the bench.
  std::ofstream(tmp.file("calib.txt"))
      << "Tr: 4.276802385584e-04 -9.999672484946e-01 -8.084491683471e-03 -1.198459927713e-02 "
         "-7.210626507497e-03 8.081198471645e-03 -9.999413164504e-01 -5.403984729748e-02 "
         "9.999738645903e-01 4.859485810390e-04 -7.206933692422e-03 -2.921968648686e-01\n";
  DatasetReaderOptions options;
  options.calibrationPath = tmp.file("calib.txt");
  options.images = false;
  auto reader = openDatasetReader("kitti", dir, options);
  std::map<int, SensorData> frames;
  DatasetRecord record;
  while (reader->next(record)) {
    if (record.kind == DatasetRecord::Kind::kFrame) frames[record.data.id() - 1] = record.data;
  }
  const IcpRegistration icp(ParametersMap{{Parameters::kIcpPointToPlane(), "true"},
                                          {Parameters::kIcpPointToPlaneK(), "10"},
                                          {Parameters::kIcpVoxelSize(), "0.2"},
                                          {Parameters::kIcpMaxCorrespondenceDistance(), "1.0"},
                                          {Parameters::kIcpIterations(), "30"},
                                          {Parameters::kIcpEpsilon(), "0.0001"},
                                          {Parameters::kIcpMaxTranslation(), "2"}});
  for (const auto& [a, b] : {std::pair<int, int>{94, 95}, std::pair<int, int>{198, 199}}) {
    ASSERT_TRUE(frames.count(a) && frames.count(b)) << a << "->" << b;
    const Transform truth = frames[a].groundTruth().inverse() * frames[b].groundTruth();
    RegistrationInfo info;
    const Transform t = icp.computeTransform(frames[a].laserScanRaw(), frames[b].laserScanRaw(),
                                             Transform::Identity(), &info);
    ASSERT_FALSE(t.isNull()) << a << "->" << b << ": " << info.rejectedMsg;
    const Transform error = truth.inverse() * t;
    EXPECT_LT(error.getNorm(), 0.05) << a << "->" << b;
    EXPECT_LT(error.getAngle() * 180.0 / M_PI, 0.2) << a << "->" << b;
  }
}

}  // namespace
}  // namespace rtabmap
