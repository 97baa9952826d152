#pragma once
// Epipolar verification of a visual loop-closure hypothesis (the original RTAB-Map's VhEp
// option): the two locations' images must be views of one rigid scene. The words each location
// has exactly once are paired by word id; a fundamental matrix is fitted to the pairs' keypoints
// with RANSAC, and the hypothesis holds when enough pairs agree with it.
//
// Why words seen once: a repeated word (tiled floor, brick wall, ceiling grid) cannot say which
// of its keypoints goes with which, and such texture is what makes two different places look
// alike to the bag of words. A true revisit keeps its posters, doors and furniture, each a word
// seen once, in a geometry one camera motion explains. What it cannot refuse: a scene that
// repeats with a period (a tiled floor seen a whole number of tiles further along a corridor puts
// the same words at the same pixels, which a fundamental matrix fits).
//
// Appearance-only mapping uses it (no registration checks the hypothesis there); metric SLAM
// verifies by registration, which implies this test.
#include <string>

#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {
class Signature;
}

namespace rtabmap::memory {

struct EpipolarCheckOptions {
  bool enabled = false;       // VhEp/Enabled
  int matchCountMin = 8;      // VhEp/MatchCountMin (RANSAC inliers)
  float inlierRatioMin = 0.35f;  // VhEp/InlierRatioMin (inliers / pairs)
  float ransacParam1 = 3.0f;  // VhEp/RansacParam1: pixels from the epipolar line
  float ransacParam2 = 0.99f; // VhEp/RansacParam2: confidence

  static EpipolarCheckOptions fromParameters(const ParametersMap& parameters);
  bool IsValid(std::string* why = nullptr) const;
};

struct EpipolarCheckSummary {
  int pairs = 0;    // words both locations have exactly once
  int inliers = 0;  // pairs consistent with the fitted fundamental matrix
  bool accepted = false;
  std::string why;  // the reason of a refusal

  std::string Summary() const;
};

// Fits F to the unique-word pairs of `query` and `candidate`. Fewer than matchCountMin pairs, no
// fit, fewer than matchCountMin inliers, or inliers under inlierRatioMin of the pairs: refused.
// The ratio matters because F has 7 degrees of freedom: RANSAC's best F over unrelated pairs
// agrees with its 7-pair sample and a few more (10 of 40, 13 of 120 in the tests), which the
// classic count alone accepts. Locations without keypoints are refused (nothing to verify with).
EpipolarCheckSummary checkEpipolarGeometry(const Signature& query, const Signature& candidate,
                                           const EpipolarCheckOptions& options);

}  // namespace rtabmap::memory
