#include "rtabmap_conversions/CameraInfoConversions.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include <limits>

using namespace rtabmap_conversions;
using rtabmap::CameraModel;
using rtabmap::Transform;

namespace {

std_msgs::Header header(const std::string& frame = "camera_optical") {
  std_msgs::Header h;
  h.frame_id = frame;
  h.stamp = ros::Time(100, 0);
  return h;
}

// A calibrated (distorted, slightly rotated) camera as camera_calibration would write it.
sensor_msgs::CameraInfo calibratedInfo(const std::string& model, std::vector<double> d) {
  sensor_msgs::CameraInfo info;
  info.header = header();
  info.width = 640;
  info.height = 480;
  info.distortion_model = model;
  info.D = std::move(d);
  info.K = {525.1, 0, 319.4, 0, 524.3, 241.2, 0, 0, 1};
  info.R = {0.9998, -0.0175, 0, 0.0175, 0.9998, 0, 0, 0, 1};
  info.P = {510.0, 0, 322.0, 0, 0, 510.0, 238.0, 0, 0, 0, 1, 0};
  return info;
}

void expectSameInfo(const sensor_msgs::CameraInfo& a, const sensor_msgs::CameraInfo& b) {
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.distortion_model, b.distortion_model);
  EXPECT_EQ(a.D, b.D);
  EXPECT_EQ(a.K, b.K);
  EXPECT_EQ(a.R, b.R);
  EXPECT_EQ(a.P, b.P);
}

}  // namespace

TEST(CameraInfoConversions, EveryDistortionModelRoundTripsExactly) {
  const std::vector<std::pair<std::string, std::vector<double>>> cases = {
      {"plumb_bob", {-0.28, 0.07, 0.0002, 0.00002, 0.0}},
      {"rational_polynomial", {-0.28, 0.07, 0.0002, 0.00002, 0.01, 0.1, -0.02, 0.003}},
      {"equidistant", {0.1, -0.01, 0.002, -0.0003}},
  };
  const Transform local(0.1, 0.02, 0.3, -1.57, 0.0, -1.57);
  for (const auto& [model, d] : cases) {
    const sensor_msgs::CameraInfo info = calibratedInfo(model, d);
    std::string error;
    const std::optional<CameraModel> cam = cameraModelFromMsg(info, local, &error);
    ASSERT_TRUE(cam) << model << ": " << error;
    EXPECT_EQ(cam->distortionModel(), model);
    EXPECT_EQ(cam->isFisheye(), model == "equidistant");
    EXPECT_EQ(cam->localTransform(), local);
    EXPECT_EQ(cam->imageSize(), cv::Size(640, 480));
    EXPECT_DOUBLE_EQ(cam->fx(), 510.0);  // rectified intrinsics come from P
    EXPECT_DOUBLE_EQ(cam->K_raw().at<double>(0, 0), 525.1);
    expectSameInfo(cameraModelToMsg(*cam, header()), info);
  }
}

TEST(CameraInfoConversions, RectifiedModelWritesPAndNoDistortion) {
  const CameraModel model(500.0, 501.0, 320.5, 240.5, CameraModel::opticalRotation(), 0.0, cv::Size(640, 480));
  const sensor_msgs::CameraInfo info = cameraModelToMsg(model, header("cam"));
  EXPECT_EQ(info.header.frame_id, "cam");
  EXPECT_EQ(info.distortion_model, "plumb_bob");
  EXPECT_EQ(info.D, std::vector<double>(5, 0.0));
  EXPECT_EQ(info.P[0], 500.0);
  EXPECT_EQ(info.P[6], 240.5);
  const std::optional<CameraModel> back = cameraModelFromMsg(info);
  ASSERT_TRUE(back);
  EXPECT_DOUBLE_EQ(back->fy(), 501.0);
  EXPECT_EQ(back->name(), "cam");
}

TEST(CameraInfoConversions, UncalibratedPMeansUseK) {
  sensor_msgs::CameraInfo info = calibratedInfo("plumb_bob", {});
  info.P.fill(0.0);
  info.R.fill(0.0);
  const std::optional<CameraModel> cam = cameraModelFromMsg(info);
  ASSERT_TRUE(cam);
  EXPECT_DOUBLE_EQ(cam->fx(), 525.1);
  EXPECT_DOUBLE_EQ(cam->cy(), 241.2);
  EXPECT_EQ(cv::norm(cam->R(), cv::Mat(cv::Mat::eye(3, 3, CV_64F))), 0.0);
}

TEST(CameraInfoConversions, BinningAndRoiDescribeThePublishedImage) {
  sensor_msgs::CameraInfo info = calibratedInfo("plumb_bob", {0, 0, 0, 0, 0});
  info.binning_x = info.binning_y = 2;
  std::optional<CameraModel> cam = cameraModelFromMsg(info);
  ASSERT_TRUE(cam);
  EXPECT_EQ(cam->imageSize(), cv::Size(320, 240));
  EXPECT_DOUBLE_EQ(cam->fx(), 255.0);
  EXPECT_DOUBLE_EQ(cam->cx(), 161.0);

  info.binning_x = info.binning_y = 1;
  info.roi.x_offset = 100;
  info.roi.y_offset = 50;
  info.roi.width = 200;
  info.roi.height = 100;
  cam = cameraModelFromMsg(info);
  ASSERT_TRUE(cam);
  EXPECT_EQ(cam->imageSize(), cv::Size(200, 100));
  EXPECT_DOUBLE_EQ(cam->cx(), 222.0);
  EXPECT_DOUBLE_EQ(cam->cy(), 188.0);
}

TEST(CameraInfoConversions, BadInfosAreErrorsThatSayWhy) {
  std::string error;
  sensor_msgs::CameraInfo zeroK = calibratedInfo("plumb_bob", {});
  zeroK.K.fill(0.0);
  zeroK.P.fill(0.0);
  EXPECT_FALSE(cameraModelFromMsg(zeroK, CameraModel::opticalRotation(), &error));
  EXPECT_NE(error.find("zero focal length"), std::string::npos) << error;
  EXPECT_NE(error.find("camera_optical"), std::string::npos) << error;

  sensor_msgs::CameraInfo nan = calibratedInfo("plumb_bob", {});
  nan.K[2] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(cameraModelFromMsg(nan, CameraModel::opticalRotation(), &error));
  EXPECT_NE(error.find("NaN"), std::string::npos) << error;

  sensor_msgs::CameraInfo noSize = calibratedInfo("plumb_bob", {});
  noSize.width = 0;
  EXPECT_FALSE(cameraModelFromMsg(noSize, CameraModel::opticalRotation(), &error));
  EXPECT_NE(error.find("image size"), std::string::npos) << error;

  sensor_msgs::CameraInfo badD = calibratedInfo("equidistant", {0.1, 0.2, 0.3, 0.4, 0.5});
  EXPECT_FALSE(cameraModelFromMsg(badD, CameraModel::opticalRotation(), &error));
  EXPECT_NE(error.find("equidistant"), std::string::npos) << error;

  sensor_msgs::CameraInfo sixD = calibratedInfo("plumb_bob", {1, 2, 3, 4, 5, 6});
  EXPECT_FALSE(cameraModelFromMsg(sixD, CameraModel::opticalRotation(), &error));

  sensor_msgs::CameraInfo unknownModel = calibratedInfo("double_sphere", {0.1, 0.2, 0.3, 0.4, 0.5});
  EXPECT_FALSE(cameraModelFromMsg(unknownModel, CameraModel::opticalRotation(), &error));
  EXPECT_NE(error.find("double_sphere"), std::string::npos) << error;

  sensor_msgs::CameraInfo binning = calibratedInfo("plumb_bob", {});
  binning.binning_x = 2;
  binning.binning_y = 4;
  EXPECT_FALSE(cameraModelFromMsg(binning, CameraModel::opticalRotation(), &error));
  EXPECT_NE(error.find("binning"), std::string::npos) << error;

  sensor_msgs::CameraInfo roi = calibratedInfo("plumb_bob", {});
  roi.roi.x_offset = 600;
  roi.roi.width = 100;
  roi.roi.height = 10;
  EXPECT_FALSE(cameraModelFromMsg(roi, CameraModel::opticalRotation(), &error));
  EXPECT_NE(error.find("region of interest"), std::string::npos) << error;
}

TEST(CameraInfoConversions, StereoPairFromTwoInfos) {
  const rtabmap::StereoCameraModel stereo(450.0, 450.0, 376.0, 240.0, 0.11, CameraModel::opticalRotation(),
                                          cv::Size(752, 480));
  sensor_msgs::CameraInfo left, right;
  stereoModelToMsgs(stereo, header("left_optical"), header("right_optical"), left, right);
  EXPECT_EQ(right.header.frame_id, "right_optical");
  EXPECT_DOUBLE_EQ(right.P[3], -450.0 * 0.11);
  const Transform local(0.2, 0.0, 1.0, -M_PI / 2, 0.0, -M_PI / 2);
  std::string error;
  const std::optional<rtabmap::StereoCameraModel> back = stereoModelFromMsgs(left, right, local, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_NEAR(back->baseline(), 0.11, 1e-12);
  EXPECT_EQ(back->localTransform(), local);
  // The right camera sits baseline metres along the left optical x axis.
  const Transform rightInLeft = back->left().localTransform().inverse() * back->right().localTransform();
  EXPECT_NEAR(rightInLeft.x(), 0.11, 1e-12);
  EXPECT_NEAR(rightInLeft.getAngle(), 0.0, 1e-12);
  EXPECT_TRUE(back->isValidForProjection());

  sensor_msgs::CameraInfo noBaseline = right;
  noBaseline.P[3] = 0.0;
  EXPECT_FALSE(stereoModelFromMsgs(left, noBaseline, local, &error));
  EXPECT_NE(error.find("Tx"), std::string::npos) << error;

  sensor_msgs::CameraInfo otherSize = right;
  otherSize.width = 640;
  EXPECT_FALSE(stereoModelFromMsgs(left, otherSize, local, &error));
  EXPECT_NE(error.find("size"), std::string::npos) << error;

  sensor_msgs::CameraInfo otherFocal = right;
  otherFocal.P[0] = 460.0;
  otherFocal.P[3] = -460.0 * 0.11;
  EXPECT_FALSE(stereoModelFromMsgs(left, otherFocal, local, &error));
  EXPECT_NE(error.find("not rectified together"), std::string::npos) << error;
}
