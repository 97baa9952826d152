#include "rtabmap_conversions/ImageConversions.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>
#include <sensor_msgs/image_encodings.h>

#include <limits>

#include "TestHelpers.h"
#include "rtabmap_core/common/Error.h"

using namespace rtabmap_conversions;
using rtabmap_conversions::test::randomImage;
using rtabmap_conversions::test::sameBits;
namespace enc = sensor_msgs::image_encodings;

namespace {

std_msgs::Header header(const std::string& frame = "camera") {
  std_msgs::Header h;
  h.frame_id = frame;
  h.stamp = ros::Time(12, 345);
  return h;
}

}  // namespace

TEST(ImageConversions, EveryCoreTypeRoundTripsBitExactly) {
  for (int type : {CV_8UC1, CV_8UC3, CV_8UC4, CV_16UC1, CV_32FC1}) {
    cv::Mat image = randomImage(37, 53, type, unsigned(type) + 1);
    if (type == CV_32FC1) image.at<float>(3, 4) = std::numeric_limits<float>::quiet_NaN();
    const sensor_msgs::Image msg = imageToMsg(image, header());
    EXPECT_EQ(msg.header.frame_id, "camera");
    EXPECT_EQ(msg.header.stamp, ros::Time(12, 345));
    EXPECT_EQ(msg.encoding, imageEncoding(type));
    std::string error;
    const std::optional<cv::Mat> back = imageFromMsg(msg, &error);
    ASSERT_TRUE(back) << error;
    EXPECT_TRUE(sameBits(*back, image)) << "type " << type;
  }
}

TEST(ImageConversions, EncodingsOfTheCore) {
  EXPECT_EQ(imageEncoding(CV_8UC1), "mono8");
  EXPECT_EQ(imageEncoding(CV_8UC3), "bgr8");
  EXPECT_EQ(imageEncoding(CV_8UC4), "bgra8");
  EXPECT_EQ(imageEncoding(CV_16UC1), "16UC1");
  EXPECT_EQ(imageEncoding(CV_32FC1), "32FC1");
  EXPECT_EQ(imageEncoding(CV_64FC3), "");
  EXPECT_THROW(imageToMsg(cv::Mat(2, 2, CV_64FC3), header()), rtabmap::FormatError);
  EXPECT_THROW(imageToMsg(cv::Mat(), header()), rtabmap::FormatError);
}

TEST(ImageConversions, RgbIsConvertedToBgrAndRgbaToBgra) {
  const cv::Mat bgr = randomImage(8, 9, CV_8UC3);
  sensor_msgs::Image msg = imageToMsg(bgr, header());
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  std::memcpy(msg.data.data(), rgb.data, msg.data.size());
  msg.encoding = enc::RGB8;
  std::optional<cv::Mat> back = colorFromMsg(msg);
  ASSERT_TRUE(back);
  EXPECT_TRUE(sameBits(*back, bgr));

  const cv::Mat bgra = randomImage(8, 9, CV_8UC4);
  msg = imageToMsg(bgra, header());
  cv::Mat rgba;
  cv::cvtColor(bgra, rgba, cv::COLOR_BGRA2RGBA);
  std::memcpy(msg.data.data(), rgba.data, msg.data.size());
  msg.encoding = enc::RGBA8;
  back = colorFromMsg(msg);
  ASSERT_TRUE(back);
  EXPECT_TRUE(sameBits(*back, bgra));
}

TEST(ImageConversions, Mono16IsDepthInMillimetresUnchanged) {
  const cv::Mat depth = randomImage(10, 12, CV_16UC1);
  sensor_msgs::Image msg = imageToMsg(depth, header());
  msg.encoding = enc::MONO16;
  const std::optional<cv::Mat> back = depthFromMsg(msg);
  ASSERT_TRUE(back);
  EXPECT_TRUE(sameBits(*back, depth));  // no scaling: mono16 and 16UC1 are the same bytes
}

TEST(ImageConversions, BayerBecomesColour) {
  sensor_msgs::Image msg = imageToMsg(randomImage(16, 16, CV_8UC1), header());
  msg.encoding = enc::BAYER_RGGB8;
  const std::optional<cv::Mat> back = colorFromMsg(msg);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->type(), CV_8UC3);
  EXPECT_EQ(back->size(), cv::Size(16, 16));
}

TEST(ImageConversions, PaddedRowsAreRead) {
  const cv::Mat image = randomImage(5, 7, CV_16UC1);
  sensor_msgs::Image msg;
  msg.header = header();
  msg.width = 7;
  msg.height = 5;
  msg.encoding = enc::TYPE_16UC1;
  msg.step = 7 * 2 + 6;  // 6 bytes of padding per row
  msg.data.assign(msg.step * msg.height, 0xAB);
  for (int r = 0; r < 5; ++r) std::memcpy(&msg.data[r * msg.step], image.ptr(r), 14);
  const std::optional<cv::Mat> back = depthFromMsg(msg);
  ASSERT_TRUE(back);
  EXPECT_TRUE(sameBits(*back, image));
}

TEST(ImageConversions, BigEndianDepthIsSwapped) {
  cv::Mat depth(2, 3, CV_16UC1);
  for (int i = 0; i < 6; ++i) depth.at<uint16_t>(i / 3, i % 3) = static_cast<uint16_t>(1000 + 257 * i);
  sensor_msgs::Image msg = imageToMsg(depth, header());
  msg.is_bigendian = 1;
  for (size_t i = 0; i + 1 < msg.data.size(); i += 2) std::swap(msg.data[i], msg.data[i + 1]);
  const std::optional<cv::Mat> back = depthFromMsg(msg);
  ASSERT_TRUE(back);
  EXPECT_TRUE(sameBits(*back, depth));
}

TEST(ImageConversions, WrongEncodingsAreRefusedByName) {
  std::string error;
  sensor_msgs::Image colour = imageToMsg(randomImage(4, 4, CV_8UC3), header("cam"));
  EXPECT_FALSE(depthFromMsg(colour, &error));
  EXPECT_NE(error.find("bgr8"), std::string::npos) << error;
  EXPECT_NE(error.find("16UC1"), std::string::npos) << error;
  EXPECT_NE(error.find("'cam'"), std::string::npos) << error;

  sensor_msgs::Image depth = imageToMsg(randomImage(4, 4, CV_16UC1), header());
  EXPECT_FALSE(colorFromMsg(depth, &error));
  EXPECT_NE(error.find("16UC1"), std::string::npos) << error;

  sensor_msgs::Image unknown = colour;
  unknown.encoding = "yuv9000";
  EXPECT_FALSE(imageFromMsg(unknown, &error));
  EXPECT_NE(error.find("yuv9000"), std::string::npos) << error;
}

TEST(ImageConversions, SizeMismatchesAreErrorsNotReadsPastTheBuffer) {
  std::string error;
  sensor_msgs::Image msg = imageToMsg(randomImage(20, 30, CV_8UC3), header());
  sensor_msgs::Image shortData = msg;
  shortData.data.resize(shortData.data.size() - 1);
  EXPECT_FALSE(imageFromMsg(shortData, &error));
  EXPECT_NE(error.find("data bytes"), std::string::npos) << error;

  sensor_msgs::Image shortStep = msg;
  shortStep.step = 30 * 3 - 1;
  EXPECT_FALSE(imageFromMsg(shortStep, &error));
  EXPECT_NE(error.find("step"), std::string::npos) << error;

  sensor_msgs::Image wider = msg;
  wider.width = 31;  // claims more pixels than the step holds
  EXPECT_FALSE(imageFromMsg(wider, &error));

  sensor_msgs::Image empty;
  empty.encoding = enc::MONO8;
  EXPECT_FALSE(imageFromMsg(empty, &error));
  EXPECT_NE(error.find("empty"), std::string::npos) << error;

  sensor_msgs::Image huge = msg;
  huge.height = 4000000000u;  // step * height overflows 32 bits: must still be refused
  EXPECT_FALSE(imageFromMsg(huge, &error));
}
