#include "rtabmap_core/codec/Compression.h"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <fstream>
#include <iterator>
#include <random>

#include "common/TestData.h"
#include "rtabmap_core/common/Error.h"

using rtabmap::Bytes;
using rtabmap::FormatError;
namespace codec = rtabmap::codec;

namespace {

cv::Mat randomMat(int rows, int cols, int type, uint64 seed) {
  cv::Mat m(rows, cols, type);
  cv::RNG rng(seed);
  cv::Mat flat = m.reshape(1);  // one channel view: RNG::fill takes at most 4 channels
  if (CV_MAT_DEPTH(type) == CV_32F || CV_MAT_DEPTH(type) == CV_64F) {
    rng.fill(flat, cv::RNG::UNIFORM, cv::Scalar::all(-1000), cv::Scalar::all(1000));
  } else {
    rng.fill(flat, cv::RNG::UNIFORM, cv::Scalar::all(0), cv::Scalar::all(255));
  }
  return m;
}

// Smooth content compresses like a real image; random noise would not exercise the codecs.
cv::Mat gradientImage(int rows, int cols, int type) {
  cv::Mat m(rows, cols, type);
  const int cn = CV_MAT_CN(type);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      for (int k = 0; k < cn; ++k) {
        const double v = 128 + 100 * std::sin(0.05 * c + 0.07 * r + k);
        if (CV_MAT_DEPTH(type) == CV_8U) {
          m.ptr<uchar>(r)[c * cn + k] = cv::saturate_cast<uchar>(v);
        } else {
          m.ptr<ushort>(r)[c * cn + k] = cv::saturate_cast<ushort>(v * 100);
        }
      }
    }
  }
  return m;
}

bool identical(const cv::Mat& a, const cv::Mat& b) {
  if (a.type() != b.type() || a.size() != b.size()) return false;
  if (a.empty()) return true;
  for (int r = 0; r < a.rows; ++r) {
    if (std::memcmp(a.ptr(r), b.ptr(r), a.cols * a.elemSize()) != 0) return false;
  }
  return true;
}

Bytes readFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

}  // namespace

TEST(Codec, CompressDataRoundTripsEveryType) {
  int n = 0;
  for (int depth : {CV_8U, CV_8S, CV_16U, CV_16S, CV_32S, CV_32F, CV_64F}) {
    for (int cn : {1, 2, 3, 4}) {
      const int type = CV_MAKETYPE(depth, cn);
      for (cv::Size size : {cv::Size(1, 1), cv::Size(17, 3), cv::Size(160, 120), cv::Size(1000, 1)}) {
        const cv::Mat m = randomMat(size.height, size.width, type, ++n);
        const Bytes bytes = codec::compressData(m);
        ASSERT_FALSE(bytes.empty());
        EXPECT_TRUE(codec::isCompressedData(bytes));
        const cv::Mat back = codec::uncompressData(bytes);
        EXPECT_TRUE(identical(back, m)) << "type " << type << " size " << size;
        const cv::Mat back2 = codec::uncompressData(bytes.data(), bytes.size());
        EXPECT_TRUE(identical(back2, m));
      }
    }
  }
  // Many channels (descriptors, scans with normals) too.
  const cv::Mat scan = randomMat(1, 500, CV_32FC(7), 99);
  EXPECT_TRUE(identical(codec::uncompressData(codec::compressData(scan)), scan));
}

TEST(Codec, CompressDataKeepsNanAndSpecialFloats) {
  cv::Mat m = (cv::Mat_<float>(1, 6) << std::numeric_limits<float>::quiet_NaN(), INFINITY, -INFINITY,
               -0.0f, std::numeric_limits<float>::denorm_min(), 1.0f);
  EXPECT_TRUE(identical(codec::uncompressData(codec::compressData(m)), m));
}

TEST(Codec, NonContinuousRoi) {
  const cv::Mat big = randomMat(100, 120, CV_32FC3, 7);
  const cv::Mat roi = big(cv::Rect(10, 20, 50, 30));
  ASSERT_FALSE(roi.isContinuous());
  EXPECT_TRUE(identical(codec::uncompressData(codec::compressData(roi)), roi));

  const cv::Mat img = gradientImage(100, 120, CV_8UC3);
  const cv::Mat imgRoi = img(cv::Rect(5, 5, 64, 48));
  ASSERT_FALSE(imgRoi.isContinuous());
  EXPECT_TRUE(identical(codec::uncompressImage(codec::compressImage(imgRoi, ".png")), imgRoi));

  const cv::Mat depth = gradientImage(100, 120, CV_16UC1);
  const cv::Mat depthRoi = depth(cv::Rect(1, 2, 33, 44));
  EXPECT_TRUE(identical(codec::uncompressDepth(codec::compressDepth(depthRoi)), depthRoi));
}

TEST(Codec, EmptyInputs) {
  EXPECT_TRUE(codec::compressData(cv::Mat()).empty());
  EXPECT_TRUE(codec::compressImage(cv::Mat()).empty());
  EXPECT_TRUE(codec::compressDepth(cv::Mat()).empty());
  EXPECT_TRUE(codec::compressBytes(Bytes()).empty());
  EXPECT_TRUE(codec::uncompressData(Bytes()).empty());
  EXPECT_TRUE(codec::uncompressData(nullptr, 0).empty());
  EXPECT_TRUE(codec::uncompressImage(Bytes()).empty());
  EXPECT_TRUE(codec::uncompressDepth(Bytes()).empty());
  EXPECT_TRUE(codec::uncompressBytes(Bytes()).empty());
  EXPECT_TRUE(codec::uncompressAny(Bytes()).empty());
}

TEST(Codec, ImagePngLosslessJpgClose) {
  for (int type : {CV_8UC1, CV_8UC3, CV_8UC4, CV_16UC1, CV_16UC3, CV_16UC4}) {
    const cv::Mat m = gradientImage(48, 64, type);
    const Bytes png = codec::compressImage(m, ".png");
    const cv::Mat back = codec::uncompressImage(png);
    EXPECT_TRUE(identical(back, m)) << "type " << type;
    EXPECT_TRUE(identical(codec::uncompressAny(png), m));
    EXPECT_FALSE(codec::isCompressedData(png));
  }
  for (int type : {CV_8UC1, CV_8UC3}) {
    const cv::Mat m = gradientImage(240, 320, type);
    for (const char* f : {".jpg", "jpg", ".JPEG"}) {
      const Bytes jpg = codec::compressImage(m, f);
      const cv::Mat back = codec::uncompressImage(jpg);
      ASSERT_EQ(back.type(), m.type());
      ASSERT_EQ(back.size(), m.size());
      cv::Mat diff;
      cv::absdiff(back, m, diff);
      EXPECT_LT(cv::mean(diff)[0], 2.0);
      EXPECT_LT(jpg.size(), m.total() * m.elemSize() / 4) << "jpeg should compress a smooth image";
    }
  }
}

TEST(Codec, CompressImageRefusesWhatItCannotHold) {
  const cv::Mat f32(10, 10, CV_32FC1, cv::Scalar(1.5));
  try {
    codec::compressImage(f32, ".png");
    ADD_FAILURE() << "32F accepted";
  } catch (const FormatError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("compressData"), std::string::npos) << what;
    EXPECT_NE(what.find("compressDepth"), std::string::npos) << what;
  }
  EXPECT_THROW(codec::compressImage(cv::Mat(10, 10, CV_64FC1, cv::Scalar(0)), ".png"), FormatError);
  EXPECT_THROW(codec::compressImage(cv::Mat(10, 10, CV_16UC1, cv::Scalar(1)), ".jpg"), FormatError);
  EXPECT_THROW(codec::compressImage(cv::Mat(10, 10, CV_8UC4, cv::Scalar(1)), ".jpg"), FormatError);
  EXPECT_THROW(codec::compressImage(cv::Mat(10, 10, CV_8UC2, cv::Scalar(1)), ".png"), FormatError);
  EXPECT_THROW(codec::compressImage(cv::Mat(10, 10, CV_32SC1, cv::Scalar(1)), ".png"), FormatError);
  EXPECT_THROW(codec::compressImage(cv::Mat(10, 10, CV_8UC1, cv::Scalar(1)), ".nosuchformat"), FormatError);
  EXPECT_THROW(codec::compressDepth(cv::Mat(10, 10, CV_8UC1, cv::Scalar(1))), FormatError);
  EXPECT_THROW(codec::compressDepth(cv::Mat(10, 10, CV_32FC2, cv::Scalar(1))), FormatError);
}

TEST(Codec, DepthBitExact) {
  cv::Mat mm = gradientImage(480, 640, CV_16UC1);
  mm(cv::Rect(0, 0, 50, 50)).setTo(0);
  mm(cv::Rect(100, 100, 20, 20)).setTo(65535);
  const Bytes png = codec::compressDepth(mm);
  EXPECT_TRUE(identical(codec::uncompressDepth(png), mm));

  cv::Mat m = randomMat(480, 640, CV_32FC1, 3);
  m.at<float>(0, 0) = std::numeric_limits<float>::quiet_NaN();
  m.at<float>(1, 0) = 0.0f;
  const Bytes z = codec::compressDepth(m);
  EXPECT_TRUE(codec::isCompressedData(z));
  EXPECT_TRUE(identical(codec::uncompressDepth(z), m));
  EXPECT_TRUE(identical(codec::uncompressAny(z), m));

  // A png that is not a depth image is refused by uncompressDepth.
  EXPECT_THROW(codec::uncompressDepth(codec::compressImage(gradientImage(8, 8, CV_8UC3), ".png")),
               FormatError);
  EXPECT_THROW(codec::uncompressDepth(codec::compressData(cv::Mat(3, 3, CV_8UC1, cv::Scalar(1)))),
               FormatError);
}

TEST(Codec, BytesRoundTrip) {
  std::string text;
  for (int i = 0; i < 1000; ++i) text += "Rtabmap/DetectionRate=1;Mem/STMSize=" + std::to_string(i) + ";";
  const Bytes raw(text.begin(), text.end());
  const Bytes z = codec::compressBytes(raw);
  EXPECT_LT(z.size(), raw.size() / 5);
  EXPECT_EQ(codec::uncompressBytes(z), raw);
  const Bytes one{42};
  EXPECT_EQ(codec::uncompressBytes(codec::compressBytes(one)), one);
}

TEST(Codec, CorruptAndTruncatedDataThrow) {
  const cv::Mat m = randomMat(64, 64, CV_32FC1, 11);
  const Bytes good = codec::compressData(m);
  // Truncation at every length: an exception, never a partial matrix or a crash.
  for (size_t n = 1; n < good.size(); n += (n < 64 ? 1 : 97)) {
    const Bytes cut(good.begin(), good.begin() + n);
    EXPECT_THROW(codec::uncompressData(cut), FormatError) << "length " << n;
  }
  // Header fields.
  auto corrupted = [&](size_t offset, unsigned char value) {
    Bytes b = good;
    b[offset] = value;
    return b;
  };
  EXPECT_THROW(codec::uncompressData(corrupted(0, 'X')), FormatError);   // magic
  EXPECT_THROW(codec::uncompressData(corrupted(3, 9)), FormatError);     // version
  EXPECT_THROW(codec::uncompressData(corrupted(4, 65)), FormatError);    // rows
  EXPECT_THROW(codec::uncompressData(corrupted(11, 0x7f)), FormatError); // cols huge
  EXPECT_THROW(codec::uncompressData(corrupted(12, 0xff)), FormatError); // type
  EXPECT_THROW(codec::uncompressData(corrupted(20, 0xff)), FormatError); // raw size
  // Payload bytes: zlib's adler32 catches them.
  for (size_t offset : {size_t(24), size_t(25), good.size() / 2, good.size() - 1}) {
    Bytes b = good;
    b[offset] ^= 0x5a;
    EXPECT_THROW(codec::uncompressData(b), FormatError) << "offset " << offset;
  }
  // A small blob announcing an enormous matrix is rejected before allocating it.
  Bytes huge = good;
  huge.resize(40);
  const uint32_t big = 0x7fffffff;
  std::memcpy(&huge[4], &big, 4);
  std::memcpy(&huge[8], &big, 4);
  EXPECT_THROW(codec::uncompressData(huge), FormatError);
  // Random garbage, including garbage that starts with the magic.
  std::mt19937 rng(rtabmap::test::drawSeed(12));
  for (int i = 0; i < 200; ++i) {
    Bytes g(1 + rng() % 200);
    for (auto& c : g) c = static_cast<unsigned char>(rng());
    if (i % 2) std::memcpy(g.data(), good.data(), std::min<size_t>(g.size(), 4 + i % 20));
    EXPECT_THROW(codec::uncompressData(g), FormatError);
  }
}

TEST(Codec, CorruptImagesAndBytesThrow) {
  const Bytes png = codec::compressImage(gradientImage(64, 64, CV_8UC3), ".png");
  EXPECT_THROW(codec::uncompressImage(Bytes(png.begin(), png.begin() + png.size() / 2)), FormatError);
  EXPECT_THROW(codec::uncompressImage(Bytes{1, 2, 3, 4, 5}), FormatError);
  // A truncated jpeg decodes (grey bottom) in libjpeg: it must be refused all the same.
  const Bytes jpg = codec::compressImage(gradientImage(64, 64, CV_8UC3), ".jpg");
  EXPECT_THROW(codec::uncompressImage(Bytes(jpg.begin(), jpg.begin() + jpg.size() * 3 / 4)), FormatError);
  EXPECT_THROW(codec::uncompressImage(Bytes(jpg.begin(), jpg.end() - 1)), FormatError);
  Bytes padded = jpg;
  padded.insert(padded.end(), 4, 0);
  EXPECT_EQ(codec::uncompressImage(padded).size(), cv::Size(64, 64));
  EXPECT_THROW(codec::uncompressImage(Bytes{0xFF, 0xD8}), FormatError);
  EXPECT_THROW(codec::uncompressImage(Bytes{0xFF, 0xD8, 0xFF, 0xD9}), FormatError);
  EXPECT_THROW(codec::uncompressDepth(Bytes{1, 2, 3, 4, 5}), FormatError);
  EXPECT_THROW(codec::uncompressAny(Bytes{1, 2, 3, 4, 5}), FormatError);
  const Bytes depthPng = codec::compressDepth(gradientImage(64, 64, CV_16UC1));
  EXPECT_THROW(codec::uncompressDepth(Bytes(depthPng.begin(), depthPng.begin() + 40)), FormatError);

  const Bytes raw(5000, 'a');
  const Bytes z = codec::compressBytes(raw);
  EXPECT_THROW(codec::uncompressBytes(Bytes(z.begin(), z.end() - 1)), FormatError);
  EXPECT_THROW(codec::uncompressBytes(Bytes(z.begin(), z.begin() + 6)), FormatError);
  Bytes bad = z;
  bad[0] = 'Q';
  EXPECT_THROW(codec::uncompressBytes(bad), FormatError);
  bad = z;
  bad[5] ^= 1;  // announced size
  EXPECT_THROW(codec::uncompressBytes(bad), FormatError);
  bad = z;
  bad.back() ^= 0xff;  // adler32
  EXPECT_THROW(codec::uncompressBytes(bad), FormatError);
  // Data blobs are not byte blobs and vice versa.
  EXPECT_THROW(codec::uncompressBytes(codec::compressData(cv::Mat(2, 2, CV_8UC1, cv::Scalar(3)))),
               FormatError);
  EXPECT_THROW(codec::uncompressData(z), FormatError);
}

TEST(Codec, Real7ScenesDepthRoundTripsBitExact) {
  RTABMAP_REQUIRE_DATA(path, "rgbd_7scenes/frame-000000.depth.png");
  const Bytes file = readFile(path);
  const cv::Mat depth = codec::uncompressImage(file);
  ASSERT_EQ(depth.type(), CV_16UC1);
  ASSERT_EQ(depth.size(), cv::Size(640, 480));
  EXPECT_GT(cv::countNonZero(depth != 65535), 1000);
  EXPECT_TRUE(identical(codec::uncompressDepth(file), depth));  // a png file is a depth blob
  const Bytes z = codec::compressDepth(depth);
  EXPECT_TRUE(identical(codec::uncompressDepth(z), depth));
  // As float metres through zlib, bit-exact too.
  cv::Mat metres;
  depth.convertTo(metres, CV_32F, 0.001);
  EXPECT_TRUE(identical(codec::uncompressDepth(codec::compressDepth(metres)), metres));
}

TEST(Codec, Real7ScenesColourJpeg) {
  RTABMAP_REQUIRE_DATA(path, "rgbd_7scenes/frame-000000.color.jpg");
  const cv::Mat rgb = codec::uncompressImage(readFile(path));
  ASSERT_EQ(rgb.type(), CV_8UC3);
  const cv::Mat back = codec::uncompressImage(codec::compressImage(rgb, ".jpg"));
  cv::Mat diff;
  cv::absdiff(back, rgb, diff);
  EXPECT_LT(cv::mean(diff)[0], 3.0);
}
