#include "rtabmap_core/geometry/LaserScan.h"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <cmath>
#include <limits>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/geometry/SensorData.h"

using rtabmap::FormatError;
using rtabmap::LaserScan;
using rtabmap::SensorData;
using rtabmap::Transform;

namespace {
// cv::Scalar holds 4 values: fill wider matrices through a one-channel view.
cv::Mat filled(int n, int channels, float value) {
  cv::Mat m(1, n, CV_32FC(channels));
  m.reshape(1).setTo(value);
  return m;
}
}  // namespace

TEST(LaserScan, FormatTable) {
  struct Row {
    LaserScan::Format f;
    int channels;
    bool is2d, normals, intensity, rgb;
    const char* name;
  };
  const Row rows[] = {
      {LaserScan::kUnknown, 0, false, false, false, false, "Unknown"},
      {LaserScan::kXY, 2, true, false, false, false, "XY"},
      {LaserScan::kXYI, 3, true, false, true, false, "XYI"},
      {LaserScan::kXYNormal, 5, true, true, false, false, "XYNormal"},
      {LaserScan::kXYINormal, 6, true, true, true, false, "XYINormal"},
      {LaserScan::kXYZ, 3, false, false, false, false, "XYZ"},
      {LaserScan::kXYZI, 4, false, false, true, false, "XYZI"},
      {LaserScan::kXYZRGB, 4, false, false, false, true, "XYZRGB"},
      {LaserScan::kXYZNormal, 6, false, true, false, false, "XYZNormal"},
      {LaserScan::kXYZINormal, 7, false, true, true, false, "XYZINormal"},
      {LaserScan::kXYZRGBNormal, 7, false, true, false, true, "XYZRGBNormal"},
  };
  for (const Row& r : rows) {
    EXPECT_EQ(LaserScan::channels(r.f), r.channels) << r.name;
    EXPECT_EQ(LaserScan::is2d(r.f), r.is2d) << r.name;
    EXPECT_EQ(LaserScan::hasNormals(r.f), r.normals) << r.name;
    EXPECT_EQ(LaserScan::hasIntensity(r.f), r.intensity) << r.name;
    EXPECT_EQ(LaserScan::hasRGB(r.f), r.rgb) << r.name;
    EXPECT_EQ(LaserScan::formatName(r.f), r.name);
    if (r.channels > 0) {
      const LaserScan s(filled(10, r.channels, 1.0f), 10, 0, 0, r.f);
      EXPECT_EQ(s.size(), 10);
      EXPECT_EQ(s.format(), r.f);
      EXPECT_EQ(s.is2d(), r.is2d);
      // Wrong channel count is refused.
      EXPECT_THROW(LaserScan(filled(10, r.channels + 1, 1.0f), 10, 0, 0, r.f),
                   FormatError);
    }
  }
}

TEST(LaserScan, ConstructorChecks) {
  const LaserScan empty;
  EXPECT_TRUE(empty.empty());
  EXPECT_TRUE(empty.isEmpty());
  EXPECT_EQ(empty.size(), 0);
  EXPECT_EQ(empty.format(), LaserScan::kUnknown);
  EXPECT_TRUE(empty.localTransform().isIdentity());
  EXPECT_THROW(LaserScan(cv::Mat(1, 5, CV_64FC2, cv::Scalar::all(0)), 5, 0, 0, LaserScan::kXY), FormatError);
  EXPECT_THROW(LaserScan(cv::Mat(1, 5, CV_32FC2, cv::Scalar::all(0)), 5, 0, 0, LaserScan::kUnknown), FormatError);
  EXPECT_THROW(LaserScan(cv::Mat(3, 5, CV_32FC2, cv::Scalar::all(0)), 5, 0, 0, LaserScan::kXY), FormatError);
  // Nx1 is accepted and stored 1xN.
  const LaserScan column(cv::Mat(7, 1, CV_32FC3, cv::Scalar(1, 2, 3)), 7, 0.1, 30, LaserScan::kXYZ,
                         Transform(0, 0, 1, 0, 0, 0));
  EXPECT_EQ(column.data().rows, 1);
  EXPECT_EQ(column.size(), 7);
  EXPECT_EQ(column.maxPoints(), 7);
  EXPECT_DOUBLE_EQ(column.rangeMin(), 0.1);
  EXPECT_DOUBLE_EQ(column.rangeMax(), 30);
  EXPECT_EQ(column.point(3), Eigen::Vector3f(1, 2, 3));
  EXPECT_THROW(column.point(7), std::out_of_range);
  EXPECT_THROW(column.point(-1), std::out_of_range);
  EXPECT_DOUBLE_EQ(column.localTransform().z(), 1.0);
}

TEST(LaserScan, FromRangesDropsInvalidBeams) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  // 8 beams over 180 degrees, 45 degrees apart.
  const std::vector<float> ranges = {1.0f, nan, 2.0f, inf, 0.05f, 50.0f, 3.0f, -inf};
  const LaserScan s = LaserScan::fromRanges(ranges, -M_PI / 2, M_PI / 4, 0.1, 30.0);
  EXPECT_EQ(s.format(), LaserScan::kXY);
  EXPECT_EQ(s.maxPoints(), 8);
  ASSERT_EQ(s.size(), 3);  // beams 0, 2, 6
  EXPECT_NEAR(s.point(0).x(), 0.0, 1e-6);
  EXPECT_NEAR(s.point(0).y(), -1.0, 1e-6);
  EXPECT_NEAR(s.point(1).x(), 2.0, 1e-6);  // beam 2 at angle 0
  EXPECT_NEAR(s.point(1).y(), 0.0, 1e-6);
  const double a6 = -M_PI / 2 + 6 * M_PI / 4;
  EXPECT_NEAR(s.point(2).x(), 3 * std::cos(a6), 1e-6);
  EXPECT_NEAR(s.point(2).y(), 3 * std::sin(a6), 1e-6);
  EXPECT_EQ(s.point(2).z(), 0.0f);
  EXPECT_DOUBLE_EQ(s.rangeMin(), 0.1);
  EXPECT_DOUBLE_EQ(s.rangeMax(), 30.0);

  const std::vector<float> intensities = {10, 11, 12, 13, 14, 15, 16, 17};
  const LaserScan si = LaserScan::fromRanges(ranges, -M_PI / 2, M_PI / 4, 0.1, 30.0,
                                             Transform(0.2, 0, 0.3, 0, 0, 0), intensities);
  EXPECT_EQ(si.format(), LaserScan::kXYI);
  ASSERT_EQ(si.size(), 3);
  EXPECT_EQ(si.data().at<cv::Vec3f>(0, 0)[2], 10.0f);
  EXPECT_EQ(si.data().at<cv::Vec3f>(0, 1)[2], 12.0f);
  EXPECT_EQ(si.data().at<cv::Vec3f>(0, 2)[2], 16.0f);
  EXPECT_DOUBLE_EQ(si.localTransform().x(), 0.2);
  EXPECT_THROW(LaserScan::fromRanges(ranges, 0, 0.1, 0, 10, Transform::Identity(), {1, 2}), FormatError);

  // All beams invalid: empty, but a full scan still had 3 beams.
  const LaserScan none = LaserScan::fromRanges({nan, nan, inf}, 0, 0.1, 0.1, 10);
  EXPECT_TRUE(none.empty());
  EXPECT_EQ(none.maxPoints(), 3);
}

TEST(LaserScan, TransformedToBaseRotatesPointsAndNormalsNotIntensity) {
  // XYZINormal: x y z i nx ny nz
  cv::Mat data(1, 2, CV_32FC(7));
  float* p = data.ptr<float>(0);
  const float pts[14] = {1, 0, 0, 42, 1, 0, 0,   //
                         0, 2, 1, 7, 0, 0, 1};
  std::copy(pts, pts + 14, p);
  const Transform local(0.5, 0, 1.0, 0, 0, M_PI / 2);  // 90 deg yaw, raised 1 m
  const LaserScan s(data, 2, 0, 0, LaserScan::kXYZINormal, local);
  const LaserScan b = s.transformedToBase();
  EXPECT_TRUE(b.localTransform().isIdentity());
  EXPECT_EQ(b.format(), LaserScan::kXYZINormal);
  const float* q = b.data().ptr<float>(0);
  // Point (1,0,0) -> yaw 90 -> (0,1,0) + (0.5,0,1)
  EXPECT_NEAR(q[0], 0.5, 1e-6);
  EXPECT_NEAR(q[1], 1.0, 1e-6);
  EXPECT_NEAR(q[2], 1.0, 1e-6);
  EXPECT_EQ(q[3], 42.0f);       // intensity untouched
  EXPECT_NEAR(q[4], 0.0, 1e-6);  // normal (1,0,0) rotated, not translated
  EXPECT_NEAR(q[5], 1.0, 1e-6);
  EXPECT_NEAR(q[6], 0.0, 1e-6);
  EXPECT_NEAR(q[7], -2 + 0.5, 1e-6);
  EXPECT_NEAR(q[8], 0.0, 1e-6);
  EXPECT_NEAR(q[9], 2.0, 1e-6);
  EXPECT_EQ(q[10], 7.0f);
  EXPECT_NEAR(q[13], 1.0, 1e-6);
  // The original is untouched.
  EXPECT_EQ(s.data().ptr<float>(0)[0], 1.0f);

  // Check against Transform on random points for XYZNormal.
  cv::Mat xyzn(1, 50, CV_32FC(6));
  cv::Mat flat = xyzn.reshape(1);
  cv::randu(flat, cv::Scalar::all(-5), cv::Scalar::all(5));
  const Transform t(1, -2, 0.3, 0.2, -0.1, 0.7);
  const LaserScan s2 = LaserScan(xyzn, 50, 0, 0, LaserScan::kXYZNormal, t).transformedToBase();
  for (int i = 0; i < 50; ++i) {
    const float* a = xyzn.ptr<float>(0) + 6 * i;
    const float* c = s2.data().ptr<float>(0) + 6 * i;
    const Eigen::Vector3d e = t * Eigen::Vector3d(a[0], a[1], a[2]);
    const Eigen::Vector3d n = t.rotationMatrix() * Eigen::Vector3d(a[3], a[4], a[5]);
    EXPECT_NEAR(c[0], e.x(), 1e-4);
    EXPECT_NEAR(c[1], e.y(), 1e-4);
    EXPECT_NEAR(c[2], e.z(), 1e-4);
    EXPECT_NEAR(c[3], n.x(), 1e-4);
    EXPECT_NEAR(c[4], n.y(), 1e-4);
    EXPECT_NEAR(c[5], n.z(), 1e-4);
  }

  // 2D scan: stays 2D, planar rotation + translation.
  const LaserScan s2d = LaserScan::fromRanges({1.0f}, 0.0, 0.1, 0, 10, Transform(0.1, 0.2, 0.3, 0, 0, M_PI));
  const LaserScan b2d = s2d.transformedToBase();
  EXPECT_EQ(b2d.format(), LaserScan::kXY);
  EXPECT_NEAR(b2d.point(0).x(), -0.9, 1e-6);
  EXPECT_NEAR(b2d.point(0).y(), 0.2, 1e-6);
  EXPECT_EQ(b2d.point(0).z(), 0.0f);
}

TEST(LaserScan, Filtered) {
  // 100 points along x at 0.1 .. 10.0 m, with intensity = index.
  cv::Mat data(1, 100, CV_32FC4);
  for (int i = 0; i < 100; ++i) data.at<cv::Vec4f>(0, i) = cv::Vec4f(0.1f * (i + 1), 0, 0, float(i));
  const LaserScan s(data, 200, 0.0, 20.0, LaserScan::kXYZI);

  const LaserScan r = s.filtered(1.0, 5.0);
  // 1.0 .. 5.0 inclusive: i+1 in [10, 50] -> 41 points
  EXPECT_EQ(r.size(), 41);
  for (int i = 0; i < r.size(); ++i) {
    EXPECT_GE(r.point(i).norm(), 1.0f - 1e-5);
    EXPECT_LE(r.point(i).norm(), 5.0f + 1e-5);
  }
  EXPECT_DOUBLE_EQ(r.rangeMin(), 1.0);
  EXPECT_DOUBLE_EQ(r.rangeMax(), 5.0);
  EXPECT_EQ(r.maxPoints(), 200);  // no downsampling

  const LaserScan all = s.filtered(0, 0);
  EXPECT_EQ(all.size(), 100);
  EXPECT_DOUBLE_EQ(all.rangeMax(), 20.0);

  const LaserScan d = s.filtered(0, 0, 10);
  ASSERT_EQ(d.size(), 10);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(d.data().at<cv::Vec4f>(0, i)[3], float(i * 10));  // uniform
  EXPECT_EQ(d.maxPoints(), 20);  // scaled like the points
  EXPECT_EQ(d.format(), LaserScan::kXYZI);

  const LaserScan both = s.filtered(5.05, 0, 7);
  EXPECT_EQ(both.size(), 7);
  for (int i = 0; i < both.size(); ++i) EXPECT_GE(both.point(i).x(), 5.05f);

  // 2D ranges ignore nothing but x, y; NaN points are dropped.
  cv::Mat xy(1, 3, CV_32FC2);
  xy.at<cv::Vec2f>(0, 0) = cv::Vec2f(3, 4);
  xy.at<cv::Vec2f>(0, 1) = cv::Vec2f(std::nanf(""), 0);
  xy.at<cv::Vec2f>(0, 2) = cv::Vec2f(0.1f, 0);
  const LaserScan f2 = LaserScan(xy, 3, 0, 0, LaserScan::kXY).filtered(0.5, 5.0);
  ASSERT_EQ(f2.size(), 1);
  EXPECT_EQ(f2.point(0).x(), 3.0f);
  EXPECT_TRUE(LaserScan(xy, 3, 0, 0, LaserScan::kXY).filtered(100, 0).empty());
  EXPECT_TRUE(LaserScan().filtered(1, 2, 3).empty());
}

// The beam geometry of a planar scan survives fromRanges -> toRanges (no-return beams come
// back as +Inf), compression through SensorData, and is dropped in the base frame.
TEST(LaserScan, BeamGeometryRoundTrip) {
  const double angleMin = -M_PI * 3.0 / 4.0;
  const double inc = (M_PI * 1.5) / 682.0;  // URG-04LX: 683 beams over 270 degrees
  std::vector<float> ranges(683);
  for (size_t i = 0; i < ranges.size(); ++i) ranges[i] = 0.5f + 0.004f * static_cast<float>(i);
  ranges[0] = std::numeric_limits<float>::quiet_NaN();        // no return
  ranges[100] = std::numeric_limits<float>::infinity();       // no return
  ranges[682] = 40.0f;                                         // beyond rangeMax: dropped
  const LaserScan scan = LaserScan::fromRanges(ranges, angleMin, inc, 0.02, 5.6);
  ASSERT_TRUE(scan.hasBeamGeometry());
  EXPECT_DOUBLE_EQ(scan.angleMin(), angleMin);
  EXPECT_NEAR(scan.angleMax(), angleMin + inc * 682, 1e-12);
  EXPECT_EQ(scan.size(), 680);

  const std::vector<float> back = scan.toRanges();
  ASSERT_EQ(back.size(), ranges.size());
  for (size_t i = 0; i < back.size(); ++i) {
    if (i == 0 || i == 100 || i == 682) {
      EXPECT_TRUE(std::isinf(back[i])) << "beam " << i;
    } else {
      EXPECT_NEAR(back[i], ranges[i], 1e-5) << "beam " << i;
    }
  }

  SensorData data(scan, 1, 0.0);
  data.compress();
  data.clearRaw();
  data.uncompress();
  EXPECT_EQ(data.laserScanRaw().angleIncrement(), inc);
  EXPECT_EQ(data.laserScanRaw().toRanges().size(), ranges.size());

  EXPECT_FALSE(scan.transformedToBase().hasBeamGeometry());
  EXPECT_TRUE(LaserScan().toRanges().empty());
  EXPECT_THROW(LaserScan().setBeamGeometry(1.0, 0.0, 0.1), FormatError);
}

// Beam indices unwrap whole turns: a full 360-degree scan crossing +-pi, and a geometry given
// one turn away (angle_min 2 pi + 0.3, -2 pi - 1), come back beam for beam. Corrupt angles are refused
// (fuzzing found toRanges stepping for ever on angles near 1e30).
TEST(LaserScan, BeamIndicesUnwrapWholeTurns) {
  const std::vector<std::pair<double, int>> cases = {{-0.2, 360}, {2.0 * M_PI + 0.3, 180}, {-2.0 * M_PI - 1.0, 360}};
  for (const auto& [angleMin, n] : cases) {
    const double inc = 2.0 * M_PI / 360;
    std::vector<float> ranges(n);
    for (int i = 0; i < n; ++i) ranges[i] = 1.0f + 0.01f * static_cast<float>(i);
    const LaserScan scan = LaserScan::fromRanges(ranges, angleMin, inc, 0.1, 10.0);
    const std::vector<float> back = scan.toRanges();
    ASSERT_EQ(back.size(), ranges.size()) << angleMin;
    for (int i = 0; i < n; ++i) EXPECT_NEAR(back[i], ranges[i], 1e-4) << "angle_min " << angleMin << " beam " << i;
  }
  EXPECT_THROW(LaserScan().setBeamGeometry(1e30, 1e30 + 1.0, 0.01), FormatError);
  EXPECT_THROW(LaserScan().setBeamGeometry(-20.0, 0.0, 0.01), FormatError);
}
