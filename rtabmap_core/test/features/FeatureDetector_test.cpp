// Feature detection: counts, grid, ROI, depth masking, 3D points, every detector type, both
// parameter groups, bad input.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <limits>

#include "odometry/SyntheticRoom.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/features/DepthFeatures.h"
#include "rtabmap_core/features/FeatureDetector.h"
#include "rtabmap_core/geometry/SensorData.h"

namespace rtabmap {
namespace {

using test::SyntheticRoom;

const Transform kView(0.0, 0.0, 1.2, 0.0, 0.1, 0.3);

SensorData roomFrame(const SyntheticRoom& room, const CameraModel& model = SyntheticRoom::camera()) {
  return room.rgbd(kView, model);
}

bool finite(const cv::Point3f& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

TEST(FeatureDetector, KeepsTheStrongestUpToMaxFeatures) {
  SyntheticRoom room;
  const SensorData data = roomFrame(room);
  ParametersMap p{{"Vis/MaxFeatures", "200"}};
  const ImageFeatures limited = FeatureDetector::create(p, FeatureGroup::kVis)->extract(data);
  EXPECT_LE(limited.size(), 200u);
  // The scene has far more corners, but BRIEF reads 28 px around a keypoint and drops those
  // nearer the border: 37% of this 320 x 240 image. Over 31 textures of the room 143-160 of the
  // 200 strongest were kept.
  EXPECT_GE(limited.size(), 120u);
  p["Vis/MaxFeatures"] = "0";
  const ImageFeatures all = FeatureDetector::create(p, FeatureGroup::kVis)->extract(data);
  EXPECT_GT(all.size(), limited.size());
  EXPECT_EQ(all.descriptors.rows, static_cast<int>(all.size()));
  EXPECT_EQ(all.points3D.size(), all.size());
  // Strongest kept: the weakest kept response is no weaker than the median of all.
  std::vector<float> responses;
  for (const auto& k : all.keypoints) responses.push_back(k.response);
  std::nth_element(responses.begin(), responses.begin() + static_cast<long>(responses.size() / 2), responses.end());
  float weakestKept = std::numeric_limits<float>::max();
  for (const auto& k : limited.keypoints) weakestKept = std::min(weakestKept, k.response);
  EXPECT_GE(weakestKept, responses[responses.size() / 2]);
}

TEST(FeatureDetector, GridSpreadsFeaturesOverCells) {
  SyntheticRoom room;
  const SensorData data = roomFrame(room);
  const ParametersMap p{{"Vis/MaxFeatures", "200"}, {"Vis/GridRows", "2"}, {"Vis/GridCols", "2"}};
  const ImageFeatures f = FeatureDetector::create(p, FeatureGroup::kVis)->extract(data);
  int cells[4] = {0, 0, 0, 0};
  for (const auto& k : f.keypoints) cells[(k.pt.y >= 120 ? 2 : 0) + (k.pt.x >= 160 ? 1 : 0)]++;
  for (int c : cells) {
    EXPECT_LE(c, 50);
    EXPECT_GE(c, 30);
  }
}

TEST(FeatureDetector, RoiCutsBorders) {
  SyntheticRoom room;
  const SensorData data = roomFrame(room);
  const ParametersMap p{{"Vis/RoiRatios", "0.25 0.25 0.1 0.1"}};
  const ImageFeatures f = FeatureDetector::create(p, FeatureGroup::kVis)->extract(data);
  ASSERT_FALSE(f.empty());
  for (const auto& k : f.keypoints) {
    EXPECT_GE(k.pt.x, 80.0f - 0.5f);
    EXPECT_LT(k.pt.x, 240.0f + 0.5f);
    EXPECT_GE(k.pt.y, 24.0f - 0.5f);
    EXPECT_LT(k.pt.y, 216.0f + 0.5f);
  }
}

TEST(FeatureDetector, NoFeatureWhereDepthIsInvalid) {
  SyntheticRoom room;
  SensorData data = roomFrame(room);
  cv::Mat depth = data.depthOrRightRaw().clone();
  depth(cv::Rect(0, 0, depth.cols / 2, depth.rows)) = std::numeric_limits<float>::quiet_NaN();
  depth(cv::Rect(depth.cols / 2, 0, depth.cols / 2, depth.rows / 4)) = 0.0f;
  data.setRGBDImage(data.imageRaw(), depth, data.cameraModels());
  const ImageFeatures f = FeatureDetector::create({}, FeatureGroup::kVis)->extract(data);
  ASSERT_GT(f.size(), 50u);
  for (size_t i = 0; i < f.size(); ++i) {
    const cv::Point2f& pt = f.keypoints[i].pt;
    EXPECT_GT(SensorData::depthAt(depth, static_cast<int>(std::lround(pt.x)), static_cast<int>(std::lround(pt.y))), 0.0f)
        << "keypoint at " << pt;
  }
  // Without the mask the invalid half gets features, with no 3D point.
  const ImageFeatures unmasked = FeatureDetector::create({{"Vis/DepthAsMask", "false"}}, FeatureGroup::kVis)->extract(data);
  int leftWithout3D = 0;
  for (size_t i = 0; i < unmasked.size(); ++i) {
    if (unmasked.keypoints[i].pt.x < depth.cols / 2 - 2) {
      EXPECT_FALSE(finite(unmasked.points3D[i]));
      ++leftWithout3D;
    }
  }
  EXPECT_GT(leftWithout3D, 20);
}

TEST(FeatureDetector, DepthRangeLimitsFeatures) {
  SyntheticRoom room;
  const SensorData data = roomFrame(room);
  const ParametersMap p{{"Vis/MinDepth", "2.5"}, {"Vis/MaxDepth", "3.5"}, {"Vis/MaxFeatures", "0"}};
  const ImageFeatures f = FeatureDetector::create(p, FeatureGroup::kVis)->extract(data);
  ASSERT_GT(f.size(), 10u);
  const Transform toOptical = data.cameraModels()[0].localTransform().inverse();
  for (const cv::Point3f& p3 : f.points3D) {
    if (!finite(p3)) continue;
    const Eigen::Vector3d c = toOptical.toEigen() * Eigen::Vector3d(p3.x, p3.y, p3.z);
    EXPECT_GE(c.z(), 2.5 - 1e-3);
    EXPECT_LE(c.z(), 3.5 + 1e-3);
  }
}

TEST(FeatureDetector, Points3DLieOnTheRoomInBaseFrame) {
  SyntheticRoom room;
  const SensorData data = roomFrame(room);
  const ImageFeatures f = FeatureDetector::create({}, FeatureGroup::kVis)->extract(data);
  ASSERT_GT(f.validPoints3D(), 100);
  for (const cv::Point3f& p : f.points3D) {
    if (!finite(p)) continue;
    // Base frame -> world, then the point must be on a face of the box.
    const Eigen::Vector3d w = kView.toEigen() * Eigen::Vector3d(p.x, p.y, p.z);
    const double d = std::min({std::fabs(std::fabs(w.x()) - 3.0), std::fabs(std::fabs(w.y()) - 3.0), std::fabs(w.z()),
                               std::fabs(w.z() - 2.5)});
    EXPECT_LT(d, 0.02) << "point " << w.transpose() << " is not on a wall";
  }
}

TEST(FeatureDetector, DecimatedDepthIsUsed) {
  SyntheticRoom room;
  SensorData data = roomFrame(room);
  cv::Mat small;
  cv::resize(data.depthOrRightRaw(), small, cv::Size(160, 120), 0, 0, cv::INTER_NEAREST);
  data.setRGBDImage(data.imageRaw(), small, data.cameraModels());
  FeatureExtractionInfo info;
  const ImageFeatures f = FeatureDetector::create({}, FeatureGroup::kVis)->extract(data, &info);
  EXPECT_TRUE(info.problem.empty()) << info.problem;
  EXPECT_GT(f.validPoints3D(), 100);
}

TEST(FeatureDetector, SubPixelRefinementMovesCorners) {
  SyntheticRoom room;
  const SensorData data = roomFrame(room);
  const ImageFeatures a = FeatureDetector::create({}, FeatureGroup::kVis)->extract(data);
  const ImageFeatures b = FeatureDetector::create({{"Vis/SubPixIterations", "10"}}, FeatureGroup::kVis)->extract(data);
  ASSERT_FALSE(a.empty());
  int fractional = 0;
  for (const auto& k : b.keypoints) fractional += (std::fabs(k.pt.x - std::round(k.pt.x)) > 1e-3) ? 1 : 0;
  EXPECT_GT(fractional, static_cast<int>(b.size()) / 2);
}

TEST(FeatureDetector, EveryTypeDetectsAndDescribes) {
  SyntheticRoom room;
  const SensorData data = roomFrame(room, SyntheticRoom::camera(640, 480));
  for (int type : {1, 2, 4, 6, 7, 8, 9, 16}) {
    const ParametersMap p{{"Vis/FeatureType", std::to_string(type)}, {"Vis/MaxFeatures", "300"}};
    auto detector = FeatureDetector::create(p, FeatureGroup::kVis);
    FeatureExtractionInfo info;
    const ImageFeatures f = detector->extract(data, &info);
    SCOPED_TRACE(featureTypeName(detector->type()));
    EXPECT_TRUE(info.problem.empty()) << info.problem;
    EXPECT_GT(f.size(), 30u);
    EXPECT_LE(f.size(), 300u);
    EXPECT_EQ(f.descriptors.rows, static_cast<int>(f.size()));
    EXPECT_EQ(f.descriptors.type(), detector->binaryDescriptors() ? CV_8U : CV_32F);
  }
}

TEST(FeatureDetector, KpGroupConfiguresTheVocabularyDetector) {
  SyntheticRoom room;
  const SensorData data = roomFrame(room);
  const ParametersMap p{{"Kp/MaxFeatures", "120"}, {"Kp/DetectorStrategy", "6"}, {"Vis/MaxFeatures", "500"}};
  auto kp = FeatureDetector::create(p, FeatureGroup::kKp);
  EXPECT_EQ(kp->type(), FeatureType::kGfttBrief);
  EXPECT_LE(kp->extract(data).size(), 120u);
  auto vis = FeatureDetector::create(p, FeatureGroup::kVis);
  EXPECT_EQ(vis->type(), FeatureType::kGfttOrb);
  EXPECT_GT(vis->extract(data).size(), 120u);
  // Kp/MaxFeatures < 0: no words at all.
  EXPECT_TRUE(FeatureDetector::create({{"Kp/MaxFeatures", "-1"}}, FeatureGroup::kKp)->extract(data).empty());
}

TEST(FeatureDetector, InvalidOptionsSayWhy) {
  FeatureOptions o;
  o.minDepth = 4.0f;
  o.maxDepth = 2.0f;
  std::string why;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("minimum depth"), std::string::npos) << why;
  EXPECT_THROW(FeatureDetector detector(o), ParameterError);
  o = FeatureOptions();
  o.roiRatios = {{0.6, 0.5, 0.0, 0.0}};
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_THROW(FeatureDetector::create({{"Vis/FeatureType", "0"}}, FeatureGroup::kVis), ParameterError);
}

TEST(FeatureDetector, BadInputIsAProblemNotACrash) {
  SyntheticRoom room;
  const SensorData good = roomFrame(room);
  auto detector = FeatureDetector::create({}, FeatureGroup::kVis);
  auto problemOf = [&](const SensorData& d) {
    FeatureExtractionInfo info;
    EXPECT_TRUE(detector->extract(d, &info).empty());
    return info.problem;
  };
  EXPECT_NE(problemOf(SensorData()).find("no image"), std::string::npos);
  cv::Mat wide;
  good.imageRaw().convertTo(wide, CV_16UC3);
  EXPECT_NE(problemOf(SensorData(wide, good.depthOrRightRaw(), good.cameraModels()[0])).find("unsupported image"),
            std::string::npos);
  EXPECT_NE(problemOf(SensorData(good.imageRaw(), good.depthOrRightRaw(), CameraModel(0, 0, 160, 120)))
                .find("not valid for projection"),
            std::string::npos);
  cv::Mat odd(100, 150, CV_32FC1, cv::Scalar(1.0f));
  EXPECT_NE(problemOf(SensorData(good.imageRaw(), odd, good.cameraModels()[0])).find("does not match"), std::string::npos);
  cv::Mat nan(good.depthOrRightRaw().size(), CV_32FC1, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  EXPECT_NE(problemOf(SensorData(good.imageRaw(), nan, good.cameraModels()[0])).find("no valid pixel"), std::string::npos);
  cv::Mat zero = cv::Mat::zeros(good.depthOrRightRaw().size(), CV_16UC1);
  EXPECT_NE(problemOf(SensorData(good.imageRaw(), zero, good.cameraModels()[0])).find("no valid pixel"), std::string::npos);
  // A textureless image is not a problem of the input: it just has no features.
  cv::Mat flat(good.imageRaw().size(), CV_8UC3, cv::Scalar(128, 128, 128));
  FeatureExtractionInfo info;
  EXPECT_TRUE(detector->extract(SensorData(flat, good.depthOrRightRaw(), good.cameraModels()[0]), &info).empty());
  EXPECT_TRUE(info.problem.empty());
}

TEST(DepthFeatures, MaskAndDecimationFactor) {
  EXPECT_EQ(depthDecimationFactor({640, 480}, {640, 480}), 1);
  EXPECT_EQ(depthDecimationFactor({640, 480}, {320, 240}), 2);
  EXPECT_EQ(depthDecimationFactor({640, 480}, {320, 200}), 0);
  EXPECT_EQ(depthDecimationFactor({640, 480}, {0, 0}), 0);
  cv::Mat depth(2, 2, CV_16UC1);
  depth.at<unsigned short>(0, 0) = 0;
  depth.at<unsigned short>(0, 1) = 65535;  // 7-Scenes' invalid marker
  depth.at<unsigned short>(1, 0) = 1500;
  depth.at<unsigned short>(1, 1) = 5000;
  int valid = 0;
  const cv::Mat mask = depthMask(depth, {4, 4}, 0.0f, 4.0f, &valid);
  EXPECT_EQ(valid, 1);
  EXPECT_EQ(cv::countNonZero(mask), 4);  // one depth pixel covers 2x2 image pixels
  EXPECT_EQ(mask.at<unsigned char>(3, 0), 255);
  EXPECT_THROW(depthMask(depth, {5, 4}, 0.0f, 0.0f), std::invalid_argument);
}

TEST(DepthFeatures, KeypointOnADepthEdgeHasNoDepth) {
  cv::Mat depth(10, 10, CV_32FC1, cv::Scalar(1.0f));
  depth(cv::Rect(5, 0, 5, 10)) = 3.0f;  // a silhouette at column 5
  EXPECT_FLOAT_EQ(keypointDepth(depth, {2.0f, 5.0f}, 1), 1.0f);
  EXPECT_FLOAT_EQ(keypointDepth(depth, {4.0f, 5.0f}, 1), 0.0f);
  EXPECT_FLOAT_EQ(keypointDepth(depth, {7.0f, 5.0f}, 1), 3.0f);
}

}  // namespace
}  // namespace rtabmap
