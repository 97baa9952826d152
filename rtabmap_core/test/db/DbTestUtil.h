#pragma once
// Helpers of the long-term-memory tests: deterministic nodes (every field derived from the
// id, so a checker can rebuild what a writer saved), exact comparisons, and raw SQLite access
// to craft files our API would never write (newer version, foreign database).
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <opencv2/core.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "rtabmap_core/codec/Compression.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/geometry/CameraModel.h"
#include "rtabmap_core/geometry/LaserScan.h"
#include "rtabmap_core/memory/Signature.h"

namespace rtabmap::test::db {

using rtabmap::db::StoredWord;

inline cv::Mat randomMat(int rows, int cols, int type, unsigned seed) {
  cv::Mat m(rows, cols, type);
  cv::RNG rng(seed);
  rng.fill(m, cv::RNG::UNIFORM, 0, 255);
  return m;
}

inline int wordIdOf(int nodeId, int index) { return 1 + (nodeId * 7 + index * 13) % 5000; }

// Words the node introduces: those of its keypoints with an id not used by an earlier node
// would be the realistic rule; tests only need each word saved once, by the node whose id
// first maps to it here (the smallest node id using it).
inline std::vector<StoredWord> wordsOf(int nodeId, int words) {
  std::vector<StoredWord> result;
  for (int i = 0; i < words; ++i) {
    const int id = wordIdOf(nodeId, i);
    result.push_back(StoredWord{id, randomMat(1, 32, CV_8UC1, static_cast<unsigned>(id))});
  }
  return result;
}

// A node with every part filled: words, links, compressed images, depth, scan, user data,
// local grid, IMU, GPS. Deterministic in (id, mapId, words).
inline Signature makeNode(int id, int mapId, int words = 40) {
  std::mt19937 rng(static_cast<unsigned>(id));
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const std::string label = id % 10 == 0 ? "place" + std::to_string(id) : std::string();
  Signature node(id, mapId, id % 7, 1000.0 + id * 0.1, label, Transform(0.5 * id, 0.1 * id, 0.0, 0.0, 0.0, 0.01 * id),
                 Transform(0.5 * id + 0.01, 0.1 * id, 0.0, 0.0, 0.0, 0.0));
  node.setVelocity({0.1f * id, 0.0f, 0.0f, 0.0f, 0.0f, 0.01f});

  std::multimap<int, int> wordIds;
  std::vector<cv::KeyPoint> keypoints;
  std::vector<cv::Point3f> points;
  for (int i = 0; i < words; ++i) {
    wordIds.emplace(wordIdOf(id, i), i);
    // Braces: the draws happen in order (as arguments of a call the order is the compiler's).
    keypoints.push_back(cv::KeyPoint{640 * u(rng), 480 * u(rng), 31.0f, 360 * u(rng), u(rng), i % 4, -1});
    const float nan = std::numeric_limits<float>::quiet_NaN();
    points.push_back(i % 5 == 0 ? cv::Point3f(nan, nan, nan) : cv::Point3f{u(rng), u(rng), 5 * u(rng)});
  }
  node.setWords(wordIds, keypoints, points, randomMat(words, 32, CV_8UC1, static_cast<unsigned>(id) * 31));

  const cv::Mat image = randomMat(24, 32, CV_8UC3, static_cast<unsigned>(id));
  const cv::Mat depth = randomMat(24, 32, CV_16UC1, static_cast<unsigned>(id) + 1);
  SensorData data(cv::Mat(), cv::Mat(), CameraModel(525.0, 525.0, 16.0, 12.0, CameraModel::opticalRotation(), 0.0, cv::Size(32, 24)), id, node.stamp());
  const cv::Mat scan = randomMat(1, 60, CV_32FC2, static_cast<unsigned>(id) + 2);
  data.setCompressed(codec::compressImage(image, ".png"), codec::compressDepth(depth), codec::compressData(scan),
                     codec::compressData(randomMat(1, 10, CV_8UC1, static_cast<unsigned>(id) + 3)));
  SensorData::ScanInfo scanInfo;
  scanInfo.format = LaserScan::kXY;
  scanInfo.maxPoints = 360;
  scanInfo.rangeMin = 0.1;
  scanInfo.rangeMax = 30.0;
  scanInfo.localTransform = Transform(0.2, 0.0, 0.3, 0.0, 0.0, 0.0);
  scanInfo.angleMin = -2.0;
  scanInfo.angleMax = 2.0;
  scanInfo.angleIncrement = 4.0 / 359.0;
  data.setLaserScanInfo(scanInfo);
  LocalGrid grid;
  grid.ground = randomMat(1, 30, CV_32FC2, static_cast<unsigned>(id) + 4);
  grid.obstacles = randomMat(1, 20, CV_32FC2, static_cast<unsigned>(id) + 5);
  grid.cellSize = 0.05f;
  grid.viewPoint = Eigen::Vector3f(0.1f, 0.0f, 0.5f);
  data.setLocalGrid(grid);
  IMU imu;
  imu.orientation = Eigen::Quaterniond(1, 0, 0, 0);
  imu.angularVelocity = Eigen::Vector3d(0.01 * id, 0, 0);
  imu.linearAcceleration = Eigen::Vector3d(0, 0, 9.81);
  data.setIMU(imu);
  GPS gps;
  gps.stamp = node.stamp();
  gps.longitude = -71.9 + id * 1e-6;
  gps.latitude = 45.4;
  data.setGPS(gps);
  data.setGroundTruth(node.getGroundTruthPose());
  node.setSensorData(data);

  Link::InfMatrix information = Link::InfMatrix::Identity() * 100.0;
  if (id > 1) node.addLink(Link(id, id - 1, Link::kNeighbor, Transform(-0.5, -0.1, 0.0, 0.0, 0.0, -0.01), information));
  if (id >= 20 && id % 20 == 0) {
    information(0, 1) = information(1, 0) = 3.0;  // a full (non-diagonal) matrix
    node.addLink(Link(id, id - 19, Link::kGlobalClosure, Transform(1.0, 2.0, 0.0, 0.0, 0.0, 0.3), information,
                      randomMat(1, 4, CV_8UC1, static_cast<unsigned>(id))));
  }
  return node;
}

inline bool sameMat(const cv::Mat& a, const cv::Mat& b) {
  if (a.empty() || b.empty()) return a.empty() && b.empty();
  if (a.type() != b.type() || a.size() != b.size()) return false;
  for (int r = 0; r < a.rows; ++r) {
    if (std::memcmp(a.ptr(r), b.ptr(r), a.cols * a.elemSize()) != 0) return false;
  }
  return true;
}

inline void expectSameLinks(const std::multimap<int, Link>& expected, const std::multimap<int, Link>& actual) {
  ASSERT_EQ(expected.size(), actual.size());
  for (const auto& [to, link] : expected) {
    bool found = false;
    auto range = actual.equal_range(to);
    for (auto it = range.first; it != range.second; ++it) {
      if (it->second.type() != link.type()) continue;
      found = true;
      EXPECT_EQ(link.from(), it->second.from());
      EXPECT_EQ(link.transform(), it->second.transform()) << "link to " << to;
      EXPECT_TRUE(link.infMatrix() == it->second.infMatrix()) << "link to " << to;
      EXPECT_TRUE(sameMat(link.userData(), it->second.userData())) << "link to " << to;
    }
    EXPECT_TRUE(found) << "missing link to " << to << " of type " << link.typeName();
  }
}

// Bit-exact comparison of everything saved.
inline void expectSameNode(const Signature& e, const Signature& a) {
  SCOPED_TRACE("node " + std::to_string(e.id()));
  EXPECT_EQ(e.id(), a.id());
  EXPECT_EQ(e.mapId(), a.mapId());
  EXPECT_EQ(e.weight(), a.weight());
  EXPECT_EQ(e.stamp(), a.stamp());
  EXPECT_EQ(e.label(), a.label());
  EXPECT_EQ(e.getPose(), a.getPose());
  EXPECT_EQ(e.getGroundTruthPose(), a.getGroundTruthPose());
  EXPECT_EQ(e.getVelocity(), a.getVelocity());
  EXPECT_EQ(e.getWords(), a.getWords());
  ASSERT_EQ(e.getWordsKpts().size(), a.getWordsKpts().size());
  for (size_t i = 0; i < e.getWordsKpts().size(); ++i) {
    const cv::KeyPoint &x = e.getWordsKpts()[i], &y = a.getWordsKpts()[i];
    EXPECT_TRUE(x.pt == y.pt && x.size == y.size && x.angle == y.angle && x.response == y.response &&
                x.octave == y.octave && x.class_id == y.class_id)
        << "keypoint " << i;
  }
  ASSERT_EQ(e.getWords3().size(), a.getWords3().size());
  EXPECT_EQ(0, std::memcmp(e.getWords3().data(), a.getWords3().data(), e.getWords3().size() * sizeof(cv::Point3f)));
  EXPECT_TRUE(sameMat(e.getWordsDescriptors(), a.getWordsDescriptors()));
  expectSameLinks(e.getLinks(), a.getLinks());

  const SensorData &d = e.sensorData(), &b = a.sensorData();
  EXPECT_EQ(d.imageCompressed(), b.imageCompressed());
  EXPECT_EQ(d.depthOrRightCompressed(), b.depthOrRightCompressed());
  EXPECT_EQ(d.laserScanCompressed(), b.laserScanCompressed());
  EXPECT_EQ(d.userDataCompressed(), b.userDataCompressed());
  ASSERT_EQ(d.cameraModels().size(), b.cameraModels().size());
  for (size_t i = 0; i < d.cameraModels().size(); ++i) {
    EXPECT_EQ(d.cameraModels()[i].serialize(), b.cameraModels()[i].serialize());
  }
  EXPECT_EQ(d.laserScanInfo().format, b.laserScanInfo().format);
  EXPECT_EQ(d.laserScanInfo().maxPoints, b.laserScanInfo().maxPoints);
  EXPECT_EQ(d.laserScanInfo().rangeMin, b.laserScanInfo().rangeMin);
  EXPECT_EQ(d.laserScanInfo().rangeMax, b.laserScanInfo().rangeMax);
  EXPECT_EQ(d.laserScanInfo().localTransform, b.laserScanInfo().localTransform);
  EXPECT_EQ(d.laserScanInfo().angleMin, b.laserScanInfo().angleMin);
  EXPECT_EQ(d.laserScanInfo().angleMax, b.laserScanInfo().angleMax);
  EXPECT_EQ(d.laserScanInfo().angleIncrement, b.laserScanInfo().angleIncrement);
  EXPECT_TRUE(sameMat(d.localGrid().ground, b.localGrid().ground));
  EXPECT_TRUE(sameMat(d.localGrid().obstacles, b.localGrid().obstacles));
  EXPECT_TRUE(sameMat(d.localGrid().empty, b.localGrid().empty));
  EXPECT_EQ(d.localGrid().cellSize, b.localGrid().cellSize);
  EXPECT_EQ(d.localGrid().viewPoint, b.localGrid().viewPoint);
  EXPECT_EQ(d.imu().angularVelocity, b.imu().angularVelocity);
  EXPECT_EQ(d.imu().linearAcceleration, b.imu().linearAcceleration);
  EXPECT_EQ(d.imu().orientation.coeffs(), b.imu().orientation.coeffs());
  EXPECT_EQ(d.gps().stamp, b.gps().stamp);
  EXPECT_EQ(d.gps().longitude, b.gps().longitude);
}

// Raw SQLite through the library already loaded by rtabmap_core (the tests do not link SQLite
// themselves): for files our API refuses to write.
class RawSqlite {
 public:
  explicit RawSqlite(const std::string& path) {
    open_ = reinterpret_cast<decltype(open_)>(symbol("sqlite3_open"));
    exec_ = reinterpret_cast<decltype(exec_)>(symbol("sqlite3_exec"));
    close_ = reinterpret_cast<decltype(close_)>(symbol("sqlite3_close"));
    if (open_(path.c_str(), &db_) != SQLITE_OK) throw std::runtime_error("sqlite3_open " + path);
  }
  ~RawSqlite() { close_(db_); }
  void exec(const std::string& sql) {
    char* error = nullptr;
    if (exec_(db_, sql.c_str(), nullptr, nullptr, &error) != SQLITE_OK) {
      throw std::runtime_error("sqlite3_exec \"" + sql + "\": " + (error ? error : "?"));
    }
  }

 private:
  static void* symbol(const char* name) {
    void* s = dlsym(RTLD_DEFAULT, name);
    if (!s) throw std::runtime_error(std::string("symbol ") + name + " not found");
    return s;
  }
  int (*open_)(const char*, sqlite3**) = nullptr;
  int (*exec_)(sqlite3*, const char*, int (*)(void*, int, char**, char**), void*, char**) = nullptr;
  int (*close_)(sqlite3*) = nullptr;
  sqlite3* db_ = nullptr;
};

inline void writeFile(const std::string& path, const std::vector<char>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

inline std::vector<char> readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Message of the DatabaseError thrown by f ("" if none).
template <typename F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const DatabaseError& e) {
    return e.what();
  }
  return "";
}

}  // namespace rtabmap::test::db
