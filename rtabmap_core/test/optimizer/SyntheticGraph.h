#pragma once
// Synthetic pose graphs for the optimizer tests: a ground-truth trajectory, odometry links
// with Gaussian noise, loop closures between poses that come back near each other, and the
// odometry-composed (drifting) initial poses. Deterministic (fixed seeds).
#include <cmath>
#include <map>
#include <random>

#include "common/TestData.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/memory/Link.h"

namespace rtabmap::test {

struct SyntheticGraph {
  std::map<int, Transform> truth;
  std::map<int, Transform> odometry;  // composed noisy odometry (the initial guess)
  std::multimap<int, Link> links;
};

struct NoiseModel {
  double sigmaXY = 0.05;
  double sigmaZ = 0.05;
  double sigmaAngle = 0.01;  // roll, pitch, yaw
};

inline Link::InfMatrix informationOf(const NoiseModel& noise, bool is2D) {
  Link::InfMatrix info = Link::InfMatrix::Zero();
  info(0, 0) = info(1, 1) = 1.0 / (noise.sigmaXY * noise.sigmaXY);
  info(2, 2) = 1.0 / (noise.sigmaZ * noise.sigmaZ);
  info(3, 3) = info(4, 4) = info(5, 5) = 1.0 / (noise.sigmaAngle * noise.sigmaAngle);
  if (is2D) info(2, 2) = info(3, 3) = info(4, 4) = 1.0;
  return info;
}

// A measured relative transform: the true one perturbed on the right by noise. Braces draw the
// components left to right; in parentheses the order would be the compiler's (GCC and clang differ).
inline Transform noisy(const Transform& t, const NoiseModel& noise, bool is2D, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  if (is2D) {
    return t * Transform{noise.sigmaXY * n(rng), noise.sigmaXY * n(rng), noise.sigmaAngle * n(rng)};
  }
  return t * Transform{noise.sigmaXY * n(rng), noise.sigmaXY * n(rng), noise.sigmaZ * n(rng),
                       noise.sigmaAngle * n(rng), noise.sigmaAngle * n(rng),
                       noise.sigmaAngle * n(rng)};
}

// `laps` laps of a square of side `side` metres, one node per metre, ids firstId..; in 3D the
// square climbs `climb` metres per lap with some roll and pitch. Odometry links between
// consecutive nodes; a loop closure from each node of laps 2.. to the node at the same place
// in lap 1.
inline SyntheticGraph makeSquareLoops(int laps, int side, bool is2D, const NoiseModel& noise,
                                      unsigned seed, int firstId = 1, double climb = 0.0) {
  SyntheticGraph g;
  std::mt19937 rng(drawSeed(seed));
  const int perLap = 4 * side;
  const int count = laps * perLap;
  for (int k = 0; k < count; ++k) {
    const int lap = k / perLap;
    const int s = k % perLap;
    const int edge = s / side;
    const double along = s % side;
    double x = 0, y = 0, yaw = 0;
    switch (edge) {
      case 0: x = along; y = 0; yaw = 0; break;
      case 1: x = side; y = along; yaw = M_PI / 2; break;
      case 2: x = side - along; y = side; yaw = M_PI; break;
      default: x = 0; y = side - along; yaw = -M_PI / 2; break;
    }
    Transform pose = is2D ? Transform(x, y, yaw)
                          : Transform(x, y, climb * (lap + double(s) / perLap),
                                      0.05 * std::sin(0.3 * k), 0.04 * std::cos(0.2 * k), yaw);
    g.truth.emplace(firstId + k, pose);
  }
  const Link::InfMatrix info = informationOf(noise, is2D);
  for (int k = 1; k < count; ++k) {
    const Transform rel = g.truth.at(firstId + k - 1).inverse() * g.truth.at(firstId + k);
    g.links.emplace(firstId + k - 1, Link(firstId + k - 1, firstId + k, Link::kNeighbor,
                                          noisy(rel, noise, is2D, rng), info));
  }
  for (int k = perLap; k < count; ++k) {
    const int from = firstId + k;
    const int to = firstId + k % perLap;
    const Transform rel = g.truth.at(from).inverse() * g.truth.at(to);
    g.links.emplace(from, Link(from, to, Link::kGlobalClosure, noisy(rel, noise, is2D, rng), info));
  }
  // Dead reckoning.
  g.odometry.emplace(firstId, g.truth.at(firstId));
  for (int k = 1; k < count; ++k) {
    const auto range = g.links.equal_range(firstId + k - 1);
    for (auto it = range.first; it != range.second; ++it) {
      if (it->second.type() == Link::kNeighbor) {
        g.odometry.emplace(firstId + k, g.odometry.at(firstId + k - 1) * it->second.transform());
      }
    }
  }
  return g;
}

// Largest position error between two pose sets over the ids of `truth` present in `estimate`,
// after expressing both relative to the pose of `anchor`.
inline double maxPositionError(const std::map<int, Transform>& truth,
                               const std::map<int, Transform>& estimate, int anchor) {
  const Transform ta = truth.at(anchor).inverse();
  const Transform ea = estimate.at(anchor).inverse();
  double worst = 0.0;
  for (const auto& [id, pose] : truth) {
    const auto it = estimate.find(id);
    if (it == estimate.end()) continue;
    worst = std::max(worst, ((ta * pose).translation() - (ea * it->second).translation()).norm());
  }
  return worst;
}

}  // namespace rtabmap::test
