#include "rtabmap_conversions/CompressedImageConversions.h"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstring>
#include <limits>

#include "TestHelpers.h"
#include "rtabmap_core/codec/Compression.h"
#include "rtabmap_core/common/Error.h"

using namespace rtabmap_conversions;
using rtabmap_conversions::test::randomImage;
using rtabmap_conversions::test::sameBits;
using rtabmap_conversions::test::smoothImage;

namespace {

std_msgs::Header header() {
  std_msgs::Header h;
  h.frame_id = "camera";
  h.stamp = ros::Time(5, 0);
  return h;
}

cv::Mat decode(const sensor_msgs::CompressedImage& msg) {
  std::string error;
  std::optional<cv::Mat> image = compressedImageFromMsg(msg, &error);
  EXPECT_TRUE(image) << error;
  return image ? *image : cv::Mat();
}

double meanAbsDiff(const cv::Mat& a, const cv::Mat& b) { return cv::norm(a, b, cv::NORM_L1) / double(a.total() * a.channels()); }

}  // namespace

TEST(CompressedImageConversions, JpegKeepsColourAndGreyCloseToTheOriginal) {
  for (int channels : {1, 3}) {
    const cv::Mat image = smoothImage(48, 64, channels);
    const sensor_msgs::CompressedImage msg = compressedImageToMsg(image, header(), "jpeg");
    const std::string enc = channels == 1 ? "mono8" : "bgr8";
    EXPECT_EQ(msg.format, enc + "; jpeg compressed " + enc);
    EXPECT_EQ(msg.header.frame_id, "camera");
    const cv::Mat back = decode(msg);
    ASSERT_EQ(back.type(), image.type());
    EXPECT_LT(meanAbsDiff(back, image), 3.0);
  }
}

TEST(CompressedImageConversions, PngIsLosslessForEveryImageType) {
  for (int type : {CV_8UC1, CV_8UC3, CV_8UC4, CV_16UC1}) {
    const cv::Mat image = randomImage(21, 17, type);
    const cv::Mat back = decode(compressedImageToMsg(image, header(), "png"));
    EXPECT_TRUE(sameBits(back, image)) << "type " << type;
  }
  EXPECT_THROW(compressedImageToMsg(randomImage(4, 4, CV_8UC4), header(), "jpeg"), rtabmap::FormatError);
  EXPECT_THROW(compressedImageToMsg(randomImage(4, 4, CV_32FC1), header(), "png"), rtabmap::FormatError);
  EXPECT_THROW(compressedImageToMsg(randomImage(4, 4, CV_8UC3), header(), "webp"), rtabmap::FormatError);
}

TEST(CompressedImageConversions, CompressedDepth16IsLosslessWithTheTransportHeader) {
  const cv::Mat depth = randomImage(30, 40, CV_16UC1);
  const sensor_msgs::CompressedImage msg = compressedDepthToMsg(depth, header());
  EXPECT_EQ(msg.format, "16UC1; compressedDepth png");
  ASSERT_GT(msg.data.size(), 12u);
  // After the 12-byte header comes a plain PNG, as compressed_depth_image_transport writes it.
  EXPECT_EQ(msg.data[12], 0x89);
  EXPECT_EQ(msg.data[13], 'P');
  EXPECT_TRUE(sameBits(decode(msg), depth));
}

TEST(CompressedImageConversions, CompressedDepth32QuantisesInverseDepth) {
  cv::Mat depth(4, 5, CV_32FC1);
  const float values[] = {0.5f, 1.0f, 2.0f, 3.3f, 9.5f};
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 5; ++c) depth.at<float>(r, c) = values[c] * (1.0f + 0.01f * r);
  }
  depth.at<float>(0, 0) = std::numeric_limits<float>::quiet_NaN();
  depth.at<float>(1, 0) = 0.0f;
  depth.at<float>(2, 0) = 12.0f;  // beyond depthMax (10 m)
  const sensor_msgs::CompressedImage msg = compressedDepthToMsg(depth, header());
  EXPECT_EQ(msg.format, "32FC1; compressedDepth png");
  const cv::Mat back = decode(msg);
  ASSERT_EQ(back.type(), CV_32FC1);
  EXPECT_TRUE(std::isnan(back.at<float>(0, 0)));
  EXPECT_TRUE(std::isnan(back.at<float>(1, 0)));
  EXPECT_TRUE(std::isnan(back.at<float>(2, 0)));
  for (int r = 0; r < 4; ++r) {
    for (int c = 1; c < 5; ++c) {
      const float z = depth.at<float>(r, c);
      // One quantisation step of q = A/z + B is dz = z^2 / A (A = 100 * 101).
      EXPECT_NEAR(back.at<float>(r, c), z, z * z / 10100.0f + 1e-4f) << "z=" << z;
    }
  }
}

TEST(CompressedImageConversions, DecodesACompressedDepthMessageBuiltByHand) {
  // The transport's own layout, written independently of our encoder: int32 0, float A, float B,
  // then the PNG of q = A / z + B.
  const float a = 42.0f * 43.0f, b = 1.0f - a / 5.0f;
  cv::Mat q(1, 3, CV_16UC1);
  q.at<uint16_t>(0, 0) = 0;
  q.at<uint16_t>(0, 1) = static_cast<uint16_t>(a / 1.0f + b);
  q.at<uint16_t>(0, 2) = static_cast<uint16_t>(a / 2.5f + b);
  std::vector<uint8_t> png;
  cv::imencode(".png", q, png);
  sensor_msgs::CompressedImage msg;
  msg.format = "32FC1; compressedDepth png";
  msg.data.resize(12);
  const int32_t format = 0;
  std::memcpy(&msg.data[0], &format, 4);
  std::memcpy(&msg.data[4], &a, 4);
  std::memcpy(&msg.data[8], &b, 4);
  msg.data.insert(msg.data.end(), png.begin(), png.end());
  const cv::Mat depth = decode(msg);
  ASSERT_EQ(depth.size(), cv::Size(3, 1));
  EXPECT_TRUE(std::isnan(depth.at<float>(0, 0)));
  EXPECT_NEAR(depth.at<float>(0, 1), 1.0f, 1e-3f);
  EXPECT_NEAR(depth.at<float>(0, 2), 2.5f, 5e-3f);

  msg.format = "16UC1; compressedDepth";  // the older format string, without the codec name
  const cv::Mat raw = decode(msg);
  EXPECT_TRUE(sameBits(raw, q));
}

TEST(CompressedImageConversions, LosslessFloatDepthUsesTheZlibBlob) {
  cv::Mat depth = randomImage(11, 13, CV_32FC1);
  depth.at<float>(2, 2) = std::numeric_limits<float>::quiet_NaN();
  const sensor_msgs::CompressedImage msg = compressedDepthLosslessToMsg(depth, header());
  EXPECT_EQ(msg.format, "32FC1; rtabmap zlib");
  EXPECT_TRUE(sameBits(decode(msg), depth));
  const cv::Mat depth16 = randomImage(11, 13, CV_16UC1);
  EXPECT_TRUE(sameBits(decode(compressedDepthLosslessToMsg(depth16, header())), depth16));
}

TEST(CompressedImageConversions, CoreBytesArePassedThroughAndDecodeToTheSameImage) {
  const cv::Mat colour = smoothImage(24, 32, 3);
  const rtabmap::Bytes jpeg = rtabmap::codec::compressImage(colour, ".jpg");
  sensor_msgs::CompressedImage msg = compressedBytesToMsg(jpeg, header(), false);
  EXPECT_EQ(msg.format, "jpeg");
  EXPECT_EQ(msg.data, jpeg);
  EXPECT_TRUE(sameBits(decode(msg), rtabmap::codec::uncompressImage(jpeg)));

  const cv::Mat depth16 = randomImage(9, 7, CV_16UC1);
  msg = compressedBytesToMsg(rtabmap::codec::compressDepth(depth16), header(), true);
  EXPECT_EQ(msg.format, "16UC1; compressedDepth png");
  EXPECT_TRUE(sameBits(decode(msg), depth16));

  const cv::Mat depth32 = randomImage(9, 7, CV_32FC1);
  msg = compressedBytesToMsg(rtabmap::codec::compressDepth(depth32), header(), true);
  EXPECT_EQ(msg.format, "rtabmap zlib");
  EXPECT_TRUE(sameBits(decode(msg), depth32));

  const cv::Mat grey = randomImage(9, 7, CV_8UC1);
  msg = compressedBytesToMsg(rtabmap::codec::compressImage(grey, ".png"), header(), false);
  EXPECT_EQ(msg.format, "png");
  EXPECT_TRUE(sameBits(decode(msg), grey));

  EXPECT_THROW(compressedBytesToMsg(rtabmap::Bytes{1, 2, 3}, header(), false), rtabmap::FormatError);
}

TEST(CompressedImageConversions, BadMessagesGiveClearErrors) {
  std::string error;
  sensor_msgs::CompressedImage msg = compressedImageToMsg(smoothImage(16, 16, 3), header(), "jpeg");

  sensor_msgs::CompressedImage empty = msg;
  empty.data.clear();
  EXPECT_FALSE(compressedImageFromMsg(empty, &error));
  EXPECT_NE(error.find("no data"), std::string::npos) << error;

  sensor_msgs::CompressedImage truncated = msg;
  truncated.data.resize(truncated.data.size() / 2);
  EXPECT_FALSE(compressedImageFromMsg(truncated, &error));
  EXPECT_NE(error.find("corrupt"), std::string::npos) << error;

  sensor_msgs::CompressedImage unknown = msg;
  unknown.format = "bgr8; webp compressed bgr8";
  EXPECT_FALSE(compressedImageFromMsg(unknown, &error));
  EXPECT_NE(error.find("unknown format"), std::string::npos) << error;

  sensor_msgs::CompressedImage depth = compressedDepthToMsg(randomImage(8, 8, CV_16UC1), header());
  sensor_msgs::CompressedImage rvl = depth;
  rvl.format = "16UC1; compressedDepth rvl";
  EXPECT_FALSE(compressedImageFromMsg(rvl, &error));
  EXPECT_NE(error.find("RVL"), std::string::npos) << error;

  sensor_msgs::CompressedImage headerOnly = depth;
  headerOnly.data.resize(12);
  EXPECT_FALSE(compressedImageFromMsg(headerOnly, &error));
  EXPECT_NE(error.find("12-byte header"), std::string::npos) << error;

  sensor_msgs::CompressedImage eightBit = depth;  // a compressedDepth png holding 8-bit grey
  const rtabmap::Bytes png8 = rtabmap::codec::compressImage(randomImage(8, 8, CV_8UC1), ".png");
  eightBit.data.resize(12);
  eightBit.data.insert(eightBit.data.end(), png8.begin(), png8.end());
  EXPECT_FALSE(compressedImageFromMsg(eightBit, &error));
  EXPECT_NE(error.find("16-bit"), std::string::npos) << error;

  sensor_msgs::CompressedImage wrongEncoding = depth;
  wrongEncoding.format = "bgr8; compressedDepth png";
  EXPECT_FALSE(compressedImageFromMsg(wrongEncoding, &error));
  EXPECT_NE(error.find("bgr8"), std::string::npos) << error;
}
