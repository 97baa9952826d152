// rectifyImages (Rtabmap/ImagesAlreadyRectified false): raw images back to the rectified ones,
// depth by nearest neighbour, models rectified so that a second pass changes nothing.
#include <gtest/gtest.h>

#include "common/DistortedFrames.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/geometry/ImageRectification.h"

namespace rtabmap {
namespace {

// Mean absolute difference over the centre (the border has no raw pixel to come from).
double centreDifference(const cv::Mat& a, const cv::Mat& b) {
  const cv::Rect centre(40, 30, a.cols - 80, a.rows - 60);
  cv::Mat fa, fb;
  a(centre).convertTo(fa, CV_32F);
  b(centre).convertTo(fb, CV_32F);
  return cv::mean(cv::abs(fa - fb))[0];
}

// Share of the centre's pixels with exactly the depth of the scene there.
double exactShare(const cv::Mat& depth, const cv::Mat& truth) {
  const cv::Rect centre(40, 30, depth.cols - 80, depth.rows - 60);
  const cv::Mat same = depth(centre) == truth(centre);
  return cv::countNonZero(same) / static_cast<double>(centre.area());
}

TEST(ImageRectification, RawImagesComeBackRectified) {
  const CameraModel camera = test::distortedCamera();
  const cv::Mat truth = test::blockTexture(), truthDepth = test::blockDepth();
  const SensorData raw(test::distort(truth, camera), test::distort(truthDepth, camera, cv::INTER_NEAREST), camera, 1, 1.0);
  ASSERT_TRUE(needsRectification(raw));
  const SensorData out = rectifyImages(raw);
  ASSERT_EQ(out.cameraModels().size(), 1u);
  EXPECT_TRUE(out.cameraModels().front().isRectified());
  EXPECT_DOUBLE_EQ(out.cameraModels().front().fx(), camera.fx());
  EXPECT_FALSE(needsRectification(out));
  const double before = centreDifference(raw.imageRaw(), truth), after = centreDifference(out.imageRaw(), truth);
  EXPECT_GT(before, 20.0) << "the distortion is too weak to test anything";
  EXPECT_LT(after, 0.2 * before) << "grey levels off by " << after << " on average (raw: " << before << ")";
  // Depth: by nearest neighbour (never a blend of two depths across an edge), so closer to the
  // scene than the raw depth, though not exact next to the blocks' edges (the raw depth was made
  // by nearest neighbour too: a pixel can be off by one twice).
  EXPECT_EQ(cv::norm(out.depthOrRightRaw(), camera.rectifyDepth(raw.depthOrRightRaw()), cv::NORM_INF), 0.0);
  const double depthBefore = exactShare(raw.depthOrRightRaw(), truthDepth);
  const double depthAfter = exactShare(out.depthOrRightRaw(), truthDepth);
  EXPECT_GT(depthAfter, depthBefore + 0.05);
  EXPECT_GT(depthAfter, 0.7);
  // A second pass changes nothing.
  const SensorData again = rectifyImages(out);
  EXPECT_EQ(again.imageRaw().data, out.imageRaw().data);
}

TEST(ImageRectification, EachCameraOfASideBySideImageOnItsOwn) {
  const CameraModel camera = test::distortedCamera();
  const cv::Mat a = test::blockTexture(3), b = test::blockTexture(4);
  cv::Mat raw;
  cv::hconcat(test::distort(a, camera), test::distort(b, camera), raw);
  cv::Mat depth;
  cv::hconcat(test::rampDepth(), test::rampDepth(), depth);
  const SensorData out = rectifyImages(SensorData(raw, depth, std::vector<CameraModel>{camera, camera}, 1, 1.0));
  EXPECT_LT(centreDifference(out.imageRaw().colRange(0, 320), a), 5.0);
  EXPECT_LT(centreDifference(out.imageRaw().colRange(320, 640), b), 5.0);
}

TEST(ImageRectification, AnImageOfAnotherSizeThanItsCalibrationIsRefused) {
  const CameraModel camera = test::distortedCamera();
  cv::Mat small;
  cv::resize(test::blockTexture(), small, cv::Size(160, 120));
  EXPECT_THROW(rectifyImages(SensorData(small, cv::Mat(), camera, 1, 1.0)), FormatError);
}

TEST(ImageRectification, RectifiedModelsPassThrough) {
  const CameraModel rectified(300, 300, 160, 120, CameraModel::opticalRotation(), 0.0, cv::Size(320, 240));
  const SensorData data(test::blockTexture(), test::rampDepth(), rectified, 1, 1.0);
  EXPECT_FALSE(needsRectification(data));
  EXPECT_EQ(rectifyImages(data).imageRaw().data, data.imageRaw().data);
}

}  // namespace
}  // namespace rtabmap
