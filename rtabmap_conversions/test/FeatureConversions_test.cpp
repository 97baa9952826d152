// Keypoints, 3D points and descriptors through their message fields: every field kept, any
// descriptor type and width, and corrupt or mismatched descriptor bytes refused with a reason.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>

#include "TestHelpers.h"
#include "rtabmap_conversions/FeatureConversions.h"

using namespace rtabmap_conversions;

TEST(FeatureConversions, KeypointsKeepEveryField) {
  const std::vector<cv::KeyPoint> kpts = {cv::KeyPoint(12.25f, 300.5f, 31.f, 271.5f, 0.0125f, 3, 7),
                                          cv::KeyPoint(0.f, 0.f, 1.f, -1.f, 0.f, 0, -1),
                                          cv::KeyPoint(639.75f, 479.25f, 8.5f, 0.f, 1e-6f, -1, 123456)};
  const std::vector<rtabmap_ros::KeyPoint> msgs = keypointsToMsg(kpts);
  ASSERT_EQ(msgs.size(), kpts.size());
  EXPECT_FLOAT_EQ(msgs[0].pt.x, 12.25f);
  EXPECT_FLOAT_EQ(msgs[0].angle, 271.5f);
  EXPECT_EQ(msgs[2].class_id, 123456);
  const std::vector<cv::KeyPoint> back = keypointsFromMsg(msgs);
  ASSERT_EQ(back.size(), kpts.size());
  for (size_t i = 0; i < kpts.size(); ++i) {
    EXPECT_EQ(back[i].pt, kpts[i].pt) << i;
    EXPECT_EQ(back[i].size, kpts[i].size) << i;
    EXPECT_EQ(back[i].angle, kpts[i].angle) << i;
    EXPECT_EQ(back[i].response, kpts[i].response) << i;
    EXPECT_EQ(back[i].octave, kpts[i].octave) << i;
    EXPECT_EQ(back[i].class_id, kpts[i].class_id) << i;
  }
  EXPECT_TRUE(keypointsFromMsg({}).empty());
}

TEST(FeatureConversions, PointsKeepNaNForUnknownDepth) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<cv::Point3f> pts = {{1.5f, -2.25f, 3.125f}, {nan, nan, nan}, {-1e-3f, 0.f, 42.f}};
  const std::vector<cv::Point3f> back = pointsFromMsg(pointsToMsg(pts));
  ASSERT_EQ(back.size(), pts.size());
  EXPECT_EQ(back[0], pts[0]);
  EXPECT_TRUE(std::isnan(back[1].x) && std::isnan(back[1].y) && std::isnan(back[1].z));
  EXPECT_EQ(back[2], pts[2]);
}

TEST(FeatureConversions, BinaryAndFloatDescriptorsRoundTripBitExactly) {
  // ORB-like (32 bytes) and SIFT-like (128 floats) descriptors: the layout travels in the blob.
  for (const cv::Mat& d : {rtabmap_conversions::test::randomImage(50, 32, CV_8UC1, 3),
                           rtabmap_conversions::test::randomImage(20, 128, CV_32FC1, 4)}) {
    const std::vector<uint8_t> bytes = descriptorsToMsg(d);
    ASSERT_FALSE(bytes.empty());
    std::string why;
    const std::optional<cv::Mat> back = descriptorsFromMsg(bytes, d.rows, &why);
    ASSERT_TRUE(back) << why;
    EXPECT_EQ(back->type(), d.type());
    EXPECT_TRUE(rtabmap_conversions::test::sameBits(*back, d));
    EXPECT_TRUE(descriptorsFromMsg(bytes, -1, &why)) << why;  // no row count to check
  }
}

TEST(FeatureConversions, NoDescriptorsIsLegal) {
  EXPECT_TRUE(descriptorsToMsg(cv::Mat()).empty());
  const std::optional<cv::Mat> back = descriptorsFromMsg({}, 10);
  ASSERT_TRUE(back);  // keypoints without descriptors: the receiver extracts them again
  EXPECT_TRUE(back->empty());
}

TEST(FeatureConversions, CorruptOrMismatchedDescriptorsAreRefused) {
  const cv::Mat d = rtabmap_conversions::test::randomImage(10, 32, CV_8UC1, 5);
  std::vector<uint8_t> bytes = descriptorsToMsg(d);
  std::string why;
  EXPECT_FALSE(descriptorsFromMsg(bytes, 11, &why));
  EXPECT_NE(why.find("10 descriptors for 11 keypoints"), std::string::npos) << why;

  why.clear();
  std::vector<uint8_t> cut(bytes.begin(), bytes.begin() + bytes.size() / 2);
  EXPECT_FALSE(descriptorsFromMsg(cut, 10, &why));
  EXPECT_NE(why.find("corrupt descriptors"), std::string::npos) << why;

  why.clear();
  std::vector<uint8_t> garbage(64, 0xAB);
  EXPECT_FALSE(descriptorsFromMsg(garbage, 10, &why));
  EXPECT_NE(why.find("corrupt descriptors"), std::string::npos) << why;
}
