#include "rtabmap_core/geometry/DepthRegistration.h"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <Eigen/Core>

#include <cmath>
#include <limits>
#include <stdexcept>

using rtabmap::CameraModel;
using rtabmap::Transform;
using rtabmap::registerDepth;

namespace {

// A scene in the colour camera's optical frame: a slanted wall z = 3 + 0.3 x behind a square
// panel z = 1.5 (|x|, |y| < 0.3), the kind of depth edge where an unregistered depth image is
// most wrong. Depth (metres, along the camera's own axis) seen by a camera at pose
// colourFromCamera through pixel (u, v); infinity if the ray misses everything.
double sceneDepth(const CameraModel& model, const Transform& colourFromCamera, double u, double v) {
  const Eigen::Vector3d o = colourFromCamera.translation();
  const Eigen::Matrix3d R = colourFromCamera.rotationMatrix();
  const Eigen::Vector3d dirCam((u - model.cx()) / model.fx(), (v - model.cy()) / model.fy(), 1.0);
  const Eigen::Vector3d d = R * dirCam;
  double best = std::numeric_limits<double>::infinity();
  // Panel: z = 1.5.
  if (std::abs(d.z()) > 1e-12) {
    const double s = (1.5 - o.z()) / d.z();
    const Eigen::Vector3d p = o + s * d;
    if (s > 0 && std::abs(p.x()) < 0.3 && std::abs(p.y()) < 0.3) best = s;
  }
  // Wall: z - 0.3 x = 3.
  const double den = d.z() - 0.3 * d.x();
  if (std::abs(den) > 1e-12) {
    const double s = (3.0 - (o.z() - 0.3 * o.x())) / den;
    if (s > 0 && s < best) best = s;
  }
  // s is the distance along dirCam, whose z in the camera frame is 1: s is the camera's depth.
  return best;
}

cv::Mat render(const CameraModel& model, const Transform& colourFromCamera, int type) {
  cv::Mat out(model.imageHeight(), model.imageWidth(), type, cv::Scalar(0));
  for (int v = 0; v < out.rows; ++v) {
    for (int u = 0; u < out.cols; ++u) {
      const double z = sceneDepth(model, colourFromCamera, u, v);
      if (!std::isfinite(z)) continue;
      if (type == CV_16UC1) {
        out.at<uint16_t>(v, u) = static_cast<uint16_t>(std::lround(z * 1000.0));
      } else {
        out.at<float>(v, u) = static_cast<float>(z);
      }
    }
  }
  return out;
}

double metres(const cv::Mat& m, int v, int u) {
  return m.type() == CV_16UC1 ? m.at<uint16_t>(v, u) * 0.001 : m.at<float>(v, u);
}

// A Kinect-like pair: the depth camera 2.5 cm to the colour camera's side, slightly turned,
// with a longer focal length (7-Scenes: depth 585, colour 525).
struct KinectLikePair {
  CameraModel depth{585.0, 585.0, 320.0, 240.0, CameraModel::opticalRotation(), 0.0, cv::Size(640, 480)};
  CameraModel colour{525.0, 525.0, 318.0, 242.0, CameraModel::opticalRotation(), 0.0, cv::Size(640, 480)};
  Transform depthToColour{-0.025, 0.0005, 0.002, 0.006, -0.008, 0.003};
};

struct Comparison {
  int registered = 0;   // colour pixels given a depth
  int wallOnPanel = 0;  // ... the wall's depth where the colour camera sees the panel
  int within3mm = 0;    // ... within 3 mm of the truth
  int insideView = 0;   // colour pixels of the central region (inside the depth camera's view)
  int insideViewSet = 0;
};

Comparison compare(const cv::Mat& registered, const cv::Mat& truth) {
  Comparison c;
  for (int v = 0; v < truth.rows; ++v) {
    for (int u = 0; u < truth.cols; ++u) {
      const double r = metres(registered, v, u);
      const bool central = v >= 60 && v < 420 && u >= 60 && u < 580;
      c.insideView += central;
      if (r <= 0.0) continue;
      c.insideViewSet += central;
      ++c.registered;
      c.within3mm += std::abs(r - metres(truth, v, u)) <= 0.003;
      c.wallOnPanel += metres(truth, v, u) < 2.0 && r > 2.5;
    }
  }
  return c;
}

}  // namespace

TEST(DepthRegistration, DepthMovedToTheColourCameraMatchesWhatTheColourCameraWouldSee) {
  const KinectLikePair pair;
  for (int type : {CV_16UC1, CV_32FC1}) {
    SCOPED_TRACE(type == CV_16UC1 ? "16UC1" : "32FC1");
    const cv::Mat depth = render(pair.depth, pair.depthToColour, type);
    const cv::Mat truth = render(pair.colour, Transform::Identity(), type);
    const cv::Mat registered = registerDepth(depth, pair.depth, pair.colour, pair.depthToColour);
    ASSERT_EQ(registered.type(), type);
    ASSERT_EQ(registered.size(), cv::Size(640, 480));

    const Comparison c = compare(registered, truth);
    // Only the panel's outline (a depth pixel of the panel rounded onto a wall pixel, ~0.5%)
    // may be off; the slanted wall's depth moves by < 1 mm for half a pixel of rounding.
    EXPECT_GE(c.within3mm, 0.99 * c.registered) << c.within3mm << " of " << c.registered;
    // The depth camera's longer focal length samples every colour pixel of its view; only the
    // panel's shadow (~5 px beside it, where the depth camera sees the wall behind) stays empty.
    EXPECT_GE(c.insideViewSet, 0.98 * c.insideView) << c.insideViewSet << " of " << c.insideView;
    // The panel is in front of the wall: where both land, the nearer one wins. The depth camera
    // sees a strip of wall beside the panel that the colour camera sees behind it: 80 pixels of
    // the panel's image would show the wall if the last sample landing on a pixel won.
    EXPECT_NEAR(metres(registered, 242, 318), 1.5, 0.002);
    EXPECT_EQ(c.wallOnPanel, 0) << "wall depth on " << c.wallOnPanel << " pixels of the panel";
    // The colour camera's wider view reaches beyond the depth camera's: its border stays empty.
    EXPECT_EQ(metres(registered, 240, 2), 0.0);

    // The test can fail: the same depth image used unregistered (as the colour camera's) is off
    // by more than 3 mm on most of the wall and by a metre and a half along the panel's edges.
    const Comparison raw = compare(depth, truth);
    EXPECT_LT(raw.within3mm, 0.5 * raw.registered);
  }
}

TEST(DepthRegistration, SameCameraIsTheIdentity) {
  const KinectLikePair pair;
  const cv::Mat depth = render(pair.colour, Transform::Identity(), CV_16UC1);
  const cv::Mat registered = registerDepth(depth, pair.colour, pair.colour, Transform::Identity());
  EXPECT_EQ(cv::countNonZero(depth != registered), 0);
}

TEST(DepthRegistration, NoMeasurementStaysNoMeasurement) {
  const KinectLikePair pair;
  cv::Mat depth(480, 640, CV_32FC1, cv::Scalar(2.0f));
  depth(cv::Rect(300, 200, 40, 40)).setTo(0.0f);
  depth(cv::Rect(100, 100, 20, 20)).setTo(std::numeric_limits<float>::quiet_NaN());
  const cv::Mat registered = registerDepth(depth, pair.colour, pair.colour, Transform::Identity());
  EXPECT_EQ(cv::countNonZero(registered == 0.0f), 40 * 40 + 20 * 20);
  cv::Mat finite = registered == registered;  // NaN != NaN
  EXPECT_EQ(cv::countNonZero(finite), 640 * 480);
}

TEST(DepthRegistration, RefusesWhatItCannotRegister) {
  const KinectLikePair pair;
  const cv::Mat depth(480, 640, CV_16UC1, cv::Scalar(1000));
  EXPECT_THROW(registerDepth(cv::Mat(480, 640, CV_8UC1), pair.depth, pair.colour, pair.depthToColour),
               std::invalid_argument);
  EXPECT_THROW(registerDepth(depth, CameraModel(), pair.colour, pair.depthToColour), std::invalid_argument);
  const CameraModel noSize(525.0, 525.0, 320.0, 240.0);
  EXPECT_THROW(registerDepth(depth, pair.depth, noSize, pair.depthToColour), std::invalid_argument);
  EXPECT_THROW(registerDepth(depth, pair.depth, pair.colour, Transform()), std::invalid_argument);
}
