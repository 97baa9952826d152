#include "common/MarkerScene.h"

#include <opencv2/aruco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>

namespace rtabmap::test {

Transform markerAhead(double distance, double yaw, double dx, double dy) {
  // Facing the camera: the marker's z toward the camera (-z optical), its y up (-y optical).
  return Transform(dx, dy, distance, 0, 0, 0) * Transform(0, 0, 0, M_PI, 0, 0) * Transform(0, 0, 0, 0, yaw, 0);
}

namespace {
cv::Point2f project(const CameraModel& m, const Eigen::Vector3d& p) {
  return cv::Point2f(static_cast<float>(m.fx() * p.x() / p.z() + m.cx()), static_cast<float>(m.fy() * p.y() / p.z() + m.cy()));
}
}  // namespace

MarkerView renderMarkers(const CameraModel& model, const std::vector<MarkerInView>& markers, int dictionary,
                         float wallDepth) {
  const cv::Size size = model.imageSize();
  MarkerView view;
  view.grey = cv::Mat(size, CV_8UC1, cv::Scalar(255));
  view.depth = cv::Mat(size, CV_32FC1, cv::Scalar(wallDepth));
  const auto dict = cv::aruco::getPredefinedDictionary(static_cast<cv::aruco::PREDEFINED_DICTIONARY_NAME>(dictionary));
  for (const MarkerInView& m : markers) {
    constexpr int kSide = 400;
    cv::Mat drawn;
    cv::aruco::drawMarker(dict, m.id, kSide, drawn, 1);
    const double h = 0.5 * m.length;
    // Corners in the marker frame, in ArUco's order: top-left, top-right, bottom-right, bottom-left.
    const Eigen::Vector3d corners[4] = {{-h, h, 0}, {h, h, 0}, {h, -h, 0}, {-h, -h, 0}};
    std::vector<cv::Point2f> image, source = {{0, 0}, {kSide, 0}, {kSide, kSide}, {0, kSide}};
    for (const Eigen::Vector3d& c : corners) image.push_back(project(model, m.cameraToMarker.toEigen() * c));
    const cv::Mat H = cv::getPerspectiveTransform(source, image);
    cv::Mat warped, mask;
    cv::warpPerspective(drawn, warped, H, size, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(255));
    cv::warpPerspective(cv::Mat(drawn.size(), CV_8UC1, cv::Scalar(255)), mask, H, size, cv::INTER_NEAREST,
                        cv::BORDER_CONSTANT, cv::Scalar(0));
    warped.copyTo(view.grey, mask);
    // Depth of the marker's plane along each pixel's ray: n . (t - 0) / n . ray.
    const Eigen::Vector3d n = m.cameraToMarker.rotationMatrix().col(2);
    const Eigen::Vector3d t = m.cameraToMarker.toEigen().translation();
    for (int v = 0; v < size.height; ++v) {
      for (int u = 0; u < size.width; ++u) {
        if (!mask.at<uchar>(v, u)) continue;
        const Eigen::Vector3d ray((u - model.cx()) / model.fx(), (v - model.cy()) / model.fy(), 1.0);
        view.depth.at<float>(v, u) = static_cast<float>(n.dot(t) / n.dot(ray));
      }
    }
  }
  return view;
}

}  // namespace rtabmap::test
