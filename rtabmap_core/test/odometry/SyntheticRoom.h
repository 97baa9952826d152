#pragma once
// A textured box room rendered by ray casting, for tests of features, visual registration and
// visual odometry that must not depend on ../shared/data: exact depth, known poses, RGB-D and
// rectified stereo views of the same photo-consistent scene.
//
// The room spans [-halfSize, halfSize]^2 x [0, height] (world z up). Each of its six faces
// carries its own texture: random rectangles and discs of random grey levels on a smooth noise
// background, so corner detectors find many well-spread corners.
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <array>
#include <cmath>
#include <limits>

#include "common/TestData.h"
#include "rtabmap_core/geometry/CameraModel.h"
#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/geometry/StereoCameraModel.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap::test {

class SyntheticRoom {
 public:
  explicit SyntheticRoom(unsigned seed = 1, double halfSize = 3.0, double height = 2.5)
      : halfSize_(halfSize), height_(height) {
    cv::RNG rng(drawSeed(seed));
    for (cv::Mat& t : textures_) t = makeTexture(rng);
  }

  // A pinhole camera of w x h pixels with a Kinect-like field of view (about 63 degrees).
  static CameraModel camera(int width = 320, int height = 240) {
    const double f = width * 525.0 / 640.0;
    return CameraModel(f, f, width / 2.0 - 0.5, height / 2.0 - 0.5, CameraModel::opticalRotation(), 0.0,
                       cv::Size(width, height));
  }
  static StereoCameraModel stereoCamera(int width = 320, int height = 240, double baseline = 0.12) {
    const double f = width * 525.0 / 640.0;
    return StereoCameraModel(f, f, width / 2.0 - 0.5, height / 2.0 - 0.5, baseline, CameraModel::opticalRotation(),
                             cv::Size(width, height));
  }

  // Grey (CV_8UC1) or BGR image and depth (CV_32FC1, metres along the optical axis) seen by a
  // camera whose optical frame has pose `opticalPose` in the world.
  void render(const Transform& opticalPose, const CameraModel& model, cv::Mat& grey, cv::Mat* depth) const {
    const int w = model.imageWidth(), h = model.imageHeight();
    grey.create(h, w, CV_8UC1);
    if (depth) depth->create(h, w, CV_32FC1);
    const Eigen::Matrix3d R = opticalPose.rotationMatrix();
    const Eigen::Vector3d o = opticalPose.translation();
    const double fx = model.fx(), fy = model.fy(), cx = model.cx(), cy = model.cy();
    for (int v = 0; v < h; ++v) {
      for (int u = 0; u < w; ++u) {
        const Eigen::Vector3d rayCam((u - cx) / fx, (v - cy) / fy, 1.0);  // z = 1: t is the depth
        const Eigen::Vector3d ray = R * rayCam;
        double tBest = std::numeric_limits<double>::infinity();
        int face = -1;
        for (int axis = 0; axis < 3; ++axis) {
          if (std::fabs(ray[axis]) < 1e-12) continue;
          const double lo = axis == 2 ? 0.0 : -halfSize_;
          const double hi = axis == 2 ? height_ : halfSize_;
          for (int side = 0; side < 2; ++side) {
            const double t = ((side ? hi : lo) - o[axis]) / ray[axis];
            if (t > 1e-6 && t < tBest) {
              tBest = t;
              face = axis * 2 + side;
            }
          }
        }
        if (face < 0) {
          grey.at<unsigned char>(v, u) = 0;
          if (depth) depth->at<float>(v, u) = 0.0f;
          continue;
        }
        const Eigen::Vector3d p = o + tBest * ray;
        grey.at<unsigned char>(v, u) = sample(face, p);
        if (depth) depth->at<float>(v, u) = static_cast<float>(tBest);
      }
    }
  }

  // RGB-D frame (BGR image, float depth) of the robot base at `basePose`.
  SensorData rgbd(const Transform& basePose, const CameraModel& model, int id = 0, double stamp = 0.0) const {
    cv::Mat grey, depth, bgr;
    render(basePose * model.localTransform(), model, grey, &depth);
    cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
    SensorData data(bgr, depth, model, id, stamp);
    data.setGroundTruth(basePose);
    return data;
  }

  // Rectified stereo frame: the right optical frame is `baseline` along the left one's x axis.
  SensorData stereo(const Transform& basePose, const StereoCameraModel& model, int id = 0, double stamp = 0.0) const {
    cv::Mat left, right;
    const Transform leftPose = basePose * model.localTransform();
    render(leftPose, model.left(), left, nullptr);
    render(leftPose * Transform(model.baseline(), 0, 0, 0, 0, 0), model.left(), right, nullptr);
    SensorData data(left, right, model, id, stamp);
    data.setGroundTruth(basePose);
    return data;
  }

  double halfSize() const { return halfSize_; }
  double height() const { return height_; }

 private:
  static constexpr int kTextureSize = 768;

  static cv::Mat makeTexture(cv::RNG& rng) {
    cv::Mat small(24, 24, CV_8UC1);
    rng.fill(small, cv::RNG::UNIFORM, 60, 200);
    cv::Mat t;
    cv::resize(small, t, cv::Size(kTextureSize, kTextureSize), 0, 0, cv::INTER_CUBIC);
    for (int i = 0; i < 700; ++i) {
      const cv::Point c{rng.uniform(0, kTextureSize), rng.uniform(0, kTextureSize)};  // braces: drawn in order
      const int s = rng.uniform(4, 22);
      const cv::Scalar g(rng.uniform(0, 256));
      if (rng.uniform(0, 3) == 0) {
        cv::circle(t, c, s / 2 + 2, g, cv::FILLED);
      } else {
        cv::rectangle(t, cv::Rect(c.x, c.y, s, rng.uniform(4, 22)), g, cv::FILLED);
      }
    }
    return t;
  }

  // Texture value at world point p of face (axis * 2 + side), bilinear.
  unsigned char sample(int face, const Eigen::Vector3d& p) const {
    const int axis = face / 2;
    const int a = axis == 0 ? 1 : 0;
    const int b = axis == 2 ? 1 : 2;
    const double spanA = 2.0 * halfSize_;
    const double spanB = b == 2 ? height_ : 2.0 * halfSize_;
    const double offB = b == 2 ? 0.0 : -halfSize_;
    const double x = std::clamp((p[a] + halfSize_) / spanA, 0.0, 1.0) * (kTextureSize - 1);
    const double y = std::clamp((p[b] - offB) / spanB, 0.0, 1.0) * (kTextureSize - 1);
    const int x0 = std::min(static_cast<int>(x), kTextureSize - 2), y0 = std::min(static_cast<int>(y), kTextureSize - 2);
    const double fx = x - x0, fy = y - y0;
    const cv::Mat& t = textures_[static_cast<size_t>(face)];
    const double v = (1 - fx) * (1 - fy) * t.at<unsigned char>(y0, x0) + fx * (1 - fy) * t.at<unsigned char>(y0, x0 + 1) +
                     (1 - fx) * fy * t.at<unsigned char>(y0 + 1, x0) + fx * fy * t.at<unsigned char>(y0 + 1, x0 + 1);
    return static_cast<unsigned char>(std::lround(v));
  }

  double halfSize_;
  double height_;
  std::array<cv::Mat, 6> textures_;
};

}  // namespace rtabmap::test
