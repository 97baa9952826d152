#pragma once
// Visual registration (JFR 2019, 3.1.1): the rigid transform between two frames (or a feature
// map and a frame) from their image features, used by visual odometry, loop closures and
// proximity links (Reg/Strategy 0, and the first step of Reg/Strategy 2).
//
//   correspondences  descriptor NNDR matching (Vis/CorType 0), guided by the projection of
//                    the reference points when a guess is given (Vis/CorGuessWinSize), or
//                    optical flow (Vis/CorType 1)
//   motion           PnP RANSAC from the reference 3D points to the new keypoints
//                    (Vis/EstimationType 1) or 3D-3D RANSAC (0); optionally also backwards
//                    and averaged (Vis/ForwardEstOnly false)
//   refinement       optional two-view bundle adjustment (Vis/BundleAdjustment 3)
//
// Several cameras (RGB-D or stereo images side by side, one model each, see FeatureDetector): the
// 3D points are all in the base frame, so descriptor matching is unchanged; guided matching
// projects each reference point into every camera of the new frame (the first that sees it
// wins, its u offset by i*w); optical flow keeps only tracks that stay in their camera's
// sub-image (Lucas-Kanade cannot follow a point from one camera into another); PnP becomes a
// multi-camera PnP (estimateMotionMultiCameraPnP below); the backward average and the two-view
// bundle adjustment, written for one camera per frame, are skipped.
//   acceptance       Vis/MinInliers, Vis/MeanInliersDistance, Vis/MinInliersDistribution
//   covariance       from the median absolute deviation of the inliers' 3D errors
//
// The transform is the pose of `to`'s base frame in `from`'s base frame (to = from * T), as for
// every registration of this library. Failure returns a null transform with
// RegistrationInfo::rejectedMsg saying why in words.
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rtabmap_core/features/FeatureDetector.h"
#include "rtabmap_core/geometry/CameraModel.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/params/Parameters.h"
#include "rtabmap_core/registration/Correspondences.h"
#include "rtabmap_core/registration/MotionEstimation.h"
#include "rtabmap_core/registration/RegistrationInfo.h"

namespace rtabmap {

class SensorData;
class Signature;

struct RegistrationVisOptions {
  FeatureOptions features;  // Vis/ feature group: used when a frame has no features yet
  CorrespondenceOptions correspondences;
  int estimationType = 1;   // Vis/EstimationType: 0 3D->3D, 1 3D->2D (PnP)
  PnPOptions pnp;
  RigidOptions rigid;
  int minInliers = 20;      // Vis/MinInliers
  bool forwardEstOnly = true;
  float meanInliersDistance = 0.0f;     // m, 0 = no check
  float minInliersDistribution = 0.0f;  // 0 = no check
  int bundleAdjustment = 0;             // Vis/BundleAdjustment: 0 off, 3 Ceres
  bool force3DoF = false;               // Reg/Force3DoF

  // From Vis/*, Reg/Force3DoF and the detector groups; throws ParameterError on invalid values.
  static RegistrationVisOptions fromParameters(const ParametersMap& parameters);
  bool IsValid(std::string* why = nullptr) const;
};

// One side of a registration. A frame from a camera has keypoints and a valid camera model;
// a feature map (F2M) has only 3D points and descriptors. points3D, descriptors rows and ids
// (when given) have one entry per feature; keypoints too when present.
struct VisualFrame {
  std::vector<cv::KeyPoint> keypoints;  // in the (left) rectified image
  std::vector<cv::Point3f> points3D;    // base frame; NaN when unknown
  cv::Mat descriptors;
  std::vector<int> ids;                 // word or map-point ids reported in RegistrationInfo
  CameraModel model;                    // (left) camera, local transform base -> optical
  // Every camera of a frame whose images are side by side (camera i owns the columns
  // [i*w, (i+1)*w) of the image); models[0] == model. Empty for a feature map.
  std::vector<CameraModel> models;
  double stereoBaseline = 0.0;          // m, > 0 for a stereo frame (bundle adjustment weights)
  cv::Mat grey;                         // 8-bit grey image, needed by optical flow
  // 3D points (base frame) of arbitrary image points of this frame, from its depth or stereo
  // pair: lets optical flow, which moves keypoints, get 3D for 3D->3D estimation.
  std::function<std::vector<cv::Point3f>(const std::vector<cv::KeyPoint>&)> points3DAt;

  size_t size() const {
    if (descriptors.rows > 0) return static_cast<size_t>(descriptors.rows);
    return !points3D.empty() ? points3D.size() : ids.size();  // words paired by id: maybe no 3D
  }
  bool isMap() const { return keypoints.empty(); }
  bool severalCameras() const { return models.size() > 1; }
  // Width of one camera's sub-image (0 when unknown), and the camera of an image column.
  int cameraWidth() const;
  int cameraOf(float x) const;
  // A camera frame from sensor data and its features (camera model, grey image, points3DAt).
  static VisualFrame fromSensorData(const SensorData& data, const ImageFeatures& features,
                                    const StereoOptions& stereo = StereoOptions());
};

// Multi-camera PnP: the new base frame's pose minimising the reprojection errors of the
// reference points `objectPoints[k]` at `imagePoints[k]` (combined image: the camera is
// cameraOf(x)) through each camera's own model and local transform. OpenCV's PnP knows one
// camera only, so the first hypothesis is the 3D->3D RANSAC estimate from the new frame's own 3D
// points (newPoints3D; RGB-D frames have them), then Gauss-Newton on the reprojection errors of
// the points within Vis/PnPReprojError, repeated Vis/PnPRefineIterations times with the inliers
// re-selected. Fails (rejectedMsg) with fewer than Vis/MinInliers inliers.
MotionEstimate estimateMotionMultiCameraPnP(const std::vector<cv::Point3f>& objectPoints,
                                            const std::vector<cv::Point2f>& imagePoints,
                                            const std::vector<cv::Point3f>& newPoints3D, const VisualFrame& to,
                                            const PnPOptions& pnp, const RigidOptions& rigid);

// The correspondences behind a result, for callers that update maps (F2M) or display them.
struct VisualCorrespondences {
  std::vector<cv::DMatch> matches;  // queryIdx: from feature, trainIdx: to feature (flow: from index)
  std::vector<int> inliers;         // indices into matches
  std::vector<cv::Point2f> toPoints;  // per match, its position in the `to` image
};

class RegistrationVis {
 public:
  // Throws ParameterError on invalid parameters.
  explicit RegistrationVis(const ParametersMap& parameters = {});
  explicit RegistrationVis(const RegistrationVisOptions& options);
  ~RegistrationVis();
  RegistrationVis(const RegistrationVis&) = delete;
  RegistrationVis& operator=(const RegistrationVis&) = delete;

  const RegistrationVisOptions& options() const { return options_; }
  const FeatureDetector& detector() const { return *detector_; }
  // Whether registering two nodes reads their images beside their words: optical flow
  // (Vis/CorType 1), 3D-3D estimation (Vis/EstimationType 0) and the backward check
  // (Vis/ForwardEstOnly false) do; so do several cameras whose models lack image sizes.
  bool needsImages() const;

  // Registration of two nodes. A node's features are its words (keypoints, 3D, descriptors)
  // if it has some, else the features of its sensor data, else they are extracted now from its
  // images (uncompressing them if needed) and stored in its sensor data (setFeatures), so the
  // next registration of that node reuses them. When both nodes have words and one of them
  // kept no descriptors (Mem/RawDescriptorsKept false), the words are paired by id
  // (matchByWordIds); a node with such words registered with a node without words is matched
  // by descriptors extracted again from its images. `guess` (from -> to, null = none) guides
  // the matching. Never throws on bad sensor data: the reason is in info->rejectedMsg.
  Transform computeTransform(Signature& from, Signature& to, const Transform& guess = Transform(),
                             RegistrationInfo* info = nullptr) const;

  // Registration of two prepared frames. With optical flow (Vis/CorType 1) and no guess, a
  // second pass tracks again from where the first pass's transform predicts each point and is
  // kept when it has more inliers.
  Transform computeTransform(const VisualFrame& from, const VisualFrame& to, const Transform& guess,
                             RegistrationInfo* info = nullptr, VisualCorrespondences* details = nullptr) const;

  // The frame registration makes of a node (its words, else its sensor data's features, else
  // features extracted now and stored in its sensor data), "" in *problem, or why it cannot.
  // wordsById: the node's words as they are, descriptors or not (both nodes are paired by id).
  VisualFrame frameOf(Signature& node, bool wordsById, std::string* problem) const;

 private:
  // One pass: correspondences, motion estimation, acceptance.
  Transform estimate(const VisualFrame& from, const VisualFrame& to, const Transform& guess, RegistrationInfo& info,
                     VisualCorrespondences* details) const;
  bool tracksByOpticalFlow(const VisualFrame& from, const VisualFrame& to) const;

  RegistrationVisOptions options_;
  std::unique_ptr<FeatureDetector> detector_;
};

}  // namespace rtabmap
