// Sparse stereo: disparities of keypoints between rectified views give their depth.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <cmath>

#include "common/TestData.h"
#include "odometry/SyntheticRoom.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/features/FeatureDetector.h"
#include "rtabmap_core/features/StereoCorrespondences.h"

namespace rtabmap {
namespace {

using test::SyntheticRoom;

const Transform kView(0.5, -0.3, 1.2, 0.0, 0.05, 0.4);

// Fraction of keypoints whose stereo depth is within 3% of the rendered depth.
double accurateFraction(const StereoOptions& options, int* matched) {
  SyntheticRoom room;
  const StereoCameraModel model = SyntheticRoom::stereoCamera();
  const SensorData data = room.stereo(kView, model);
  cv::Mat grey, depth;
  room.render(kView * model.localTransform(), model.left(), grey, &depth);
  auto detector = FeatureDetector::create({}, FeatureGroup::kVis);
  const std::vector<cv::KeyPoint> keypoints = detector->detect(data.imageRaw());
  std::vector<cv::Point2f> points;
  cv::KeyPoint::convert(keypoints, points);
  const std::vector<float> d = computeStereoDisparities(data.imageRaw(), data.depthOrRightRaw(), points, options);
  int good = 0;
  *matched = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (d[i] <= 0.0f) continue;
    ++*matched;
    const double z = model.computeDepth(d[i]);
    const double truth = depth.at<float>(static_cast<int>(std::lround(points[i].y)), static_cast<int>(std::lround(points[i].x)));
    good += std::fabs(z - truth) < 0.03 * truth ? 1 : 0;
  }
  return *matched > 0 ? static_cast<double>(good) / *matched : 0.0;
}

TEST(StereoCorrespondences, OpticalFlowRecoversDepth) {
  int matched = 0;
  EXPECT_GT(accurateFraction(StereoOptions(), &matched), 0.85);
  EXPECT_GT(matched, 100);
}

TEST(StereoCorrespondences, BlockMatchingRecoversDepth) {
  StereoOptions o;
  o.opticalFlow = false;
  o.winWidth = 9;
  o.winHeight = 9;
  o.maxDisparity = 64;
  int matched = 0;
  EXPECT_GT(accurateFraction(o, &matched), 0.8);
  EXPECT_GT(matched, 100);
}

TEST(StereoCorrespondences, RejectsMatchesOffTheRow) {
  SyntheticRoom room;
  const StereoCameraModel model = SyntheticRoom::stereoCamera();
  const SensorData data = room.stereo(kView, model);
  // Shift the right image down 4 pixels: the pair is no longer rectified.
  cv::Mat shifted;
  const cv::Mat M = (cv::Mat_<double>(2, 3) << 1, 0, 0, 0, 1, 4);
  cv::warpAffine(data.depthOrRightRaw(), shifted, M, data.depthOrRightRaw().size());
  auto detector = FeatureDetector::create({}, FeatureGroup::kVis);
  std::vector<cv::Point2f> points;
  cv::KeyPoint::convert(detector->detect(data.imageRaw()), points);
  const std::vector<float> good = computeStereoDisparities(data.imageRaw(), data.depthOrRightRaw(), points, StereoOptions());
  const std::vector<float> bad = computeStereoDisparities(data.imageRaw(), shifted, points, StereoOptions());
  const auto count = [](const std::vector<float>& d) { return std::count_if(d.begin(), d.end(), [](float v) { return v > 0; }); };
  EXPECT_LT(count(bad), count(good) / 5);
}

// Real rectified pairs (EuRoC V1_01, an indoor room with many straight edges): the optical flow
// along the row matches most corners and agrees with block matching. OpenCV's 2D tracker with
// the same 15x3 window drifted off the row for 85% of them (a window 3 pixels high does not
// constrain a vertical shift).
TEST(StereoCorrespondences, OpticalFlowMatchesMostCornersOfARealPair) {
  RTABMAP_REQUIRE_DATA(path, "euroc_v1_01_micro");
  std::unique_ptr<DatasetReader> reader = openDatasetReader("euroc", path);
  DatasetRecord rec;
  StereoOptions blocks;
  blocks.opticalFlow = false;
  int points = 0, matched = 0, both = 0, agree = 0, frames = 0;
  while (frames < 3 && reader->next(rec)) {
    if (rec.kind != DatasetRecord::Kind::kFrame) continue;
    ++frames;
    const cv::Mat left = rec.data.imageRaw(), right = rec.data.depthOrRightRaw();
    ASSERT_EQ(left.type(), CV_8UC1);
    std::vector<cv::Point2f> corners;
    cv::goodFeaturesToTrack(left, corners, 500, 0.01, 7);
    const std::vector<float> flow = computeStereoDisparities(left, right, corners, StereoOptions());
    const std::vector<float> block = computeStereoDisparities(left, right, corners, blocks);
    for (size_t i = 0; i < corners.size(); ++i) {
      ++points;
      matched += flow[i] > 0.0f;
      if (flow[i] > 0.0f && block[i] > 0.0f) {
        ++both;
        agree += std::fabs(flow[i] - block[i]) < 0.5f;
      }
    }
  }
  ASSERT_EQ(frames, 3);
  EXPECT_GT(matched, points * 6 / 10) << matched << " of " << points << " corners matched";
  EXPECT_GT(agree, both * 3 / 4) << agree << " of " << both << " within 0.5 px of block matching";
}

TEST(StereoCorrespondences, FeaturesOfAStereoFrameHave3D) {
  SyntheticRoom room;
  const StereoCameraModel model = SyntheticRoom::stereoCamera();
  const SensorData data = room.stereo(kView, model);
  FeatureExtractionInfo info;
  const ImageFeatures f = FeatureDetector::create({}, FeatureGroup::kVis)->extract(data, &info);
  EXPECT_TRUE(info.problem.empty()) << info.problem;
  EXPECT_GT(f.validPoints3D(), static_cast<int>(f.size()) * 3 / 4);
  // 3D points in the base frame, on the room's faces.
  int onWall = 0, valid = 0;
  for (const cv::Point3f& p : f.points3D) {
    if (!std::isfinite(p.x)) continue;
    ++valid;
    const Eigen::Vector3d w = kView.toEigen() * Eigen::Vector3d(p.x, p.y, p.z);
    const double d = std::min({std::fabs(std::fabs(w.x()) - 3.0), std::fabs(std::fabs(w.y()) - 3.0), std::fabs(w.z()),
                               std::fabs(w.z() - 2.5)});
    onWall += d < 0.1 ? 1 : 0;
  }
  EXPECT_GT(onWall, valid * 9 / 10);
}

TEST(StereoCorrespondences, OptionsValidation) {
  StereoOptions o;
  std::string why;
  EXPECT_TRUE(o.IsValid(&why)) << why;
  o.maxDisparity = 0.1f;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("Stereo/MaxDisparity"), std::string::npos);
  cv::Mat a(10, 10, CV_8UC1), b(10, 12, CV_8UC1);
  EXPECT_THROW(computeStereoDisparities(a, b, {}, StereoOptions()), std::invalid_argument);
}

}  // namespace
}  // namespace rtabmap
