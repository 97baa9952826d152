// What a node keeps of its images. Mem/ImagePreDecimation and Mem/ImagePostDecimation: words
// found in a shrunk image, a node that keeps shrunk images, and in every combination keypoints
// that lie where their 3D points project in the image the node keeps (what visual registration
// of a loop closure relies on). Mem/SaveDepth16Format: float depth kept as millimetres.
#include <gtest/gtest.h>

#include "PoseOnlyFrames.h"
#include "TexturedFrames.h"
#include "common/DistortedFrames.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/slam/Rtabmap.h"

namespace rtabmap {
namespace {

using test::texturedFrame;
constexpr int kWidth = test::kTexturedWidth, kHeight = test::kTexturedHeight;

struct Decimations {
  int pre, post;
};

class NodeImageDecimation : public ::testing::TestWithParam<Decimations> {};

TEST_P(NodeImageDecimation, KeptImagesShrinkAndWordsStayOnThem) {
  const auto [pre, post] = GetParam();
  Rtabmap slam;
  ParametersMap p = test::everyFrame();
  p["Mem/ImagePreDecimation"] = std::to_string(pre);
  p["Mem/ImagePostDecimation"] = std::to_string(post);
  slam.init(p, "");
  ASSERT_TRUE(slam.process(texturedFrame(1, 1.0), Transform::Identity(), test::smallCov())) << slam.lastRejection();
  const std::optional<Signature> node = slam.node(slam.lastNodeId());
  ASSERT_TRUE(node.has_value());
  SensorData data = node->sensorData();
  data.uncompress(true, true, false, false);
  EXPECT_EQ(data.imageRaw().cols, kWidth / post);
  EXPECT_EQ(data.imageRaw().rows, kHeight / post);
  EXPECT_EQ(data.depthOrRightRaw().cols, kWidth / post);
  ASSERT_EQ(data.cameraModels().size(), 1u);
  const CameraModel& model = data.cameraModels().front();
  EXPECT_NEAR(model.fx(), 525.0 / post, 1e-6);
  EXPECT_EQ(model.imageSize(), data.imageRaw().size());

  const std::vector<cv::KeyPoint>& kpts = node->getWordsKpts();
  const std::vector<cv::Point3f>& points = node->getWords3();
  ASSERT_GT(kpts.size(), 50u);
  ASSERT_EQ(points.size(), kpts.size());
  const Transform toCamera = model.localTransform().inverse();
  int checked = 0;
  for (size_t i = 0; i < kpts.size(); ++i) {
    const cv::Point2f& k = kpts[i].pt;
    EXPECT_TRUE(k.x >= 0 && k.y >= 0 && k.x < data.imageRaw().cols && k.y < data.imageRaw().rows) << k;
    if (!std::isfinite(points[i].x)) continue;
    const Eigen::Vector3d c = toCamera.toEigen() * Eigen::Vector3d(points[i].x, points[i].y, points[i].z);
    double u, v;
    ASSERT_TRUE(model.reproject(c.x(), c.y(), c.z(), u, v));
    // The models scale as ROS binning does (fx / b, cx / b): exact up to float rounding. A
    // keypoint left in the coordinates of the image it was found in is pixels away.
    EXPECT_NEAR(u, k.x, 0.02) << "word " << i;
    EXPECT_NEAR(v, k.y, 0.02) << "word " << i;
    ++checked;
  }
  EXPECT_GT(checked, 50);
}

INSTANTIATE_TEST_SUITE_P(PrePost, NodeImageDecimation,
                         ::testing::Values(Decimations{1, 1}, Decimations{2, 2}, Decimations{1, 2}, Decimations{2, 1},
                                           Decimations{4, 2}),
                         [](const ::testing::TestParamInfo<Decimations>& i) {
                           return "pre" + std::to_string(i.param.pre) + "_post" + std::to_string(i.param.post);
                         });

TEST(NodeImageDecimation, PreDecimationFindsWordsInTheSmallerImage) {
  auto words = [](int pre) {
    Rtabmap slam;
    ParametersMap p = test::everyFrame();
    p["Mem/ImagePreDecimation"] = std::to_string(pre);
    p["Kp/MaxFeatures"] = "0";  // every keypoint the detector finds
    slam.init(p, "");
    EXPECT_TRUE(slam.process(texturedFrame(1, 1.0), Transform::Identity(), test::smallCov()));
    return slam.node(slam.lastNodeId())->getWordsKpts().size();
  };
  const size_t full = words(1), quarter = words(4);
  EXPECT_GT(quarter, 0u);
  EXPECT_LT(quarter, full) << "a 160x120 image has fewer corners than a 640x480 one";
}

TEST(NodeImageDecimation, DecimationBelowOneIsRefused) {
  Rtabmap slam;
  ParametersMap p = test::everyFrame();
  p["Mem/ImagePostDecimation"] = "0";
  EXPECT_THROW(slam.init(p, ""), ParameterError);
}

TEST(NodeImages, FloatDepthIsKeptAsMillimetresWithSaveDepth16Format) {
  for (const bool mm : {false, true}) {
    SCOPED_TRACE(mm ? "Mem/SaveDepth16Format" : "default");
    Rtabmap slam;
    ParametersMap p = test::everyFrame();
    p["Mem/SaveDepth16Format"] = mm ? "true" : "false";
    slam.init(p, "");
    ASSERT_TRUE(slam.process(texturedFrame(1, 1.0), Transform::Identity(), test::smallCov()));
    SensorData data = slam.node(slam.lastNodeId())->sensorData();
    data.uncompress(true, true, false, false);
    const cv::Mat& depth = data.depthOrRightRaw();
    ASSERT_EQ(depth.type(), mm ? CV_16UC1 : CV_32FC1);
    // The slanted plane: 1.5 m at the left edge, 2.5 at the right.
    const double left = mm ? depth.at<uint16_t>(240, 0) * 0.001 : depth.at<float>(240, 0);
    const double right = mm ? depth.at<uint16_t>(240, kWidth - 1) * 0.001 : depth.at<float>(240, kWidth - 1);
    EXPECT_NEAR(left, 1.5, 0.001);
    EXPECT_NEAR(right, 1.5 + (kWidth - 1.0) / kWidth, 0.001);
  }
}

// Mem/CompressionParallelized (default) shrinks and compresses the kept images beside the words
// and the grid: the node keeps the same bytes as without it, and a stereo node its right image
// lossless; the scan stays raw, the images only compressed (Mem/ImageKept false).
TEST(NodeImages, ParallelCompressionKeepsWhatSequentialCompressionKeeps) {
  auto keptBy = [](bool parallel, const SensorData& frame) {
    Rtabmap slam;
    ParametersMap p = test::everyFrame();
    p["Mem/CompressionParallelized"] = parallel ? "true" : "false";
    p["Mem/ImagePostDecimation"] = "2";
    p["Mem/SaveDepth16Format"] = "true";
    slam.init(p, "");
    EXPECT_TRUE(slam.process(frame, Transform::Identity(), test::smallCov())) << slam.lastRejection();
    return slam.node(slam.lastNodeId())->sensorData();
  };
  SensorData rgbd = texturedFrame(1, 1.0);
  cv::Mat points(1, 50, CV_32FC2);
  for (int i = 0; i < points.cols; ++i) points.at<cv::Vec2f>(i) = cv::Vec2f(2.f, -1.f + 0.04f * static_cast<float>(i));
  rgbd.setLaserScan(LaserScan(points, 50, 0.1, 10.0, LaserScan::kXY));
  const SensorData sequential = keptBy(false, rgbd), parallel = keptBy(true, rgbd);
  ASSERT_FALSE(parallel.imageCompressed().empty());
  ASSERT_FALSE(parallel.depthOrRightCompressed().empty());
  EXPECT_EQ(parallel.imageCompressed(), sequential.imageCompressed());
  EXPECT_EQ(parallel.depthOrRightCompressed(), sequential.depthOrRightCompressed());
  EXPECT_EQ(parallel.laserScanCompressed(), sequential.laserScanCompressed());
  EXPECT_TRUE(parallel.imageRaw().empty());
  EXPECT_TRUE(parallel.depthOrRightRaw().empty());
  EXPECT_EQ(parallel.laserScanRaw().size(), 50);
  ASSERT_EQ(parallel.cameraModels().size(), 1u);
  EXPECT_NEAR(parallel.cameraModels().front().fx(), 525.0 / 2, 1e-9);
  SensorData depth = parallel;
  depth.uncompress(true, true, false, false);
  EXPECT_EQ(depth.depthOrRightRaw().type(), CV_16UC1);
  EXPECT_EQ(depth.imageRaw().cols, kWidth / 2);

  const SensorData mono = texturedFrame(2, 2.0);
  cv::Mat left;
  cv::cvtColor(mono.imageRaw(), left, cv::COLOR_BGR2GRAY);
  const StereoCameraModel stereo(525.0, 525.0, 319.5, 239.5, 0.1, CameraModel::opticalRotation(),
                                 cv::Size(kWidth, kHeight));
  const SensorData pair(left, left.clone(), stereo, 2, 2.0);
  const SensorData stereoSequential = keptBy(false, pair), stereoParallel = keptBy(true, pair);
  EXPECT_EQ(stereoParallel.depthOrRightCompressed(), stereoSequential.depthOrRightCompressed());
  SensorData right = stereoParallel;
  right.uncompress(true, true, false, false);
  ASSERT_TRUE(right.isStereo());
  cv::Mat shrunk;
  cv::resize(left, shrunk, cv::Size(kWidth / 2, kHeight / 2), 0, 0, cv::INTER_AREA);
  EXPECT_EQ(cv::norm(right.depthOrRightRaw(), shrunk, cv::NORM_INF), 0.0) << "the right image is kept lossless";
}

// Mem/BinDataKept false: the node keeps its words, grid, scan and camera models (scaled as its
// keypoints were), not its images.
TEST(NodeImages, WithoutBinDataTheNodeKeepsEverythingButItsImages) {
  Rtabmap slam;
  ParametersMap p = test::everyFrame();
  p["Mem/BinDataKept"] = "false";
  p["Mem/ImagePostDecimation"] = "2";
  p["RGBD/CreateOccupancyGrid"] = "true";  // from the depth image, before it goes
  slam.init(p, "");
  SensorData frame = texturedFrame(1, 1.0);
  cv::Mat points(1, 50, CV_32FC2, cv::Scalar(2.f, 0.5f));
  frame.setLaserScan(LaserScan(points, 50, 0.1, 10.0, LaserScan::kXY));
  ASSERT_TRUE(slam.process(frame, Transform::Identity(), test::smallCov())) << slam.lastRejection();
  const std::optional<Signature> node = slam.node(slam.lastNodeId());
  ASSERT_TRUE(node.has_value());
  const SensorData& data = node->sensorData();
  EXPECT_TRUE(data.imageRaw().empty() && data.imageCompressed().empty());
  EXPECT_TRUE(data.depthOrRightRaw().empty() && data.depthOrRightCompressed().empty());
  ASSERT_EQ(data.cameraModels().size(), 1u);
  EXPECT_NEAR(data.cameraModels().front().fx(), 525.0 / 2, 1e-9);
  EXPECT_EQ(data.laserScanRaw().size(), 50);
  EXPECT_FALSE(data.localGrid().isEmpty());
  ASSERT_GT(node->getWordsKpts().size(), 50u);
  for (const cv::KeyPoint& k : node->getWordsKpts()) ASSERT_LT(k.pt.x, kWidth / 2.f);
}

// Rtabmap/ImagesAlreadyRectified false: the node keeps the rectified images, with rectified
// models; by default the images are taken as they come.
TEST(NodeImages, RawImagesAreRectifiedWhenNotAlreadyRectified) {
  const CameraModel camera = test::distortedCamera();
  const cv::Mat raw = test::distort(test::blockTexture(), camera);
  for (const bool already : {true, false}) {
    SCOPED_TRACE(already ? "default" : "Rtabmap/ImagesAlreadyRectified false");
    Rtabmap slam;
    ParametersMap p = test::everyFrame();
    p["Rtabmap/ImagesAlreadyRectified"] = already ? "true" : "false";
    p["Mem/ImageCompressionFormat"] = ".png";  // lossless: the kept image compares to the bit
    slam.init(p, "");
    ASSERT_TRUE(slam.process(SensorData(raw, test::rampDepth(), camera, 1, 1.0), Transform::Identity(), test::smallCov()));
    SensorData kept = slam.node(slam.lastNodeId())->sensorData();
    kept.uncompress(true, true, false, false);
    ASSERT_EQ(kept.cameraModels().size(), 1u);
    EXPECT_EQ(kept.cameraModels().front().isRectified(), !already);
    const cv::Mat expected = already ? raw : camera.rectifyImage(raw);
    EXPECT_EQ(cv::norm(kept.imageRaw(), expected, cv::NORM_INF), 0.0);
  }
}

}  // namespace
}  // namespace rtabmap
