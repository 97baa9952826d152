#include "rtabmap_core/geometry/DepthRegistration.h"

#include <Eigen/Core>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace rtabmap {
namespace {

// Depth in metres at (row, col), or 0 for no measurement.
double depthAt(const cv::Mat& depth, int row, int col) {
  if (depth.type() == CV_16UC1) return depth.at<uint16_t>(row, col) * 0.001;
  const float d = depth.at<float>(row, col);
  return std::isfinite(d) && d > 0.0f ? d : 0.0;
}

}  // namespace

cv::Mat registerDepth(const cv::Mat& depth, const CameraModel& depthModel,
                      const CameraModel& colourModel, const Transform& depthToColour) {
  if (depth.type() != CV_16UC1 && depth.type() != CV_32FC1) {
    throw std::invalid_argument("registerDepth: depth must be CV_16UC1 (mm) or CV_32FC1 (m)");
  }
  if (!depthModel.isValidForProjection() || !colourModel.isValidForProjection()) {
    throw std::invalid_argument("registerDepth: both camera models need fx, fy > 0");
  }
  if (colourModel.imageWidth() <= 0 || colourModel.imageHeight() <= 0) {
    throw std::invalid_argument("registerDepth: the colour model needs its image size");
  }
  if (depthToColour.isNull()) throw std::invalid_argument("registerDepth: null depth-to-colour transform");

  const int rows = colourModel.imageHeight();
  const int cols = colourModel.imageWidth();
  // Nearest surface per colour pixel, in metres (a z-buffer); infinity = nothing landed there.
  cv::Mat nearest(rows, cols, CV_64FC1, cv::Scalar(std::numeric_limits<double>::infinity()));
  const double fxd = depthModel.fx(), fyd = depthModel.fy(), cxd = depthModel.cx(), cyd = depthModel.cy();
  const double fxc = colourModel.fx(), fyc = colourModel.fy(), cxc = colourModel.cx(), cyc = colourModel.cy();
  const Eigen::Matrix3d R = depthToColour.rotationMatrix();
  const Eigen::Vector3d t = depthToColour.translation();
  for (int v = 0; v < depth.rows; ++v) {
    for (int u = 0; u < depth.cols; ++u) {
      const double z = depthAt(depth, v, u);
      if (z <= 0.0) continue;
      const Eigen::Vector3d p(((u - cxd) / fxd) * z, ((v - cyd) / fyd) * z, z);
      const Eigen::Vector3d q = R * p + t;
      if (q.z() <= 0.0) continue;
      const long uc = std::lround(fxc * q.x() / q.z() + cxc);
      const long vc = std::lround(fyc * q.y() / q.z() + cyc);
      if (uc < 0 || vc < 0 || uc >= cols || vc >= rows) continue;
      double& best = nearest.at<double>(static_cast<int>(vc), static_cast<int>(uc));
      if (q.z() < best) best = q.z();
    }
  }

  cv::Mat out(rows, cols, depth.type(), cv::Scalar(0));
  for (int v = 0; v < rows; ++v) {
    for (int u = 0; u < cols; ++u) {
      const double z = nearest.at<double>(v, u);
      if (!std::isfinite(z)) continue;
      if (out.type() == CV_16UC1) {
        // Millimetres: a surface beyond 65.534 m cannot be stored (65535 is an invalid marker).
        const long mm = std::lround(z * 1000.0);
        if (mm > 0 && mm < 65535) out.at<uint16_t>(v, u) = static_cast<uint16_t>(mm);
      } else {
        out.at<float>(v, u) = static_cast<float>(z);
      }
    }
  }
  return out;
}

}  // namespace rtabmap
