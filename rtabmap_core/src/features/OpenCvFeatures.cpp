#include "OpenCvFeatures.h"

#include <algorithm>
#include <cmath>

#include "BriefDescriptor.h"

namespace rtabmap::features_detail {
namespace {

int getInt(const ParametersMap& p, const std::string& key) { return Parameters::getInt(p, key); }
double getDouble(const ParametersMap& p, const std::string& key) { return Parameters::getDouble(p, key); }
bool getBool(const ParametersMap& p, const std::string& key) { return Parameters::getBool(p, key); }

cv::Ptr<cv::ORB> makeOrb(const ParametersMap& p, int maxKeypoints) {
  // ORB's own count limit; "no limit" is a count no image reaches.
  const int n = maxKeypoints > 0 ? maxKeypoints : 1000000;
  return cv::ORB::create(n, static_cast<float>(getDouble(p, "ORB/ScaleFactor")), getInt(p, "ORB/NLevels"),
                         getInt(p, "ORB/EdgeThreshold"), getInt(p, "ORB/FirstLevel"), getInt(p, "ORB/WTA_K"),
                         getInt(p, "ORB/ScoreType") == 1 ? cv::ORB::FAST_SCORE : cv::ORB::HARRIS_SCORE,
                         getInt(p, "ORB/PatchSize"));
}

cv::KAZE::DiffusivityType diffusivity(const ParametersMap& p) {
  return static_cast<cv::KAZE::DiffusivityType>(getInt(p, "KAZE/Diffusivity"));
}

void keepStrongest(std::vector<cv::KeyPoint>& keypoints, int maxKeypoints) {
  if (maxKeypoints > 0 && static_cast<int>(keypoints.size()) > maxKeypoints) {
    cv::KeyPointsFilter::retainBest(keypoints, maxKeypoints);
    // retainBest keeps ties at the cut: trim to the exact count.
    if (static_cast<int>(keypoints.size()) > maxKeypoints) {
      std::stable_sort(keypoints.begin(), keypoints.end(),
                       [](const cv::KeyPoint& a, const cv::KeyPoint& b) { return a.response > b.response; });
      keypoints.resize(static_cast<size_t>(maxKeypoints));
    }
  }
}

}  // namespace

OpenCvFeatures::OpenCvFeatures(FeatureType type, const ParametersMap& p) : type_(type), p_(p) {
  switch (type) {
    case FeatureType::kSIFT:
      detector_ = cv::SIFT::create(getInt(p, "SIFT/NFeatures"), getInt(p, "SIFT/NOctaveLayers"),
                                   getDouble(p, "SIFT/ContrastThreshold"), getDouble(p, "SIFT/EdgeThreshold"),
                                   getDouble(p, "SIFT/Sigma"));
      descriptor_ = detector_;
      rootSift_ = getBool(p, "SIFT/RootSIFT");
      break;
    case FeatureType::kORB:
    case FeatureType::kGfttOrb:
      descriptor_ = makeOrb(p, 0);
      break;
    case FeatureType::kFastBrief:
    case FeatureType::kGfttBrief:
      descriptor_ = cv::makePtr<BriefDescriptor>(getInt(p, "BRIEF/Bytes"));
      break;
    case FeatureType::kBRISK:
      detector_ = cv::BRISK::create(getInt(p, "BRISK/Thresh"), getInt(p, "BRISK/Octaves"),
                                    static_cast<float>(getDouble(p, "BRISK/PatternScale")));
      descriptor_ = detector_;
      break;
    case FeatureType::kKAZE:
      detector_ = cv::KAZE::create(getBool(p, "KAZE/Extended"), getBool(p, "KAZE/Upright"),
                                   static_cast<float>(getDouble(p, "KAZE/Threshold")), getInt(p, "KAZE/NOctaves"),
                                   getInt(p, "KAZE/NOctaveLayers"), diffusivity(p));
      descriptor_ = detector_;
      break;
    case FeatureType::kAKAZE:
      detector_ = cv::AKAZE::create(
          getBool(p, "KAZE/Upright") ? cv::AKAZE::DESCRIPTOR_MLDB_UPRIGHT : cv::AKAZE::DESCRIPTOR_MLDB, 0, 3,
          static_cast<float>(getDouble(p, "KAZE/Threshold")), getInt(p, "KAZE/NOctaves"),
          getInt(p, "KAZE/NOctaveLayers"), diffusivity(p));
      descriptor_ = detector_;
      break;
  }
}

std::vector<cv::KeyPoint> OpenCvFeatures::detectFast(const cv::Mat& grey, const cv::Mat& mask,
                                                     int maxKeypoints) const {
  const int threshold = getInt(p_, "FAST/Threshold");
  const bool nonmax = getBool(p_, "FAST/NonmaxSuppression");
  const int rows = getInt(p_, "FAST/GridRows");
  const int cols = getInt(p_, "FAST/GridCols");
  std::vector<cv::KeyPoint> keypoints;
  if (rows <= 0 || cols <= 0 || maxKeypoints <= 0) {
    cv::FastFeatureDetector::create(threshold, nonmax)->detect(grey, keypoints, mask);
    keepStrongest(keypoints, maxKeypoints);
    return keypoints;
  }
  // Per-cell threshold adaptation: a low-contrast cell lowers its threshold (down to
  // FAST/MinThreshold) until it has its share of keypoints, a busy one raises it (up to
  // FAST/MaxThreshold), so texture-poor parts of the image still get corners.
  const int minT = getInt(p_, "FAST/MinThreshold");
  const int maxT = std::max(minT, getInt(p_, "FAST/MaxThreshold"));
  const int target = std::max(1, maxKeypoints / (rows * cols));
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const cv::Rect cell(c * grey.cols / cols, r * grey.rows / rows,
                          (c + 1) * grey.cols / cols - c * grey.cols / cols,
                          (r + 1) * grey.rows / rows - r * grey.rows / rows);
      if (cell.width <= 0 || cell.height <= 0) continue;
      const cv::Mat cellMask = mask.empty() ? cv::Mat() : mask(cell);
      int t = std::clamp(threshold, minT, maxT);
      std::vector<cv::KeyPoint> cellKeypoints;
      for (int attempt = 0; attempt < 5; ++attempt) {
        cellKeypoints.clear();
        cv::FastFeatureDetector::create(t, nonmax)->detect(grey(cell), cellKeypoints, cellMask);
        const int n = static_cast<int>(cellKeypoints.size());
        if (n < target && t > minT) {
          t = std::max(minT, t / 2);
        } else if (n > 2 * target && t < maxT) {
          t = std::min(maxT, t + t / 2 + 1);
        } else {
          break;
        }
      }
      keepStrongest(cellKeypoints, target);
      for (cv::KeyPoint& k : cellKeypoints) {
        k.pt.x += static_cast<float>(cell.x);
        k.pt.y += static_cast<float>(cell.y);
        keypoints.push_back(k);
      }
    }
  }
  keepStrongest(keypoints, maxKeypoints);
  return keypoints;
}

std::vector<cv::KeyPoint> OpenCvFeatures::detect(const cv::Mat& grey, const cv::Mat& mask, int maxKeypoints) const {
  std::vector<cv::KeyPoint> keypoints;
  switch (type_) {
    case FeatureType::kGfttOrb:
    case FeatureType::kGfttBrief: {
      // GFTT returns its corners by decreasing quality, at most maxCorners (<= 0: all).
      cv::Ptr<cv::GFTTDetector> gftt = cv::GFTTDetector::create(
          maxKeypoints, getDouble(p_, "GFTT/QualityLevel"), getDouble(p_, "GFTT/MinDistance"),
          getInt(p_, "GFTT/BlockSize"), getBool(p_, "GFTT/UseHarrisDetector"), getDouble(p_, "GFTT/K"));
      gftt->detect(grey, keypoints, mask);
      break;
    }
    case FeatureType::kORB:
      makeOrb(p_, maxKeypoints)->detect(grey, keypoints, mask);
      break;
    case FeatureType::kFastBrief:
      return detectFast(grey, mask, maxKeypoints);
    default:
      detector_->detect(grey, keypoints, mask);
      break;
  }
  keepStrongest(keypoints, maxKeypoints);
  return keypoints;
}

cv::Mat OpenCvFeatures::compute(const cv::Mat& grey, std::vector<cv::KeyPoint>& keypoints) const {
  cv::Mat descriptors;
  if (keypoints.empty()) return descriptors;
  descriptor_->compute(grey, keypoints, descriptors);
  if (rootSift_ && !descriptors.empty()) {
    // RootSIFT (Arandjelovic & Zisserman, CVPR 2012): L1-normalise then square-root, so the
    // Euclidean distance between descriptors becomes the Hellinger kernel of the originals.
    for (int i = 0; i < descriptors.rows; ++i) {
      cv::Mat row = descriptors.row(i);
      const double l1 = cv::norm(row, cv::NORM_L1);
      if (l1 > 0.0) row /= l1;
      cv::sqrt(row, row);
    }
  }
  return descriptors;
}

}  // namespace rtabmap::features_detail
