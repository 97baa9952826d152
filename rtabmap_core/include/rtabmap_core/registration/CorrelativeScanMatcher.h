#pragma once
// Correlative scan matching in 2D (Olson, "Real-time correlative scan matching", ICRA 2009),
// searched exhaustively at the finest resolution by branch and bound over max-pooled grids
// (Hess et al., "Real-time loop closure in 2D LIDAR SLAM", ICRA 2016, section V).
//
// ICP only refines a guess within its correspondence distance (a few decimetres). When the
// robot comes back to a place after a long loop, the graph's guess can be metres off: this
// finds the pose of a scan against reference points anywhere inside a search window around the
// guess, and ICP then refines from there. Proximity detection uses it on merged scans.
//
//   CorrelativeOptions o;  o.linearWindow = 3.0f;
//   CorrelativeResult r = matchCorrelative(referencePoints, scanPoints, guess, o);
//   if (r.found) icpGuess = Transform(r.pose.x(), r.pose.y(), 0, 0, 0, r.pose.z());
//
// Score of a pose P: the mean, over the scan's points q, of the reference likelihood grid at
// P q. A cell's likelihood is a Gaussian (sigma = one cell) of the distance from its centre to
// the nearest reference point: a scan point in the cell of a reference point counts near 1,
// one cell off about 0.6. Rotations are searched at the step that moves the farthest scan point
// by one cell; translations at one cell.
#include <Eigen/Core>

#include <string>
#include <vector>

namespace rtabmap {

struct CorrelativeOptions {
  float resolution = 0.05f;     // m per cell of the finest grid
  float linearWindow = 2.0f;    // search +- this in x and y around the guess (m)
  float angularWindow = 0.35f;  // search +- this around the guess' yaw (rad)
  float minScore = 0.55f;       // the best pose must score at least this (0..1)
  // Ambiguity test: refuse the match when a pose farther than peakSeparation (m) or turned more
  // than peakAngleSeparation (rad) from the best scores at least maxSecondPeakRatio times the
  // best (a corridor, a hub of look-alike doors: the best peak is then chance). 1 = no test.
  float maxSecondPeakRatio = 1.0f;
  float peakSeparation = 0.5f;
  float peakAngleSeparation = 0.2f;
  bool IsValid(std::string* why = nullptr) const;
};

struct CorrelativeResult {
  bool found = false;                            // a pose scored >= minScore, unambiguous
  Eigen::Vector3f pose = Eigen::Vector3f::Zero();  // x, y, yaw of the scan in the reference frame
  float score = 0.0f;                            // of `pose` (of the best pose seen when !found)
  float guessScore = 0.0f;                       // of the guess itself
  float secondScore = 0.0f;                      // of a far pose reaching the ratio (ambiguous)
  long scoredCandidates = 0;                     // work done by branch and bound
  std::string why;                               // when !found
};

// reference, scan: 2D points (reference frame, scan frame). guess: x, y, yaw of the scan frame
// in the reference frame. Throws ParameterError for invalid options.
CorrelativeResult matchCorrelative(const std::vector<Eigen::Vector2f>& reference,
                                   const std::vector<Eigen::Vector2f>& scan, const Eigen::Vector3f& guess,
                                   const CorrelativeOptions& options);

}  // namespace rtabmap
