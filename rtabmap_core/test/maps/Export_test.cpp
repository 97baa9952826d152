// rtabmap-export on a small database: grid (PGM + YAML + PNG), OctoMap, cloud, poses; grids
// stored or computed again; errors.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/TestData.h"
#include "maps/MapsTestUtil.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/maps/LocalGridStages.h"
#include "rtabmap_core/maps/MapIO.h"
#include "rtabmap_core/maps/OccupancyGrid.h"

using namespace rtabmap;
using rtabmap::test::TempDir;
using rtabmap::test::toolPath;

namespace {

struct ToolRun {
  int exitCode = -1;
  std::string out;  // stdout
};

ToolRun runExport(const std::string& arguments) {
  const std::string command = toolPath("export") + " " + arguments + " 2>/dev/null";
  ToolRun run;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return run;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) run.out.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

nlohmann::json lastJson(const std::string& text) {
  std::istringstream lines(text);
  std::string line, last;
  while (std::getline(lines, line)) {
    if (!line.empty()) last = line;
  }
  return nlohmann::json::parse(last);
}

struct Fixture {
  std::map<int, Transform> poses;
  std::map<int, LocalGrid> grids;  // what the nodes store (nodes 4 and 7 store none)
  LocalGridOptions options;
};

// Ten nodes down a corridor, with their scans, neighbour links and (but for two) local grids.
// The links are exact; the stored (odometry) poses drift sideways by `odometryDrift` metres per
// node, as wheel odometry does, when it is not 0.
Fixture makeDatabase(const std::string& path, double odometryDrift = 0.0) {
  Fixture f;
  f.options.sensor = LocalGridOptions::Sensor::kScan;
  f.options.cellSize = 0.05f;
  f.options.rangeMax = 0.0f;
  const auto world = test::World2D::room(0, 0, 8, 3);
  db::Database::Options o;
  o.sessionParameters = Parameters::serialize(
      {{"Grid/Sensor", "0"}, {"Grid/CellSize", "0.05"}, {"Grid/RangeMax", "0"}});
  db::Database database(path, o);
  Transform previous;
  for (int id = 1; id <= 10; ++id) {
    const Transform pose(0.8 + 0.6 * id, 1.5, 0.1 * std::sin(id));
    f.poses[id] = pose;
    const LaserScan scan = test::simulateScan(world, pose);
    SensorData data(scan, id, 100.0 + id);
    if (id != 4 && id != 7) {
      f.grids[id] = rayTraceScan2D(scan, f.options);
      data.setLocalGrid(f.grids[id]);
    }
    const Transform odometry = Transform(0, odometryDrift * (id - 1), 0, 0, 0, 0) * pose;
    Signature node(id, 0, 0, 100.0 + id, "", odometry, Transform(), data);
    if (!previous.isNull()) {
      node.addLink(Link(id, id - 1, Link::kNeighbor, pose.inverse() * previous));
    }
    database.saveNode(node);
    previous = pose;
  }
  database.close();
  return f;
}

}  // namespace

TEST(Export, WritesTheGridOctoMapCloudAndPosesOfADatabase) {
  TempDir dir("maps_export");
  const Fixture f = makeDatabase(dir.file("map.db"));
  const ToolRun run = runExport("--json --grid " + dir.file("out/map.pgm") + " --octomap " + dir.file("map.bt") +
                                " --cloud " + dir.file("map.ply") + " --poses " + dir.file("poses.tum") + " " +
                                dir.file("map.db"));
  ASSERT_EQ(run.exitCode, 1);  // out/ does not exist: a clear failure, not a crash
  std::filesystem::create_directory(dir.file("out"));
  const ToolRun ok = runExport("--json --grid " + dir.file("out/map.pgm") + " --octomap " + dir.file("map.bt") +
                               " --cloud " + dir.file("map.ply") + " --poses " + dir.file("poses.tum") + " " +
                               dir.file("map.db"));
  ASSERT_EQ(ok.exitCode, 0) << ok.out;
  const nlohmann::json j = lastJson(ok.out);
  EXPECT_EQ(j["nodes"], 10);
  EXPECT_EQ(j["grids_stored"], 8);
  EXPECT_EQ(j["grids_regenerated"], 2);  // nodes 4 and 7, from their scans
  EXPECT_EQ(j["grids_failed"], 0);
  EXPECT_GT(j["outputs"]["octomap"]["leaves"].get<int>(), 1000);
  EXPECT_GT(j["outputs"]["cloud"]["points"].get<int>(), 100);
  for (const char* file : {"out/map.pgm", "out/map.yaml", "out/map.png", "map.bt", "map.ply", "poses.tum"}) {
    EXPECT_TRUE(std::filesystem::exists(dir.file(file))) << file;
  }
  // The exported grid is the one the library assembles from the same grids and poses.
  OccupancyGrid expected;
  for (int id = 1; id <= 10; ++id) {
    expected.addLocalGrid(id, f.grids.count(id) ? f.grids.at(id) : rayTraceScan2D(test::simulateScan(test::World2D::room(0, 0, 8, 3), f.poses.at(id)), f.options));
  }
  expected.update(f.poses);
  const GridMap want = expected.map(), got = readMapServer(dir.file("out/map.yaml"));
  ASSERT_EQ(got.data.size(), want.data.size());
  EXPECT_EQ(cv::countNonZero(got.data != want.data), 0);
  EXPECT_NEAR(got.originX, want.originX, 1e-6);
  EXPECT_NEAR(got.originY, want.originY, 1e-6);
  EXPECT_EQ(readPly(dir.file("map.ply")).size(), j["outputs"]["cloud"]["points"].get<size_t>());
  // Poses: one TUM line per node, stamp first.
  std::ifstream tum(dir.file("poses.tum"));
  double stamp, x, y, z, qx, qy, qz, qw;
  int lines = 0;
  while (tum >> stamp >> x >> y >> z >> qx >> qy >> qz >> qw) {
    ++lines;
    EXPECT_NEAR(stamp, 100.0 + lines, 1e-6);
    EXPECT_NEAR(x, f.poses.at(lines).x(), 1e-6);
  }
  EXPECT_EQ(lines, 10);
}

// The map is the graph the links make, not the odometry stored with each node: exported poses
// are the optimised ones (node 1, the oldest, fixed where its odometry put it).
TEST(Export, PosesAreTheOptimisedGraphNotTheStoredOdometry) {
  TempDir dir("maps_export_optimised");
  const Fixture f = makeDatabase(dir.file("map.db"), 0.2);
  const ToolRun ok = runExport("--json --poses " + dir.file("poses.tum") + " " + dir.file("map.db"));
  ASSERT_EQ(ok.exitCode, 0) << ok.out;
  std::ifstream tum(dir.file("poses.tum"));
  double stamp, x, y, z, qx, qy, qz, qw;
  int lines = 0;
  while (tum >> stamp >> x >> y >> z >> qx >> qy >> qz >> qw) {
    ++lines;
    EXPECT_NEAR(x, f.poses.at(lines).x(), 1e-4) << "node " << lines;
    EXPECT_NEAR(y, f.poses.at(lines).y(), 1e-4) << "node " << lines << " (odometry says "
                                                  << f.poses.at(lines).y() + 0.2 * (lines - 1) << ")";
  }
  EXPECT_EQ(lines, 10);
}

TEST(Export, RegenerateAndOtAndPcdFiles) {
  TempDir dir("maps_export2");
  makeDatabase(dir.file("map.db"));
  const ToolRun run = runExport("--json --regenerate --octomap " + dir.file("map.ot") +
                                " --cloud " + dir.file("map.pcd") + " " + dir.file("map.db"));
  ASSERT_EQ(run.exitCode, 0) << run.out;
  const nlohmann::json j = lastJson(run.out);
  EXPECT_EQ(j["grids_stored"], 0);
  EXPECT_EQ(j["grids_regenerated"], 10);
  EXPECT_EQ(readPcd(dir.file("map.pcd")).size(), j["outputs"]["cloud"]["points"].get<size_t>());
  EXPECT_GT(std::filesystem::file_size(dir.file("map.ot")), 1000u);
  // A cell size on the command line recomputes the grids at that size.
  const ToolRun coarse = runExport("--json --Grid/CellSize 0.1 --grid " + dir.file("c.pgm") + " " + dir.file("map.db"));
  ASSERT_EQ(coarse.exitCode, 0) << coarse.out;
  EXPECT_FLOAT_EQ(lastJson(coarse.out)["outputs"]["grid"]["resolution"].get<float>(), 0.1f);
  EXPECT_EQ(lastJson(coarse.out)["grids_regenerated"], 10);
}

TEST(Export, BadCommandLinesAndDatabasesFailClearly) {
  TempDir dir("maps_export3");
  EXPECT_EQ(runExport(dir.file("map.db")).exitCode, 2);                                  // nothing to export
  EXPECT_EQ(runExport("--grid " + dir.file("m.png") + " " + dir.file("map.db")).exitCode, 2);  // not .pgm
  EXPECT_EQ(runExport("--octomap " + dir.file("m.txt") + " x.db").exitCode, 2);
  EXPECT_EQ(runExport("--png-scale 0 --grid m.pgm x.db").exitCode, 2);
  EXPECT_EQ(runExport("--Grid/CellSize 0 --grid m.pgm x.db").exitCode, 2);  // parameter error
  EXPECT_EQ(runExport("--grid " + dir.file("m.pgm") + " " + dir.file("missing.db")).exitCode, 1);
  // A database whose nodes have neither grids nor sensor data.
  {
    db::Database database(dir.file("bare.db"));
    database.saveNode(Signature(1, 0, 0, 1.0, "", Transform::Identity()));
    database.close();
  }
  EXPECT_EQ(runExport("--grid " + dir.file("b.pgm") + " " + dir.file("bare.db")).exitCode, 1);
  EXPECT_FALSE(std::filesystem::exists(dir.file("b.pgm")));
  EXPECT_EQ(runExport("--help").exitCode, 0);
}
