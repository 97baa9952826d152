#pragma once
// Correspondences between the features of two frames (or a feature map and a frame), the first
// half of visual registration (JFR 2019, section 3.1.1 "Feature Matching"):
//  - descriptor matching by nearest neighbour with the distance ratio test (NNDR, Lowe 2004)
//    over the whole image, through FLANN or brute force (Hamming for binary descriptors);
//  - guided matching: with a motion guess, each reference point is projected into the new
//    image and compared only with the keypoints within Vis/CorGuessWinSize pixels of its
//    projection, which is faster and rejects most false matches before RANSAC;
//  - optical flow: reference keypoints tracked into the new image by pyramidal Lucas-Kanade.
// A correspondence is a cv::DMatch: queryIdx indexes the reference (from) features, trainIdx
// the new (to) features, distance the descriptor distance (0 for optical flow).
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include <string>
#include <vector>

#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {

// Vis/CorNNType.
enum class NearestNeighborType { kFlannLinear = 0, kFlannKdTree = 1, kFlannLsh = 2, kBruteForce = 3, kBruteForceCrossCheck = 5 };

struct CorrespondenceOptions {
  int type = 0;  // Vis/CorType: 0 descriptor matching, 1 optical flow
  NearestNeighborType nnType = NearestNeighborType::kFlannKdTree;
  float nndr = 0.8f;
  int guessWinSize = 40;
  bool guessMatchToProjection = false;
  int flowWinSize = 16;
  int flowIterations = 30;
  float flowEps = 0.01f;
  int flowMaxLevel = 3;
  // Pixels: a tracked point must track back to within this of where it started (0 = no
  // check). Not a parameter of the original; fixed here.
  float flowBackCheck = 1.0f;

  static CorrespondenceOptions fromParameters(const ParametersMap& parameters);
  bool IsValid(std::string* why = nullptr) const;
};

// The search actually used for a descriptor type: binary descriptors cannot go in a kd-tree
// (Vis/CorNNType 1), so they are compared by brute-force Hamming instead (measured faster than
// FLANN's LSH for the ~1000 x 2000 descriptors of odometry, see the bench); float descriptors
// cannot go in an LSH index (2), so they use the kd-tree.
NearestNeighborType effectiveNearestNeighborType(NearestNeighborType requested, bool binaryDescriptors);

// NNDR matching of every `to` descriptor against the `from` descriptors: the nearest `from`
// descriptor is kept if it is closer than nndr times the second nearest. Each `from` feature is
// matched at most once (the closest claim wins). With kBruteForceCrossCheck, mutual nearest
// neighbours are kept instead of the ratio test. Descriptor types must agree (CV_8U binary,
// CV_32F float), else std::invalid_argument.
std::vector<cv::DMatch> matchDescriptors(const cv::Mat& fromDescriptors, const cv::Mat& toDescriptors,
                                         const CorrespondenceOptions& options);

// Guided matching. `projected[i]` is where reference feature i falls in the new image (NaN
// coordinates when it does not project: behind the camera, unknown 3D). Each projected
// reference is compared with the keypoints within `radius` pixels; it is matched to the
// nearest by descriptor distance if that one passes the ratio test against the second nearest
// in the window, or is alone in it and close enough (binary: under 30% of the bits differ).
// With options.guessMatchToProjection the roles swap: each keypoint looks for the nearest
// projected reference within the radius. Each feature of either side is matched at most once.
std::vector<cv::DMatch> matchByProjection(const std::vector<cv::Point2f>& projected, const cv::Mat& fromDescriptors,
                                          const std::vector<cv::KeyPoint>& toKeypoints, const cv::Mat& toDescriptors,
                                          float radius, const CorrespondenceOptions& options);

// Matching by visual word (the bag-of-words pairing of the original for nodes without
// descriptors, Mem/RawDescriptorsKept false): reference feature i and new feature j match when
// they carry the same word id and that id appears once in each frame (a word seen twice in an
// image does not say which keypoint is which). `projected` as for matchByProjection, or empty:
// when given, a pair is kept only if reference i projects within `radius` pixels of new keypoint
// j. distance is 0. Ids must have one entry per feature (toKeypoints too, when projecting).
std::vector<cv::DMatch> matchByWordIds(const std::vector<int>& fromIds, const std::vector<int>& toIds,
                                       const std::vector<cv::Point2f>& projected,
                                       const std::vector<cv::KeyPoint>& toKeypoints, float radius);

// Pyramidal Lucas-Kanade tracking of `fromPoints` from one 8-bit grey image to another of the
// same size. `initial` (same size as fromPoints, or empty) seeds the search, e.g. with the
// projection of each point under a motion guess. Returns tracked positions; status[i] is 0
// where tracking failed, left the image, or did not track back to within
// options.flowBackCheck pixels of its start.
std::vector<cv::Point2f> trackOpticalFlow(const cv::Mat& fromGrey, const cv::Mat& toGrey,
                                          const std::vector<cv::Point2f>& fromPoints,
                                          const std::vector<cv::Point2f>& initial,
                                          const CorrespondenceOptions& options, std::vector<unsigned char>& status);

}  // namespace rtabmap
