#pragma once
// Distances between two descriptor rows without cv::norm's per-call dispatch, which dominates
// guided matching (tens of thousands of short comparisons per frame).
#include <opencv2/core/mat.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>

namespace rtabmap::registration_detail {

// Hamming distance between two CV_8U rows of `bytes` bytes.
inline int hammingDistance(const unsigned char* a, const unsigned char* b, int bytes) {
  int d = 0;
  int i = 0;
  for (; i + 8 <= bytes; i += 8) {
    uint64_t x, y;
    std::memcpy(&x, a + i, 8);
    std::memcpy(&y, b + i, 8);
    d += __builtin_popcountll(x ^ y);
  }
  for (; i < bytes; ++i) d += __builtin_popcount(static_cast<unsigned>(a[i] ^ b[i]));
  return d;
}

// Euclidean distance between two CV_32F rows of n values.
inline float l2Distance(const float* a, const float* b, int n) {
  float s = 0.0f;
  for (int i = 0; i < n; ++i) {
    const float d = a[i] - b[i];
    s += d * d;
  }
  return std::sqrt(s);
}

// Distance between row i of A and row j of B (binary: Hamming, float: L2).
inline float descriptorDistance(const cv::Mat& A, int i, const cv::Mat& B, int j) {
  if (A.type() == CV_8U) return static_cast<float>(hammingDistance(A.ptr<unsigned char>(i), B.ptr<unsigned char>(j), A.cols));
  return l2Distance(A.ptr<float>(i), B.ptr<float>(j), A.cols);
}

}  // namespace rtabmap::registration_detail
