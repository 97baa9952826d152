#pragma once
// Loop-closure detection scored against ground truth: precision, recall, and the recall at
// 100% precision obtained by sweeping the detector's confidence threshold (the figure of merit
// of appearance-based loop closure papers, e.g. Labbe & Michaud, T-RO 2013).
//
// Images are identified by 1-based ids in input order (the first image of the sequence is
// id 1), as rtabmap-console numbers them; id 0 means "no loop".
//
// Detections file: one query per line, `query_id matched_id confidence` (blank- or
// comma-separated; matched_id 0 = no loop closure accepted for that image; confidence: any
// number, higher = more confident, e.g. the loop-closure hypothesis probability; 1 when the
// column is absent). Blank lines and '#' comments are skipped. A query may appear at most once.
//
// Ground truth, either:
//  - an N x N matrix, as an image (any OpenCV-readable file, e.g. png/bmp/pgm) or a text file
//    of N rows of N numbers: element (i-1, j-1) non-zero = images i and j show the same place.
//    Either triangle may be filled (the matrix is read symmetrically); the diagonal is
//    ignored.
//  - or ground-truth poses, one per image in image order: images i and j close a loop when
//    their poses are at most maxDistance metres and maxAngle apart and |i - j| >= minFrameGap.
//    Optionally a third band: pairs that are not loops but within ambiguousDistance and
//    ambiguousAngle are neither (the views may well overlap, as the 7-Scenes bands of the
//    loop-closure issue say): accepting one counts neither as a true nor as a false positive.
#include <cstddef>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap {

struct LoopDetection {
  int queryId = 0;
  int matchedId = 0;  // 0: none
  double confidence = 0.0;
};

// Throws FormatError "file:line: ..." on a malformed line or a repeated query.
std::vector<LoopDetection> readLoopDetections(const std::string& path);

class LoopGroundTruth {
 public:
  LoopGroundTruth() = default;
  // An N x N single-channel matrix of any depth; non-zero = loop. FormatError if not square.
  static LoopGroundTruth fromMatrix(const cv::Mat& matrix);
  // Image file (extension png, bmp, pgm, ppm, jpg, jpeg, tif, tiff) or text matrix.
  static LoopGroundTruth readMatrix(const std::string& path);
  // How fromPoses decides that two images show the same place. Distances in metres, angles in
  // radians; an angle <= 0 leaves orientation out of that band.
  struct PoseCriteria {
    double maxDistance = 0.0;  // a loop: camera centres within this distance ...
    double maxAngle = 0.0;     // ... and within this angle,
    int minFrameGap = 1;       // ... images at least this many apart in the sequence.
    // Not a loop, but within ambiguousDistance (>= maxDistance; 0 = no band) and ambiguousAngle:
    // neither true nor false.
    double ambiguousDistance = 0.0;
    double ambiguousAngle = 0.0;
    // The angle between two poses: their whole relative rotation (false), or the angle between
    // their viewing directions, `viewingAxis` of each pose (true): a hand-held camera rolled
    // about its optical axis still sees the same place. UnitX: the base frame's forward axis
    // (ROS body axes), which the readers put along the camera's optical axis.
    bool viewingDirectionOnly = false;
    Eigen::Vector3d viewingAxis = Eigen::Vector3d::UnitX();
  };
  // Null poses close no loop. FormatError when the ambiguous band is narrower than the loop's.
  static LoopGroundTruth fromPoses(const std::vector<Transform>& poses, const PoseCriteria& criteria);
  // A loop within maxDistance and maxAngle (whole relative rotation), no ambiguous band.
  static LoopGroundTruth fromPoses(const std::vector<Transform>& poses, double maxDistance,
                                   double maxAngle, int minFrameGap);

  int size() const { return size_; }
  // Images a and b (1-based) show the same place; false for ids outside [1, size()] or a == b.
  bool isLoop(int a, int b) const;
  // Images a and b are in the ambiguous band: neither a loop nor a false match.
  bool isAmbiguous(int a, int b) const;
  // Image `id` closes a loop with an earlier image (one with a smaller id).
  bool hasLoopWithEarlier(int id) const;
  // Number of images that close a loop with an earlier image: the positives of recall.
  size_t positives() const;

 private:
  void addLoop(int a, int b);  // 1-based, a != b
  void finish();               // sorts and deduplicates

  int size_ = 0;
  std::vector<std::vector<int>> loops_;      // per image (index id - 1): sorted ids it loops with
  std::vector<std::vector<int>> ambiguous_;  // per image: sorted ids in the ambiguous band (or empty)
};

struct PrecisionRecallPoint {
  double threshold = 0.0;  // detections with confidence >= threshold are accepted
  size_t truePositives = 0;
  size_t falsePositives = 0;
  double precision = 1.0;  // 1 when nothing is accepted
  double recall = 0.0;
};

struct LoopClosurePR {
  size_t queries = 0;     // detections read
  size_t positives = 0;   // images closing a loop with an earlier image (ground truth)
  size_t detections = 0;  // queries with a match (matched_id != 0)
  size_t ignored = 0;     // detections whose ids are outside the ground truth
  size_t ambiguous = 0;   // accepted at the threshold, in the ground truth's ambiguous band
  // At the given threshold:
  double threshold = 0.0;
  size_t truePositives = 0;   // accepted, and a true loop
  size_t falsePositives = 0;  // accepted, not a loop
  size_t falseNegatives = 0;  // positives without an accepted true match
  double precision = 1.0;
  double recall = 0.0;
  // Sweep over every distinct confidence of the detections (descending):
  double recallAt100Precision = 0.0;  // best recall with no false positive (0 if none)
  double thresholdAt100Precision = 0.0;  // lowest threshold reaching it (+inf if none)
  std::vector<PrecisionRecallPoint> curve;
};
// A detection of query q is accepted when matched != 0 and confidence >= threshold; it is a
// true positive when isLoop(q, matched), neither when isAmbiguous(q, matched), else a false
// positive. Recall = true positives / positives.
LoopClosurePR computeLoopClosurePR(const std::vector<LoopDetection>& detections,
                                   const LoopGroundTruth& groundTruth, double threshold = 0.0);

}  // namespace rtabmap
