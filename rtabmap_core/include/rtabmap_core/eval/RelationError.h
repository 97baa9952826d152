#pragma once
// The relation-based SLAM metric of Kuemmerle et al., "On measuring the accuracy of SLAM
// algorithms" (Autonomous Robots 27(4), 2009), used for the Freiburg / Radish datasets (ACES,
// Intel, ...): the estimate is judged only on relative poses between pairs of instants that a
// human checked (the relations), so no global ground truth is needed.
//
// For a relation (t1, t2, delta*) and the estimated poses x1, x2 at t1 and t2, the estimated
// relative pose is delta = x1^-1 x2 (x2 in the frame of x1) and the error is
// e = delta*^-1 delta (the paper's delta (-) delta*). Its translational part is |t(e)|
// (metres), its rotational part the angle of R(e) (degrees; for planar motion, the absolute
// yaw difference). The paper reports the mean and standard deviation of each ("absolute"
// errors), and the mean of their squares (its epsilon).
#include <cstddef>
#include <string>
#include <vector>

#include "rtabmap_core/eval/Trajectory.h"
#include "rtabmap_core/eval/TrajectoryError.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap {

struct Relation {
  double stamp1 = 0.0;
  double stamp2 = 0.0;
  Transform pose;  // pose at stamp2 in the frame of the pose at stamp1
  int line = 0;    // line in the relations file (0 if not from a file)
};

// Reads a relations file: one relation per line, `t1 t2 x y z roll pitch yaw` (metres,
// radians; 2D logs use x, y and yaw). Blank lines and '#' comments are skipped. Throws
// FormatError "file:line: ..." on a malformed line, or when the file is missing or empty.
std::vector<Relation> readRelations(const std::string& path);

struct RelationOptions {
  // A relation stamp matches an estimated pose whose stamp is within this many seconds (the
  // nearest one). The metric needs a pose at every relation stamp: a SLAM run must output one
  // per input scan (see ../shared/data/README.md).
  double maxTimeDifference = 1e-3;
  // Relations whose stamps are at most this many seconds apart are "local" (what odometry and
  // the neighbour links decide), the others "loop" (revisits: what loop closure decides). The
  // mean of all mixes the two, and an ACES run whose loops all close can still lose to raw wheel
  // odometry on the local ones. <= 0: no split.
  double localSpan = 5.0;
};

struct RelationResult {
  size_t relations = 0;  // in the input
  size_t used = 0;       // with estimated poses at both stamps
  size_t skipped = 0;    // without
  ErrorStats translation;  // metres
  ErrorStats rotation;     // degrees
  double translationSquaredMean = 0.0;  // m^2, the paper's epsilon_trans
  double rotationSquaredMean = 0.0;     // deg^2
  // The split of RelationOptions::localSpan (empty stats when a side has no relation).
  ErrorStats localTranslation, localRotation;  // m, deg
  ErrorStats loopTranslation, loopRotation;    // m, deg
  std::vector<double> translationErrors;  // per used relation, in input order
  std::vector<double> rotationErrors;     // degrees
  std::vector<size_t> skippedRelations;   // indices in the input of the skipped ones
  std::vector<size_t> usedRelations;      // indices in the input of the used ones (as the errors)
};
// Throws FormatError when not a single relation can be used (with the stamp ranges of both,
// to show a clock mismatch).
RelationResult computeRelationError(const Trajectory& estimate,
                                    const std::vector<Relation>& relations,
                                    const RelationOptions& options = {});

// The used relations with the largest translational errors, at most n, largest first (ties by
// input order): indices into RelationResult::translationErrors / rotationErrors / usedRelations.
// A mean over a whole log hides where it comes from: on ACES one missed revisit (20 relations
// between the same two passes, 0.76-0.96 m each) is over half of the loop relations' error.
std::vector<size_t> worstRelations(const RelationResult& result, size_t n);

// How far a relations file is from agreeing with itself: wherever it holds the three sides of a
// triangle of instants (a->b, b->c and a->c, in either direction), the composition
// delta_ac^-1 delta_ab delta_bc should be the identity. Its size bounds what the metric can
// resolve: with three independent errors alike, each relation's own error is about the
// inconsistency's RMS / sqrt(3), and an estimate scored near that is as good as the reference
// can tell. (ACES: 28 triangles, inconsistency 0.057 m mean, 0.044 m RMS a relation: about
// the 0.0375 m mean that Cartographer scores and raw wheel odometry's 0.037 m on the local ones.)
struct RelationConsistency {
  size_t triangles = 0;
  ErrorStats translation;  // metres, per triangle
  ErrorStats rotation;     // degrees, per triangle
  double relationRms = 0.0;  // translation RMS / sqrt(3): one relation's own error, estimated (m)
};
// Stamps within maxTimeDifference are the same instant.
RelationConsistency relationConsistency(const std::vector<Relation>& relations, double maxTimeDifference = 1e-3);

}  // namespace rtabmap
