// Structural complexity from normals (issue 5: second eigenvalue x 2 in 2D, third x 3 in 3D).
#include <gtest/gtest.h>

#include <cmath>

#include "rtabmap_core/registration/StructuralComplexity.h"

namespace rtabmap {
namespace {

Eigen::Matrix3Xf normals(std::initializer_list<Eigen::Vector3f> list) {
  Eigen::Matrix3Xf m(3, static_cast<Eigen::Index>(list.size()));
  Eigen::Index i = 0;
  for (const auto& n : list) m.col(i++) = n;
  return m;
}

TEST(StructuralComplexity, RoomIsFullCorridorIsNone2D) {
  // A rectangle seen from inside: as many normals along x as along y.
  const auto room = normals({{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}});
  EXPECT_NEAR(computeStructuralComplexity(room, true).value, 1.0, 1e-9);
  // Two parallel walls: nothing faces x.
  const auto corridor = normals({{0, 1, 0}, {0, -1, 0}, {0, 1, 0}, {0, -1, 0}});
  const StructuralComplexity c = computeStructuralComplexity(corridor, true);
  EXPECT_NEAR(c.value, 0.0, 1e-9);
  // The unconstrained direction is x.
  EXPECT_NEAR(std::abs(c.directions(0, 0)), 1.0, 1e-9);
  EXPECT_EQ(c.dimensions, 2);
  EXPECT_EQ(c.normals, 4);
}

TEST(StructuralComplexity, CornerSeenFromInsideIsConstrained) {
  // Normals (-1,0) and (0,-1): the centred PCA would call this degenerate (one spread
  // direction); the second moment sees both axes constrained.
  const auto corner = normals({{-1, 0, 0}, {0, -1, 0}, {-1, 0, 0}, {0, -1, 0}});
  EXPECT_NEAR(computeStructuralComplexity(corner, true).value, 1.0, 1e-9);
  // Mostly one wall, a little of the other: in between.
  const auto mostlyOne = normals({{-1, 0, 0}, {-1, 0, 0}, {-1, 0, 0}, {0, -1, 0}});
  EXPECT_NEAR(computeStructuralComplexity(mostlyOne, true).value, 0.5, 1e-9);
}

TEST(StructuralComplexity, ThreeD) {
  const auto box = normals({{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}});
  EXPECT_NEAR(computeStructuralComplexity(box, false).value, 1.0, 1e-9);
  // A tunnel: floor, ceiling and walls, nothing facing along it.
  const auto tunnel = normals({{0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}});
  EXPECT_NEAR(computeStructuralComplexity(tunnel, false).value, 0.0, 1e-9);
  // Non-unit and NaN normals: normalised, skipped.
  const float nan = std::nanf("");
  const auto messy = normals({{2, 0, 0}, {0, 3, 0}, {0, 0, 0.5f}, {nan, 0, 0}});
  const StructuralComplexity m = computeStructuralComplexity(messy, false);
  EXPECT_EQ(m.normals, 3);
  EXPECT_NEAR(m.value, 1.0, 1e-6);
}

TEST(StructuralComplexity, FromLaserScan) {
  cv::Mat data(1, 4, CV_32FC(5));
  const float rows[4][5] = {{1, 0, -1, 0, 0}, {0, 1, 0, -1, 0}, {-1, 0, 1, 0, 0}, {0, -1, 0, 1, 0}};
  for (int i = 0; i < 4; ++i)
    for (int c = 0; c < 5; ++c) data.ptr<float>(0)[i * 5 + c] = rows[i][c];
  const LaserScan scan(data, 4, 0, 10, LaserScan::kXYNormal);
  EXPECT_NEAR(computeStructuralComplexity(scan).value, 1.0, 1e-6);
  cv::Mat xy(1, 4, CV_32FC2, cv::Scalar(1, 1));
  EXPECT_EQ(computeStructuralComplexity(LaserScan(xy, 4, 0, 10, LaserScan::kXY)).normals, 0);
}

}  // namespace
}  // namespace rtabmap
