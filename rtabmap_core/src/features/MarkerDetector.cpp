#include "rtabmap_core/features/MarkerDetector.h"

#include <opencv2/aruco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <array>
#include <cmath>
#include <sstream>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/geometry/SensorData.h"

namespace rtabmap {

namespace {
constexpr int kLastDictionary = cv::aruco::DICT_APRILTAG_36h11;  // 20
bool finiteAtLeast(float v, float lo) { return std::isfinite(v) && v >= lo; }
}  // namespace

MarkerDetectorOptions MarkerDetectorOptions::fromParameters(const ParametersMap& p) {
  MarkerDetectorOptions o;
  o.dictionary = Parameters::getInt(p, Parameters::kMarkerDictionary());
  o.length = Parameters::getFloat(p, Parameters::kMarkerLength());
  o.maxDepthError = Parameters::getFloat(p, Parameters::kMarkerMaxDepthError());
  o.varianceLinear = Parameters::getFloat(p, Parameters::kMarkerVarianceLinear());
  o.varianceAngular = Parameters::getFloat(p, Parameters::kMarkerVarianceAngular());
  o.cornerRefinementMethod = Parameters::getInt(p, Parameters::kMarkerCornerRefinementMethod());
  o.maxRange = Parameters::getFloat(p, Parameters::kMarkerMaxRange());
  o.minRange = Parameters::getFloat(p, Parameters::kMarkerMinRange());
  return o;
}

bool MarkerDetectorOptions::IsValid(std::string* why) const {
  std::ostringstream r;
  if (dictionary < 0 || dictionary > kLastDictionary) {
    r << Parameters::kMarkerDictionary() << " must be between 0 and " << kLastDictionary << " (got " << dictionary << ")";
  } else if (cornerRefinementMethod < cv::aruco::CORNER_REFINE_NONE ||
             cornerRefinementMethod > cv::aruco::CORNER_REFINE_APRILTAG) {
    r << Parameters::kMarkerCornerRefinementMethod() << " must be between 0 and 3 (got " << cornerRefinementMethod << ")";
  } else if (!finiteAtLeast(length, 0.0f)) {
    r << Parameters::kMarkerLength() << " must be >= 0 (got " << length << ")";
  } else if (!std::isfinite(maxDepthError) || maxDepthError <= 0.0f) {
    r << Parameters::kMarkerMaxDepthError() << " must be > 0 (got " << maxDepthError << ")";
  } else if (!std::isfinite(varianceLinear) || varianceLinear <= 0.0f) {
    r << Parameters::kMarkerVarianceLinear() << " must be > 0 (got " << varianceLinear << ")";
  } else if (!std::isfinite(varianceAngular) || varianceAngular <= 0.0f) {
    r << Parameters::kMarkerVarianceAngular() << " must be > 0 (got " << varianceAngular << ")";
  } else if (!finiteAtLeast(minRange, 0.0f) || !finiteAtLeast(maxRange, 0.0f)) {
    r << Parameters::kMarkerMinRange() << " and " << Parameters::kMarkerMaxRange() << " must be >= 0";
  } else if (maxRange > 0.0f && minRange > maxRange) {
    r << Parameters::kMarkerMinRange() << " " << minRange << " is above " << Parameters::kMarkerMaxRange() << " "
      << maxRange;
  }
  const std::string text = r.str();
  if (why) *why = text;
  return text.empty();
}

struct MarkerDetector::Detector {
  cv::Ptr<cv::aruco::Dictionary> dictionary;
  cv::Ptr<cv::aruco::DetectorParameters> parameters;
};

MarkerDetector::MarkerDetector(const MarkerDetectorOptions& options) : options_(options) {
  std::string why;
  if (!options_.IsValid(&why)) throw ParameterError(why);
  detector_ = std::make_unique<Detector>();
  detector_->dictionary =
      cv::aruco::getPredefinedDictionary(static_cast<cv::aruco::PREDEFINED_DICTIONARY_NAME>(options_.dictionary));
  detector_->parameters = cv::aruco::DetectorParameters::create();
  detector_->parameters->cornerRefinementMethod = options_.cornerRefinementMethod;
}

MarkerDetector::~MarkerDetector() = default;

namespace {

// One camera's share of the frame: its part of the image (grey) and of the depth image.
struct CameraView {
  cv::Mat grey, depth;
  const CameraModel* model = nullptr;
};

std::vector<CameraView> cameraViews(const SensorData& frame) {
  std::vector<const CameraModel*> models;
  for (const CameraModel& m : frame.cameraModels()) models.push_back(&m);
  for (const StereoCameraModel& m : frame.stereoCameraModels()) models.push_back(&m.left());
  std::vector<CameraView> views;
  const cv::Mat& image = frame.imageRaw();
  if (models.empty() || image.empty() || image.cols % static_cast<int>(models.size()) != 0) return views;
  cv::Mat grey;
  if (image.channels() == 3) {
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  } else if (image.channels() == 4) {
    cv::cvtColor(image, grey, cv::COLOR_BGRA2GRAY);
  } else {
    grey = image;
  }
  const int n = static_cast<int>(models.size());
  const int w = image.cols / n;
  // Only a depth image (not a stereo pair's right image) measures marker sides.
  const cv::Mat depth = frame.isStereo() ? cv::Mat() : frame.depthOrRightRaw();
  const bool depthSplits = !depth.empty() && depth.cols % n == 0;
  for (int i = 0; i < n; ++i) {
    CameraView v;
    v.grey = grey.colRange(i * w, (i + 1) * w);
    if (depthSplits) {
      const int dw = depth.cols / n;
      v.depth = depth.colRange(i * dw, (i + 1) * dw);
    }
    v.model = models[static_cast<size_t>(i)];
    views.push_back(v);
  }
  return views;
}

// The side of a marker facing the camera, from the depth at its corners; 0 when a corner has no
// depth or the corners' depths differ by more than maxDepthError (seen at an angle: the pixel
// sampled beside a corner may then be off the marker's plane by more than that).
float sideFromDepth(const std::vector<cv::Point2f>& corners, const CameraView& v, float maxDepthError) {
  if (v.depth.empty() || corners.size() != 4) return 0.0f;
  const float sx = static_cast<float>(v.depth.cols) / static_cast<float>(v.grey.cols);
  const float sy = static_cast<float>(v.depth.rows) / static_cast<float>(v.grey.rows);
  cv::Point2f centre(0, 0);
  for (const cv::Point2f& c : corners) centre += c * 0.25f;
  std::array<cv::Point3f, 4> points;
  float lo = 1e9f, hi = 0.0f;
  for (size_t i = 0; i < 4; ++i) {
    // Sampled an eighth of the way in: the corner pixel itself may see what is behind the edge.
    const cv::Point2f in = corners[i] + (centre - corners[i]) * 0.125f;
    const float z = SensorData::depthAt(v.depth, static_cast<int>(std::lround(in.x * sx)),
                                        static_cast<int>(std::lround(in.y * sy)));
    if (z <= 0.0f) return 0.0f;
    lo = std::min(lo, z);
    hi = std::max(hi, z);
    const CameraModel& m = *v.model;
    points[i] = cv::Point3f(static_cast<float>((corners[i].x - m.cx()) * z / m.fx()),
                            static_cast<float>((corners[i].y - m.cy()) * z / m.fy()), z);
  }
  if (hi - lo > maxDepthError) return 0.0f;
  float side = 0.0f;
  for (size_t i = 0; i < 4; ++i) side += static_cast<float>(cv::norm(points[i] - points[(i + 1) % 4])) * 0.25f;
  return side;
}

// The marker's pose in the optical frame from its corners (detectMarkers' order: top-left,
// top-right, bottom-right, bottom-left), by iterative PnP, as aruco's own estimate does.
// (Debian's OpenCV 4.6 IPPE_SQUARE returned the identity rotation for markers facing the camera:
// MarkerDetector tests.)
bool markerPose(const std::vector<cv::Point2f>& corners, float side, const CameraModel& model, cv::Vec3d& rvec,
                cv::Vec3d& tvec) {
  const float h = 0.5f * side;
  const std::vector<cv::Point3f> square = {{-h, h, 0}, {h, h, 0}, {h, -h, 0}, {-h, -h, 0}};
  if (!cv::solvePnP(square, corners, model.K(), model.D(), rvec, tvec, false, cv::SOLVEPNP_ITERATIVE)) return false;
  return std::isfinite(cv::norm(rvec)) && std::isfinite(cv::norm(tvec)) && tvec[2] > 0.0;
}

Transform fromRvecTvec(const cv::Vec3d& rvec, const cv::Vec3d& tvec) {
  cv::Mat r;
  cv::Rodrigues(rvec, r);
  return Transform(r.at<double>(0, 0), r.at<double>(0, 1), r.at<double>(0, 2), tvec[0], r.at<double>(1, 0),
                   r.at<double>(1, 1), r.at<double>(1, 2), tvec[1], r.at<double>(2, 0), r.at<double>(2, 1),
                   r.at<double>(2, 2), tvec[2]);
}

}  // namespace

Landmarks MarkerDetector::detect(const SensorData& frame, MarkerDetectionInfo* info) {
  MarkerDetectionInfo local;
  MarkerDetectionInfo& out = info ? *info : local;
  out = MarkerDetectionInfo();
  Landmarks seen;
  const std::vector<CameraView> views = cameraViews(frame);
  if (views.empty()) {
    out.problem = frame.imageRaw().empty() ? "no raw image" : "no camera model matching the image";
    return seen;
  }
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  covariance.diagonal() << options_.varianceLinear, options_.varianceLinear, options_.varianceLinear,
      options_.varianceAngular, options_.varianceAngular, options_.varianceAngular;
  for (const CameraView& v : views) {
    std::vector<std::vector<cv::Point2f>> corners;
    std::vector<int> ids;
    cv::aruco::detectMarkers(v.grey, detector_->dictionary, corners, ids, detector_->parameters);
    out.detected += static_cast<int>(ids.size());
    for (size_t i = 0; i < ids.size(); ++i) {
      if (ids[i] <= 0) {
        ++out.idZero;  // its graph node would be 0, not a landmark (the original's rule too)
        continue;
      }
      float side = options_.length;
      if (side <= 0.0f) {
        auto known = measuredLengths_.find(ids[i]);
        if (known == measuredLengths_.end()) {
          const float measured = sideFromDepth(corners[i], v, options_.maxDepthError);
          if (measured > 0.0f) known = measuredLengths_.emplace(ids[i], measured).first;
        }
        if (known == measuredLengths_.end()) {
          ++out.withoutLength;
          continue;
        }
        side = known->second;
      }
      cv::Vec3d rvec, tvec;
      if (!markerPose(corners[i], side, *v.model, rvec, tvec)) continue;
      const double range = cv::norm(tvec);
      if ((options_.minRange > 0.0f && range < options_.minRange) ||
          (options_.maxRange > 0.0f && range > options_.maxRange)) {
        ++out.outOfRange;
        continue;
      }
      Landmark l;
      l.id = ids[i];
      l.size = side;
      l.pose = v.model->localTransform() * fromRvecTvec(rvec, tvec);
      l.covariance = covariance;
      // The same marker in two cameras: the nearer sighting (smaller pixel error in metres).
      auto prior = seen.find(l.id);
      if (prior == seen.end() || prior->second.pose.getNorm() > l.pose.getNorm()) seen[l.id] = l;
    }
  }
  return seen;
}

}  // namespace rtabmap
