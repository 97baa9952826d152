#include "rtabmap_core/features/StereoCorrespondences.h"


#include <cmath>
#include <limits>
#include <stdexcept>

#include "RowFlow.h"
#include "rtabmap_core/geometry/StereoCameraModel.h"

namespace rtabmap {

StereoOptions StereoOptions::fromParameters(const ParametersMap& p) {
  StereoOptions o;
  o.opticalFlow = Parameters::getBool(p, Parameters::kStereoOpticalFlow());
  o.winWidth = Parameters::getInt(p, Parameters::kStereoWinWidth());
  o.winHeight = Parameters::getInt(p, Parameters::kStereoWinHeight());
  o.iterations = Parameters::getInt(p, Parameters::kStereoIterations());
  o.maxLevel = Parameters::getInt(p, Parameters::kStereoMaxLevel());
  o.eps = Parameters::getDouble(p, Parameters::kStereoEps());
  o.ssd = Parameters::getBool(p, Parameters::kStereoSSD());
  o.minDisparity = Parameters::getFloat(p, Parameters::kStereoMinDisparity());
  o.maxDisparity = Parameters::getFloat(p, Parameters::kStereoMaxDisparity());
  return o;
}

bool StereoOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (winWidth < 1 || winHeight < 1) return fail("Stereo/WinWidth and Stereo/WinHeight must be at least 1");
  if (opticalFlow && (winWidth < 3 || winHeight < 3)) {
    // A window of one or two pixels has no centre and no texture to track.
    return fail("with Stereo/OpticalFlow, Stereo/WinWidth and Stereo/WinHeight must be at least 3");
  }
  if (iterations < 1) return fail("Stereo/Iterations must be at least 1");
  if (maxLevel < 0) return fail("Stereo/MaxLevel must not be negative");
  if (!(eps > 0.0)) return fail("Stereo/Eps must be positive");
  if (minDisparity < 0.0f) return fail("Stereo/MinDisparity must not be negative");
  if (!(maxDisparity > minDisparity)) {
    return fail("Stereo/MaxDisparity (" + std::to_string(maxDisparity) +
                ") must be greater than Stereo/MinDisparity (" + std::to_string(minDisparity) + ")");
  }
  return true;
}

namespace {

// Sub-pixel disparity by block matching along the row: the window around the left point is
// compared with windows of the right image shifted by each whole disparity; the best cost and
// its two neighbours are fitted with a parabola. 0 when the window leaves the image or the
// minimum sits at the end of the search range (the true match may lie beyond it).
float blockMatchDisparity(const cv::Mat& left, const cv::Mat& right, const cv::Point2f& p,
                          const StereoOptions& o) {
  const int hw = o.winWidth / 2;
  const int hh = o.winHeight / 2;
  const int x = static_cast<int>(std::floor(p.x + 0.5f));
  const int y = static_cast<int>(std::floor(p.y + 0.5f));
  if (y - hh < 0 || y + hh >= left.rows || x - hw < 0 || x + hw >= left.cols) return 0.0f;
  const int dMin = static_cast<int>(std::ceil(o.minDisparity));
  const int dMax = std::min(static_cast<int>(std::floor(o.maxDisparity)), x - hw);
  if (dMax - dMin < 2) return 0.0f;
  std::vector<double> cost(static_cast<size_t>(dMax - dMin + 1));
  for (int d = dMin; d <= dMax; ++d) {
    double c = 0.0;
    for (int r = -hh; r <= hh; ++r) {
      const unsigned char* l = left.ptr<unsigned char>(y + r);
      const unsigned char* rr = right.ptr<unsigned char>(y + r);
      for (int k = -hw; k <= hw; ++k) {
        const double diff = static_cast<double>(l[x + k]) - static_cast<double>(rr[x + k - d]);
        c += o.ssd ? diff * diff : std::fabs(diff);
      }
    }
    cost[static_cast<size_t>(d - dMin)] = c;
  }
  size_t best = 0;
  for (size_t i = 1; i < cost.size(); ++i) {
    if (cost[i] < cost[best]) best = i;
  }
  if (best == 0 || best + 1 == cost.size()) return 0.0f;
  const double c0 = cost[best - 1], c1 = cost[best], c2 = cost[best + 1];
  const double denom = c0 - 2.0 * c1 + c2;
  const double offset = denom > 0.0 ? 0.5 * (c0 - c2) / denom : 0.0;
  return static_cast<float>(dMin + static_cast<double>(best) + offset);
}

}  // namespace

std::vector<float> computeStereoDisparities(const cv::Mat& leftGrey, const cv::Mat& rightGrey,
                                            const std::vector<cv::Point2f>& leftPoints,
                                            const StereoOptions& options) {
  if (leftGrey.type() != CV_8UC1 || rightGrey.type() != CV_8UC1) {
    throw std::invalid_argument("computeStereoDisparities: images must be 8-bit grey");
  }
  if (leftGrey.size() != rightGrey.size()) {
    throw std::invalid_argument("computeStereoDisparities: left and right images differ in size");
  }
  std::vector<float> disparities(leftPoints.size(), 0.0f);
  if (leftPoints.empty()) return disparities;
  if (!options.opticalFlow) {
    for (size_t i = 0; i < leftPoints.size(); ++i) {
      const float d = blockMatchDisparity(leftGrey, rightGrey, leftPoints[i], options);
      if (d >= options.minDisparity && d <= options.maxDisparity && d > 0.0f) disparities[i] = d;
    }
    return disparities;
  }
  features_detail::RowFlowOptions flow;
  flow.winWidth = options.winWidth;
  flow.winHeight = options.winHeight;
  flow.iterations = options.iterations;
  flow.maxLevel = options.maxLevel;
  flow.eps = options.eps;
  const std::vector<float> tracked = features_detail::rowFlowDisparities(leftGrey, rightGrey, leftPoints, flow);
  for (size_t i = 0; i < leftPoints.size(); ++i) {
    const float d = tracked[i];
    if (d > 0.0f && d >= options.minDisparity && d <= options.maxDisparity) disparities[i] = d;
  }
  return disparities;
}

std::vector<cv::Point3f> keypoints3DFromDisparities(const std::vector<cv::KeyPoint>& keypoints,
                                                    const std::vector<float>& disparities,
                                                    const StereoCameraModel& model, float minDepth,
                                                    float maxDepth) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<cv::Point3f> points(keypoints.size(), cv::Point3f(nan, nan, nan));
  if (disparities.size() != keypoints.size() || !model.isValidForProjection()) return points;
  const Eigen::Isometry3d& local = model.localTransform().toEigen();
  for (size_t i = 0; i < keypoints.size(); ++i) {
    if (!(disparities[i] > 0.0f)) continue;
    const double depth = model.computeDepth(disparities[i]);
    if (!(depth > 0.0) || (minDepth > 0.0f && depth < minDepth) || (maxDepth > 0.0f && depth > maxDepth)) {
      continue;
    }
    double x, y, z;
    if (!model.left().project(keypoints[i].pt.x, keypoints[i].pt.y, depth, x, y, z)) continue;
    const Eigen::Vector3d p = local * Eigen::Vector3d(x, y, z);
    points[i] = cv::Point3f(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  }
  return points;
}

}  // namespace rtabmap
