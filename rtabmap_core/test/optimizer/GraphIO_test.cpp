// g2o and TORO files: round trips and every kind of bad input, each error naming the line.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "SyntheticGraph.h"
#include "common/TestData.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/optimizer/Chi2.h"
#include "rtabmap_core/optimizer/GraphIO.h"

namespace rtabmap {
namespace {

using graph::PoseGraphFile;

double maxDifference(const Transform& a, const Transform& b) {
  return (a.toMatrix4d() - b.toMatrix4d()).cwiseAbs().maxCoeff();
}

// Same poses and links (transforms, information, types) up to `tolerance`.
void expectSameGraph(const std::map<int, Transform>& poses, const std::multimap<int, Link>& links,
                     const PoseGraphFile& file, double tolerance) {
  ASSERT_EQ(file.poses.size(), poses.size());
  for (const auto& [id, pose] : poses) {
    ASSERT_TRUE(file.poses.count(id)) << id;
    EXPECT_LT(maxDifference(file.poses.at(id), pose), tolerance) << id;
  }
  ASSERT_EQ(file.links.size(), links.size());
  auto it = file.links.begin();
  for (const auto& [key, link] : links) {
    EXPECT_EQ(it->first, key);
    EXPECT_EQ(it->second.from(), link.from());
    EXPECT_EQ(it->second.to(), link.to());
    EXPECT_EQ(it->second.type(), link.type());
    EXPECT_LT(maxDifference(it->second.transform(), link.transform()), tolerance);
    EXPECT_LT((it->second.infMatrix() - link.infMatrix()).cwiseAbs().maxCoeff(),
              tolerance * link.infMatrix().cwiseAbs().maxCoeff());
    ++it;
  }
}

// The synthetic graphs have Neighbor links between consecutive ids and GlobalClosure ones
// otherwise, which is what the readers assign.
test::SyntheticGraph graphFor(bool is2D) {
  test::NoiseModel noise;
  auto g = test::makeSquareLoops(2, 4, is2D, noise, 101, 0, 0.5);
  // A full information matrix with cross terms, so ordering mistakes show.
  for (auto& [k, link] : g.links) {
    (void)k;
    Link::InfMatrix info = link.infMatrix();
    info(0, 1) = info(1, 0) = 3.0;
    info(0, 5) = info(5, 0) = 2.0;
    if (!is2D) info(2, 4) = info(4, 2) = 1.5;
    link.setInfMatrix(info);
  }
  return g;
}

TEST(GraphIO, G2oRoundTripsExactly) {
  test::TempDir dir;
  for (bool is2D : {true, false}) {
    const auto g = graphFor(is2D);
    const std::string path = dir.file(is2D ? "se2.g2o" : "se3.g2o");
    EXPECT_EQ(graph::writeG2o(path, g.truth, g.links, is2D), 0);
    const PoseGraphFile file = graph::readG2o(path);
    EXPECT_EQ(file.is2D, is2D);
    EXPECT_TRUE(file.hasVertices);
    if (is2D) {
      // z, roll and pitch do not exist in 2D: unused information becomes 1.
      auto links = g.links;
      for (auto& [k, l] : links) {
        (void)k;
        l.setInfMatrix(graph::linkInformationFromSE2(graph::informationSE2(l.infMatrix())));
      }
      expectSameGraph(g.truth, links, file, 1e-12);
    } else {
      expectSameGraph(g.truth, g.links, file, 1e-12);
    }
  }
}

TEST(GraphIO, ToroRoundTrips) {
  test::TempDir dir;
  for (bool is2D : {true, false}) {
    const auto g = graphFor(is2D);
    const std::string path = dir.file(is2D ? "se2.graph" : "se3.toro");
    EXPECT_EQ(graph::writeGraph(path, g.truth, g.links, is2D), 0);
    const PoseGraphFile file = graph::readGraph(path);
    EXPECT_EQ(file.is2D, is2D);
    auto links = g.links;
    if (is2D) {
      for (auto& [k, l] : links) {
        (void)k;
        l.setInfMatrix(graph::linkInformationFromSE2(graph::informationSE2(l.infMatrix())));
      }
    }
    // Euler angles in the file: a few ulps of conversion.
    expectSameGraph(g.truth, links, file, 1e-12);
  }
}

TEST(GraphIO, ToroTwoDimensionalInformationOrder) {
  // EDGE2 i j x y theta  Ixx Ixy Iyy Itt Ixt Iyt
  std::istringstream text("VERTEX2 1 0 0 0\nVERTEX2 2 1 0 0\nEDGE2 1 2 1 0 0  10 1 20 30 2 3\n");
  const PoseGraphFile file = graph::parseToro(text, "order.graph");
  const Eigen::Matrix3d info = graph::informationSE2(file.links.begin()->second.infMatrix());
  EXPECT_EQ(info(0, 0), 10);
  EXPECT_EQ(info(0, 1), 1);
  EXPECT_EQ(info(1, 1), 20);
  EXPECT_EQ(info(2, 2), 30);
  EXPECT_EQ(info(0, 2), 2);
  EXPECT_EQ(info(1, 2), 3);
}

TEST(GraphIO, EdgesOnlyFilesGiveNullPoses) {
  std::istringstream text(
      "# M3500-like: edges only\n"
      "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n"
      "\n"
      "EDGE_SE2 1 2 1 0 0 1 0 0 1 0 1   # odometry\n"
      "EDGE_SE2 2 0 -2 0 0 1 0 0 1 0 1\n");
  const PoseGraphFile file = graph::parseG2o(text, "edges.g2o");
  EXPECT_FALSE(file.hasVertices);
  EXPECT_TRUE(file.is2D);
  ASSERT_EQ(file.poses.size(), 3u);
  for (const auto& [id, pose] : file.poses) EXPECT_TRUE(pose.isNull()) << id;
  ASSERT_EQ(file.links.size(), 3u);
  auto it = file.links.begin();
  EXPECT_EQ(it->second.type(), Link::kNeighbor);
  ++it;
  ++it;
  EXPECT_EQ(it->second.type(), Link::kGlobalClosure);  // 2 -> 0
}

TEST(GraphIO, FixRecordsAreKept) {
  std::istringstream text("VERTEX_SE2 4 0 0 0\nVERTEX_SE2 5 1 0 0\nFIX 5\nEDGE_SE2 4 5 1 0 0 1 0 0 1 0 1\n");
  const PoseGraphFile file = graph::parseG2o(text, "fix.g2o");
  ASSERT_EQ(file.fixedIds.size(), 1u);
  EXPECT_EQ(file.fixedIds[0], 5);
}

// Parses `text` as g2o (or TORO) and returns the error message ("" if it parsed).
std::string errorOf(const std::string& text, bool toro = false) {
  std::istringstream in(text);
  try {
    if (toro) {
      graph::parseToro(in, "bad.graph");
    } else {
      graph::parseG2o(in, "bad.g2o");
    }
  } catch (const FormatError& e) {
    return e.what();
  }
  return "";
}

void expectError(const std::string& text, const std::string& location, const std::string& what,
                 bool toro = false) {
  const std::string message = errorOf(text, toro);
  EXPECT_EQ(message.rfind(location, 0), 0u) << "message: " << message;
  EXPECT_NE(message.find(what), std::string::npos) << "message: " << message;
}

const char* kGoodSe2 = "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n";

TEST(GraphIO, BadInputErrorsNameTheLine) {
  EXPECT_EQ(errorOf(std::string(kGoodSe2) + "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n"), "");
  // Unknown tag.
  expectError(std::string(kGoodSe2) + "VERTEX_XYZ 3 1 2 3\n", "bad.g2o:3:", "unknown tag 'VERTEX_XYZ'");
  // NaN and infinity.
  expectError(std::string(kGoodSe2) + "EDGE_SE2 0 1 nan 0 0 1 0 0 1 0 1\n", "bad.g2o:3:", "NaN or infinite");
  expectError("VERTEX_SE2 0 0 inf 0\n", "bad.g2o:1:", "NaN or infinite");
  // A link to a missing node.
  expectError(std::string(kGoodSe2) + "\n# comment\nEDGE_SE2 0 7 1 0 0 1 0 0 1 0 1\n", "bad.g2o:5:",
              "node 7, which has no vertex");
  // Non positive-definite information (2D and 3D).
  expectError(std::string(kGoodSe2) + "EDGE_SE2 0 1 1 0 0 1 0 0 -1 0 1\n", "bad.g2o:3:",
              "not positive definite");
  expectError("VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_SE3:QUAT 1 1 0 0 0 0 0 1\n"
              "EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1  1 0 0 0 0 0  1 0 0 0 0  1 0 0 0  1 0 0  1 5  1\n",
              "bad.g2o:3:", "not positive definite");
  // Empty graph: the error names the line count.
  expectError("", "bad.g2o:0:", "empty graph");
  expectError("# nothing\n\n", "bad.g2o:2:", "empty graph");
  // Wrong number of values, not a number, not an id.
  expectError("VERTEX_SE2 0 0 0\n", "bad.g2o:1:", "needs 4 values");
  expectError("VERTEX_SE2 0 0 x 0\n", "bad.g2o:1:", "'x' is not a number");
  expectError("VERTEX_SE2 0.5 0 0 0\n", "bad.g2o:1:", "not a node id");
  // Duplicate vertex, self edge, zero quaternion, 2D and 3D mixed.
  expectError(std::string(kGoodSe2) + "VERTEX_SE2 1 2 0 0\n", "bad.g2o:3:", "given twice");
  expectError(std::string(kGoodSe2) + "EDGE_SE2 1 1 1 0 0 1 0 0 1 0 1\n", "bad.g2o:3:", "to itself");
  expectError("VERTEX_SE3:QUAT 0 0 0 0 0 0 0 0\n", "bad.g2o:1:", "quaternion is zero");
  expectError(std::string(kGoodSe2) + "VERTEX_SE3:QUAT 2 0 0 0 0 0 0 1\n", "bad.g2o:3:",
              "cannot be mixed");
  // TORO too.
  expectError("VERTEX2 0 0 0 0\nVERTEX2 1 1 0 nan\n", "bad.graph:2:", "NaN", true);
  expectError("VERTEX2 0 0 0 0\nEDGE2 0 3 1 0 0 1 0 1 1 0 0\n", "bad.graph:2:", "no vertex", true);
  expectError("VERTEX2 0 0 0 0\nFOO 1\n", "bad.graph:2:", "unknown tag 'FOO'", true);
}

TEST(GraphIO, FilesThatCannotBeOpenedOrGuessed) {
  EXPECT_THROW(graph::readG2o("/nonexistent/dir/graph.g2o"), FormatError);
  EXPECT_THROW(graph::readGraph("/tmp/graph.txt"), FormatError);
  EXPECT_EQ(graph::graphFormatFromPath("a/b.G2O"), graph::GraphFormat::kG2o);
  EXPECT_EQ(graph::graphFormatFromPath("a.b/c.graph"), graph::GraphFormat::kToro);
  test::TempDir dir;
  EXPECT_THROW(graph::writeG2o(dir.file("missing/dir/out.g2o"), {}, {}, true), FormatError);
}

TEST(GraphIO, WritersSkipPriorsAndGravity) {
  std::map<int, Transform> poses{{1, Transform(0, 0, 0)}, {2, Transform(1, 0, 0)}};
  std::multimap<int, Link> links;
  links.emplace(1, Link(1, 2, Link::kNeighbor, Transform(1, 0, 0)));
  links.emplace(1, Link(1, 1, Link::kPosePrior, Transform(0, 0, 0)));
  links.emplace(2, Link(2, 2, Link::kGravity, Transform(0, 0, 0)));
  std::ostringstream out;
  EXPECT_EQ(graph::formatG2o(out, poses, links, true), 2);
  EXPECT_EQ(graph::formatToro(out, poses, links, false), 2);
}

TEST(GraphIO, ReadsTheReferenceGraphs) {
  RTABMAP_REQUIRE_DATA(intel, "posegraphs/intel.g2o");
  RTABMAP_REQUIRE_DATA(manhattan, "posegraphs/manhattan.g2o");
  RTABMAP_REQUIRE_DATA(kitti, "posegraphs/kitti_00.g2o");
  RTABMAP_REQUIRE_DATA(garage, "posegraphs/parking-garage.g2o");
  const PoseGraphFile a = graph::readG2o(intel);
  EXPECT_TRUE(a.is2D);
  EXPECT_TRUE(a.hasVertices);
  EXPECT_EQ(a.poses.size(), 1728u);
  EXPECT_EQ(a.links.size(), 2512u);
  const PoseGraphFile b = graph::readG2o(manhattan);
  EXPECT_FALSE(b.hasVertices);
  EXPECT_EQ(b.poses.size(), 3500u);
  EXPECT_EQ(b.links.size(), 5453u);
  const PoseGraphFile c = graph::readG2o(kitti);  // has blank lines
  EXPECT_EQ(c.poses.size(), 4541u);
  const PoseGraphFile d = graph::readG2o(garage);
  EXPECT_FALSE(d.is2D);
  EXPECT_EQ(d.poses.size(), 1661u);
  EXPECT_EQ(d.links.size(), 6275u);
}

}  // namespace
}  // namespace rtabmap
