#pragma once
// BRIEF, the binary descriptor of Calonder, Lepetit, Strecha and Fua (ECCV 2010), written here
// because Debian's OpenCV lacks the xfeatures2d module that holds OpenCV's own.
//
// Each bit compares the smoothed intensity at two points of a S x S patch around the keypoint;
// the point pairs are drawn once, i.i.d. from an isotropic Gaussian of standard deviation S / 5
// (the paper's best sampling strategy, "G II"), from a fixed seed so descriptors stay
// comparable across runs and machines (the database stores them). Smoothing is a 9 x 9 box
// filter read from the integral image: the paper shows box smoothing is as good as Gaussian
// for BRIEF, and it costs 4 reads per test point. Not rotation or scale invariant, which is
// what makes it fast and discriminative enough for frame-to-frame tracking.
#include <opencv2/features2d.hpp>

#include <vector>

namespace rtabmap::features_detail {

class BriefDescriptor : public cv::Feature2D {
 public:
  static constexpr int kPatchSize = 48;
  static constexpr int kKernelSize = 9;

  // bytes: 16, 32 or 64 (std::invalid_argument otherwise).
  explicit BriefDescriptor(int bytes = 32);

  int descriptorSize() const override { return bytes_; }
  int descriptorType() const override { return CV_8U; }
  int defaultNorm() const override { return cv::NORM_HAMMING; }
  cv::String getDefaultName() const override { return "rtabmap.BRIEF"; }

  // Keypoints whose patch (plus the smoothing kernel) leaves the image are removed.
  void compute(cv::InputArray image, std::vector<cv::KeyPoint>& keypoints,
               cv::OutputArray descriptors) override;

  struct Test {
    signed char x1, y1, x2, y2;
  };
  const std::vector<Test>& pattern() const { return pattern_; }

 private:
  int bytes_;
  std::vector<Test> pattern_;
};

}  // namespace rtabmap::features_detail
