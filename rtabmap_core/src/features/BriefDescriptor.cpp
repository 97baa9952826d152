#include "BriefDescriptor.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>

namespace rtabmap::features_detail {
namespace {

constexpr int kHalfKernel = BriefDescriptor::kKernelSize / 2;
constexpr int kMaxOffset = BriefDescriptor::kPatchSize / 2 - 1;
// Distance from a keypoint to the image border its tests may read (integral image included).
constexpr int kBorder = kMaxOffset + kHalfKernel + 1;

// Standard normal draws from a generator whose output sequence the C++ standard fixes
// (std::mt19937), through Box-Muller written here: std::normal_distribution differs between
// standard libraries, and the pattern must not.
class PortableNormal {
 public:
  explicit PortableNormal(uint32_t seed) : engine_(seed) {}
  double operator()() {
    const double u1 = (static_cast<double>(engine_()) + 0.5) / 4294967296.0;
    const double u2 = (static_cast<double>(engine_()) + 0.5) / 4294967296.0;
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }

 private:
  std::mt19937 engine_;
};

signed char drawOffset(PortableNormal& normal) {
  const double sigma = BriefDescriptor::kPatchSize / 5.0;
  const double v = std::round(normal() * sigma);
  return static_cast<signed char>(std::clamp(v, -static_cast<double>(kMaxOffset), static_cast<double>(kMaxOffset)));
}

// Sum of the 9 x 9 box centred on (x, y), from a CV_32S integral image.
inline int boxSum(const cv::Mat& integral, int x, int y) {
  const int x0 = x - kHalfKernel, y0 = y - kHalfKernel;
  const int x1 = x + kHalfKernel + 1, y1 = y + kHalfKernel + 1;
  const int* r0 = integral.ptr<int>(y0);
  const int* r1 = integral.ptr<int>(y1);
  return r1[x1] - r1[x0] - r0[x1] + r0[x0];
}

}  // namespace

BriefDescriptor::BriefDescriptor(int bytes) : bytes_(bytes) {
  if (bytes != 16 && bytes != 32 && bytes != 64) {
    throw std::invalid_argument("BRIEF descriptor length must be 16, 32 or 64 bytes, got " + std::to_string(bytes));
  }
  // One fixed seed for every length: a 16-byte pattern is the start of the 32-byte one.
  PortableNormal normal(0x42524945u);  // "BRIE"
  pattern_.resize(static_cast<size_t>(bytes) * 8);
  for (Test& t : pattern_) {
    // Draw until the two points differ: comparing a point with itself carries no information.
    do {
      t.x1 = drawOffset(normal);
      t.y1 = drawOffset(normal);
      t.x2 = drawOffset(normal);
      t.y2 = drawOffset(normal);
    } while (t.x1 == t.x2 && t.y1 == t.y2);
  }
}

void BriefDescriptor::compute(cv::InputArray imageArray, std::vector<cv::KeyPoint>& keypoints,
                              cv::OutputArray descriptorsArray) {
  cv::Mat image = imageArray.getMat();
  if (image.channels() == 3) {
    cv::cvtColor(image, image, cv::COLOR_BGR2GRAY);
  } else if (image.channels() == 4) {
    cv::cvtColor(image, image, cv::COLOR_BGRA2GRAY);
  }
  if (image.type() != CV_8UC1) throw std::invalid_argument("BRIEF needs an 8-bit image");

  // Keep keypoints whose tests and smoothing windows stay inside the image.
  keypoints.erase(std::remove_if(keypoints.begin(), keypoints.end(),
                                 [&](const cv::KeyPoint& k) {
                                   const int x = static_cast<int>(std::floor(k.pt.x + 0.5f));
                                   const int y = static_cast<int>(std::floor(k.pt.y + 0.5f));
                                   return x < kBorder || y < kBorder || x >= image.cols - kBorder ||
                                          y >= image.rows - kBorder;
                                 }),
                  keypoints.end());
  if (keypoints.empty()) {
    descriptorsArray.release();
    return;
  }
  cv::Mat integral;
  cv::integral(image, integral, CV_32S);
  descriptorsArray.create(static_cast<int>(keypoints.size()), bytes_, CV_8U);
  cv::Mat descriptors = descriptorsArray.getMat();
  for (size_t i = 0; i < keypoints.size(); ++i) {
    const int x = static_cast<int>(std::floor(keypoints[i].pt.x + 0.5f));
    const int y = static_cast<int>(std::floor(keypoints[i].pt.y + 0.5f));
    unsigned char* out = descriptors.ptr<unsigned char>(static_cast<int>(i));
    for (int b = 0; b < bytes_; ++b) {
      unsigned char byte = 0;
      for (int bit = 0; bit < 8; ++bit) {
        const Test& t = pattern_[static_cast<size_t>(b * 8 + bit)];
        if (boxSum(integral, x + t.x1, y + t.y1) < boxSum(integral, x + t.x2, y + t.y2)) {
          byte |= static_cast<unsigned char>(1u << bit);
        }
      }
      out[b] = byte;
    }
  }
}

}  // namespace rtabmap::features_detail
