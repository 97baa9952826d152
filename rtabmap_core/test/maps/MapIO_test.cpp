// Map files: map_server PGM + YAML round trip, PNG preview, PLY / PCD round trips, and the
// cloud map.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <fstream>

#include "common/TestData.h"
#include "maps/MapsTestUtil.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/maps/CloudMap.h"
#include "rtabmap_core/maps/LocalGridMaker.h"
#include "rtabmap_core/maps/LocalGridStages.h"
#include "rtabmap_core/maps/MapIO.h"
#include "rtabmap_core/maps/OccupancyGrid.h"

using namespace rtabmap;

namespace {

GridMap sampleMap() {
  GridMap m;
  m.resolution = 0.05f;
  m.originX = -1.25;
  m.originY = 3.5;
  m.data = cv::Mat(7, 11, CV_8SC1, cv::Scalar(GridMap::kUnknown));
  for (int c = 0; c < 11; ++c) m.data.at<int8_t>(0, c) = GridMap::kOccupied;  // bottom row: a wall
  for (int r = 1; r < 5; ++r)
    for (int c = 2; c < 9; ++c) m.data.at<int8_t>(r, c) = GridMap::kFree;
  return m;
}

}  // namespace

TEST(MapIO, MapServerPgmAndYamlLoadBackToTheSameGrid) {
  test::TempDir dir("maps_io");
  const GridMap m = sampleMap();
  writeMapServer(m, dir.file("map.pgm"), dir.file("map.yaml"));
  std::ifstream yaml(dir.file("map.yaml"));
  const std::string text((std::istreambuf_iterator<char>(yaml)), std::istreambuf_iterator<char>());
  for (const char* key : {"image: map.pgm", "resolution: 0.05", "origin: [-1.250000, 3.500000, 0.0]", "negate: 0",
                          "occupied_thresh: 0.65", "free_thresh: 0.196"}) {
    EXPECT_NE(text.find(key), std::string::npos) << key << "\n" << text;
  }
  // The image's top row is the map's highest row.
  const cv::Mat pgm = cv::imread(dir.file("map.pgm"), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(pgm.type(), CV_8UC1);
  EXPECT_EQ(pgm.at<uchar>(6, 0), 0);    // the wall (row 0 of the map)
  EXPECT_EQ(pgm.at<uchar>(5, 3), 254);  // free
  EXPECT_EQ(pgm.at<uchar>(0, 0), 205);  // unknown
  const GridMap back = readMapServer(dir.file("map.yaml"));
  EXPECT_FLOAT_EQ(back.resolution, m.resolution);
  EXPECT_DOUBLE_EQ(back.originX, m.originX);
  EXPECT_DOUBLE_EQ(back.originY, m.originY);
  ASSERT_EQ(back.data.size(), m.data.size());
  EXPECT_EQ(cv::countNonZero(back.data != m.data), 0);
}

TEST(MapIO, AGlobalGridSurvivesTheRoundTrip) {
  const auto world = test::World2D::room(-2, -1.5, 3, 1.5);
  LocalGridOptions lo;
  lo.cellSize = 0.05f;
  lo.rangeMax = 0.0f;
  OccupancyGrid grid;
  grid.addLocalGrid(1, rayTraceScan2D(test::simulateScan(world, Transform::Identity()), lo));
  grid.addLocalGrid(2, rayTraceScan2D(test::simulateScan(world, Transform(1.0, 0.5, 1.0)), lo));
  grid.update({{1, Transform::Identity()}, {2, Transform(1.0, 0.5, 1.0)}});
  const GridMap m = grid.map();
  test::TempDir dir("maps_io2");
  writeMapServer(m, dir.file("g.pgm"), dir.file("g.yaml"));
  const GridMap back = readMapServer(dir.file("g.yaml"));
  EXPECT_NEAR(back.originX, m.originX, 1e-6);  // written to the micrometre
  EXPECT_NEAR(back.originY, m.originY, 1e-6);
  EXPECT_EQ(cv::countNonZero(back.data != m.data), 0);
  writeGridPng(m, dir.file("g.png"), 2);
  const cv::Mat png = cv::imread(dir.file("g.png"), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(png.cols, m.width() * 2);
  EXPECT_EQ(png.rows, m.height() * 2);
}

TEST(MapIO, MalformedMapFilesAreFormatErrors) {
  test::TempDir dir("maps_io_bad");
  EXPECT_THROW(readMapServer(dir.file("missing.yaml")), FormatError);
  std::ofstream(dir.file("noimage.yaml")) << "resolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
                                            "occupied_thresh: 0.65\nfree_thresh: 0.196\n";
  try {
    readMapServer(dir.file("noimage.yaml"));
    FAIL();
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("image"), std::string::npos) << e.what();
  }
  std::ofstream(dir.file("lost.yaml")) << "image: lost.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n"
                                         "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
  EXPECT_THROW(readMapServer(dir.file("lost.yaml")), FormatError);
  EXPECT_THROW(writeMapServer(GridMap(), dir.file("e.pgm"), dir.file("e.yaml")), FormatError);
  EXPECT_THROW(writeMapServer(sampleMap(), dir.file("no/such/dir/m.pgm"), dir.file("m.yaml")), FormatError);
}

TEST(MapIO, PlyAndPcdRoundTripWithAndWithoutColours) {
  test::TempDir dir("maps_clouds");
  Cloud plain, coloured;
  for (int i = 0; i < 100; ++i) {
    plain.push_back({0.1f * i, -0.2f * i, 1.5f});
    coloured.push_back({0.1f * i, 0.3f, -1.0f * i}, {uint8_t(i), uint8_t(2 * i), uint8_t(255 - i)});
  }
  for (const Cloud* c : {&plain, &coloured}) {
    writePly(*c, dir.file("c.ply"));
    writePcd(*c, dir.file("c.pcd"));
    for (const Cloud& back : {readPly(dir.file("c.ply")), readPcd(dir.file("c.pcd"))}) {
      ASSERT_EQ(back.size(), c->size());
      EXPECT_EQ(back.hasColors(), c->hasColors());
      for (size_t i = 0; i < c->size(); ++i) {
        EXPECT_EQ(back.points[i], c->points[i]);
        if (c->hasColors()) {
          EXPECT_EQ(back.colors[i], c->colors[i]);
        }
      }
    }
  }
  EXPECT_THROW(writePly(Cloud(), dir.file("empty.ply")), FormatError);
  EXPECT_THROW(writePcd(Cloud(), dir.file("empty.pcd")), FormatError);
  std::ofstream(dir.file("ascii.ply")) << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                          "property float y\nproperty float z\nend_header\n1 2 3\n";
  EXPECT_THROW(readPly(dir.file("ascii.ply")), FormatError);
}

TEST(CloudMap, AssemblesVoxelFilteredColouredPointsAndFollowsMovedNodes) {
  LocalGridOptions lo;
  lo.depthDecimation = 2;
  const LocalGridResult r =
      createLocalGrid(test::DepthScene::floorBoxTable().render(320, 240, 262.5, 1.0, 30.0 * M_PI / 180.0), lo);
  ASSERT_TRUE(r.success) << r.why;
  CloudMap map;
  ASSERT_TRUE(map.addLocalGrid(1, r.grid));
  ASSERT_TRUE(map.addLocalGrid(2, r.grid));
  CloudMapUpdateSummary s = map.update({{1, Transform::Identity()}, {2, Transform::Identity()}});
  EXPECT_EQ(s.nodesAdded, 2);
  const size_t n = r.grid.ground.total() + r.grid.obstacles.total();
  EXPECT_EQ(map.rawPoints(), 2 * n);
  EXPECT_LE(map.cloud().size(), n + n / 20);  // two identical nodes: the voxel filter merges them
  EXPECT_TRUE(map.cloud().hasColors());
  s = map.update({{1, Transform::Identity()}, {2, Transform(0, 10, 0)}});
  EXPECT_EQ(s.nodesMoved, 1);
  EXPECT_GE(map.cloud().size(), 2 * n - n / 20);
  int far = 0;
  for (const auto& p : map.cloud().points) far += p.y > 8.0f;
  EXPECT_GT(far, static_cast<int>(n / 2));
  std::string why;
  EXPECT_FALSE(map.addLocalGrid(3, LocalGrid(), &why));
  EXPECT_NE(why.find("no obstacle or ground"), std::string::npos);
}
