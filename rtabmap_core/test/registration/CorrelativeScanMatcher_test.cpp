// Correlative scan matching (Olson 2009; branch and bound of Hess et al. 2016): finds a scan's
// pose metres away from the guess, where ICP's correspondences cannot reach, and branch and
// bound returns the same best pose as scoring every candidate.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/registration/CorrelativeScanMatcher.h"

namespace rtabmap {
namespace {

// An irregular room (no symmetry a matcher could confuse): walls sampled every 2 cm, with a
// pillar and a doorway recess.
std::vector<Eigen::Vector2f> room() {
  std::vector<Eigen::Vector2f> pts;
  auto wall = [&](Eigen::Vector2f a, Eigen::Vector2f b) {
    const int n = static_cast<int>((b - a).norm() / 0.02f);
    for (int i = 0; i <= n; ++i) pts.push_back(a + (b - a) * (float(i) / n));
  };
  wall({0, 0}, {12, 0});
  wall({12, 0}, {12, 4});
  wall({12, 4}, {13.5f, 4});
  wall({13.5f, 4}, {13.5f, 5.5f});
  wall({13.5f, 5.5f}, {12, 5.5f});
  wall({12, 5.5f}, {12, 8});
  wall({12, 8}, {3, 8});
  wall({3, 8}, {0, 6});
  wall({0, 6}, {0, 0});
  // A pillar.
  wall({5, 3}, {5.6f, 3});
  wall({5.6f, 3}, {5.6f, 3.4f});
  wall({5.6f, 3.4f}, {5, 3.4f});
  wall({5, 3.4f}, {5, 3});
  return pts;
}

// What a robot at `pose` (x, y, yaw) would see of the reference within `range`, in its frame,
// every `every`-th point, with Gaussian noise.
std::vector<Eigen::Vector2f> scanFrom(const std::vector<Eigen::Vector2f>& reference, const Eigen::Vector3f& pose,
                                      float range, int every, float noise, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> n(0.0f, noise);
  const float c = std::cos(pose.z()), s = std::sin(pose.z());
  std::vector<Eigen::Vector2f> out;
  for (size_t i = 0; i < reference.size(); i += every) {
    const Eigen::Vector2f d = reference[i] - pose.head<2>();
    if (d.norm() > range) continue;
    const float ex = noise > 0 ? n(rng) : 0.f;  // drawn in this order on every compiler
    const float ey = noise > 0 ? n(rng) : 0.f;
    out.emplace_back(c * d.x() + s * d.y() + ex, -s * d.x() + c * d.y() + ey);
  }
  return out;
}

float angleDiff(float a, float b) { return std::atan2(std::sin(a - b), std::cos(a - b)); }

TEST(CorrelativeScanMatcher, FindsAPoseMetresFromTheGuess) {
  const std::vector<Eigen::Vector2f> ref = room();
  const Eigen::Vector3f truth(6.3f, 5.1f, 0.4f);
  const std::vector<Eigen::Vector2f> scan = scanFrom(ref, truth, 8.0f, 3, 0.01f, 1);
  ASSERT_GT(scan.size(), 300u);
  // 1.6 m, 1.3 m and 0.25 rad off: far beyond an ICP correspondence distance of 0.3 m.
  const Eigen::Vector3f guess = truth + Eigen::Vector3f(-1.6f, 1.3f, -0.25f);
  CorrelativeOptions o;
  o.resolution = 0.05f;
  o.linearWindow = 2.0f;
  o.angularWindow = 0.35f;
  const CorrelativeResult r = matchCorrelative(ref, scan, guess, o);
  ASSERT_TRUE(r.found) << r.why;
  EXPECT_NEAR(r.pose.x(), truth.x(), 2 * o.resolution);
  EXPECT_NEAR(r.pose.y(), truth.y(), 2 * o.resolution);
  EXPECT_NEAR(angleDiff(r.pose.z(), truth.z()), 0.0f, 0.02f);
  EXPECT_GT(r.score, 0.7f);
  EXPECT_LT(r.guessScore, 0.3f) << "the guess itself must be a poor fit, or the test shows nothing";
  // Branch and bound scored far fewer candidates than the whole window holds.
  const long all = long(81 * 81) * long(2 * std::ceil(0.35f / 0.005f) + 1);
  EXPECT_LT(r.scoredCandidates, all / 10);
}

TEST(CorrelativeScanMatcher, BranchAndBoundEqualsScoringEveryOffset) {
  const std::vector<Eigen::Vector2f> ref = room();
  const Eigen::Vector3f truth(8.0f, 3.0f, -0.3f);
  const std::vector<Eigen::Vector2f> scan = scanFrom(ref, truth, 6.0f, 4, 0.03f, 2);
  const Eigen::Vector3f guess = truth + Eigen::Vector3f(0.4f, -0.3f, 0.05f);
  CorrelativeOptions o;
  o.resolution = 0.1f;
  o.linearWindow = 0.6f;
  o.angularWindow = 0.1f;
  o.minScore = 0.01f;
  const CorrelativeResult bnb = matchCorrelative(ref, scan, guess, o);
  ASSERT_TRUE(bnb.found) << bnb.why;
  // Every offset of the window scored on its own (window 0: all rotations, one translation).
  CorrelativeOptions one = o;
  one.linearWindow = 0.0f;
  float best = 0.0f;
  const int w = 6;
  for (int iy = -w; iy <= w; ++iy) {
    for (int ix = -w; ix <= w; ++ix) {
      const Eigen::Vector3f g = guess + Eigen::Vector3f(ix * o.resolution, iy * o.resolution, 0.0f);
      const CorrelativeResult r = matchCorrelative(ref, scan, g, one);
      if (r.found) best = std::max(best, r.score);
    }
  }
  // Cells computed from shifted guesses may round differently at a cell border: a point or so.
  EXPECT_NEAR(bnb.score, best, 0.01f);
}

TEST(CorrelativeScanMatcher, NeverWorseThanTheTruthAtTheGridsEdge) {
  // A corner whose walls are the reference grid's edges: the blocks of branch and bound that
  // start outside the grid must still bound the cells they reach inside it.
  std::vector<Eigen::Vector2f> corner;
  for (int i = 0; i <= 500; ++i) corner.emplace_back(i * 0.02f, 0.0f);
  for (int i = 1; i <= 300; ++i) corner.emplace_back(0.0f, i * 0.02f);
  CorrelativeOptions o;
  o.linearWindow = 0.5f;
  o.minScore = 0.01f;
  for (float resolution : {0.05f, 0.1f}) {
    o.resolution = resolution;
    const float truthScore = matchCorrelative(corner, corner, Eigen::Vector3f::Zero(), o).guessScore;
    // The truth is on the search lattice: the guess' yaw is exact, its translation whole cells off.
    const CorrelativeResult r = matchCorrelative(corner, corner, Eigen::Vector3f(4 * resolution, 2 * resolution, 0), o);
    ASSERT_TRUE(r.found) << r.why;
    EXPECT_GE(r.score, truthScore - 1e-4f) << "resolution " << resolution;
    // Points on cell borders make neighbouring cells tie: within one cell.
    EXPECT_NEAR(r.pose.x(), 0.0f, 1.01f * resolution);
    EXPECT_NEAR(r.pose.y(), 0.0f, 1.01f * resolution);
  }
}

TEST(CorrelativeScanMatcher, NothingOutsideTheWindowOrUnderTheMinimumScore) {
  const std::vector<Eigen::Vector2f> ref = room();
  const Eigen::Vector3f truth(6.3f, 5.1f, 0.4f);
  const std::vector<Eigen::Vector2f> scan = scanFrom(ref, truth, 8.0f, 3, 0.01f, 3);
  CorrelativeOptions o;
  o.linearWindow = 0.5f;  // the truth is 2 m away
  o.minScore = 0.7f;
  const CorrelativeResult far = matchCorrelative(ref, scan, truth + Eigen::Vector3f(2.0f, 0.0f, 0.0f), o);
  EXPECT_FALSE(far.found);
  EXPECT_NE(far.why.find("scores"), std::string::npos) << far.why;
  // A scan of somewhere else entirely (a different room) never reaches a high score.
  std::vector<Eigen::Vector2f> other;
  for (int i = 0; i < 400; ++i) other.emplace_back(3.0f * std::cos(i * 0.0157f), 1.0f * std::sin(i * 0.0157f));
  o.linearWindow = 2.0f;
  EXPECT_FALSE(matchCorrelative(ref, other, truth, o).found);
}

// Two copies of the same irregular room side by side, 8 m apart: a hub of look-alike places.
// A scan of one copy, searched from a guess half-way between them, fits both equally.
std::vector<Eigen::Vector2f> twinRooms() {
  std::vector<Eigen::Vector2f> pts = room();
  const size_t n = pts.size();
  for (size_t i = 0; i < n; ++i) pts.push_back(pts[i] + Eigen::Vector2f(14.0f, 0.0f));
  return pts;
}

TEST(CorrelativeScanMatcher, AmbiguityTestRefusesATwinPlace) {
  const std::vector<Eigen::Vector2f> one = room();
  const Eigen::Vector3f truth(6.3f, 4.1f, 0.2f);
  // Range 6 m: the scan stays inside its own copy, so both copies give it the same score.
  const std::vector<Eigen::Vector2f> scan = scanFrom(one, truth, 6.0f, 3, 0.01f, 4);
  ASSERT_GT(scan.size(), 200u);
  CorrelativeOptions o;
  o.resolution = 0.1f;
  o.linearWindow = 8.0f;
  o.angularWindow = 0.1f;
  o.minScore = 0.5f;
  const Eigen::Vector3f guess = truth + Eigen::Vector3f(7.0f, 0.3f, 0.0f);  // between the copies
  const CorrelativeResult off = matchCorrelative(twinRooms(), scan, guess, o);
  ASSERT_TRUE(off.found) << "without the test one of the twins wins: " << off.why;
  o.maxSecondPeakRatio = 0.9f;
  const CorrelativeResult twin = matchCorrelative(twinRooms(), scan, guess, o);
  EXPECT_FALSE(twin.found);
  EXPECT_GE(twin.secondScore, 0.9f * twin.score);
  EXPECT_NE(twin.why.find("ambiguous"), std::string::npos) << twin.why;
  // The same search in the single room is unambiguous: the test only refuses real look-alikes.
  const CorrelativeResult single = matchCorrelative(one, scan, guess - Eigen::Vector3f(7.0f, 0.0f, 0.0f), o);
  ASSERT_TRUE(single.found) << single.why;
  EXPECT_NEAR(single.pose.x(), truth.x(), 2 * o.resolution);
  EXPECT_NEAR(single.pose.y(), truth.y(), 2 * o.resolution);
}

TEST(CorrelativeScanMatcher, AmbiguityTestRefusesACorridor) {
  // Two parallel walls 2 m apart, 30 m long, no door: a scan inside fits anywhere along it.
  std::vector<Eigen::Vector2f> corridor;
  for (int i = 0; i <= 1500; ++i) {
    corridor.emplace_back(i * 0.02f, 0.0f);
    corridor.emplace_back(i * 0.02f, 2.0f);
  }
  const Eigen::Vector3f truth(15.0f, 1.0f, 0.0f);
  const std::vector<Eigen::Vector2f> scan = scanFrom(corridor, truth, 5.0f, 2, 0.01f, 5);
  CorrelativeOptions o;
  o.resolution = 0.1f;
  o.linearWindow = 2.0f;
  o.angularWindow = 0.1f;
  o.minScore = 0.5f;
  o.maxSecondPeakRatio = 0.9f;
  const CorrelativeResult r = matchCorrelative(corridor, scan, truth + Eigen::Vector3f(1.0f, 0.3f, 0.0f), o);
  EXPECT_FALSE(r.found) << "a corridor match at x = " << r.pose.x() << " passed the ambiguity test";
  EXPECT_NE(r.why.find("ambiguous"), std::string::npos) << r.why;
  // The room has no such twin: with the test on, it still finds the pose metres from the guess.
  const std::vector<Eigen::Vector2f> ref = room();
  const Eigen::Vector3f roomTruth(6.3f, 5.1f, 0.4f);
  const std::vector<Eigen::Vector2f> roomScan = scanFrom(ref, roomTruth, 8.0f, 3, 0.01f, 1);
  o.angularWindow = 0.35f;
  const CorrelativeResult inRoom = matchCorrelative(ref, roomScan, roomTruth + Eigen::Vector3f(-1.6f, 1.3f, -0.25f), o);
  ASSERT_TRUE(inRoom.found) << inRoom.why;
  EXPECT_NEAR(inRoom.pose.x(), roomTruth.x(), 2 * o.resolution);
  EXPECT_NEAR(inRoom.pose.y(), roomTruth.y(), 2 * o.resolution);
}

TEST(CorrelativeScanMatcher, BadInputIsRefusedWithAReason) {
  const std::vector<Eigen::Vector2f> ref = room();
  CorrelativeOptions o;
  EXPECT_FALSE(matchCorrelative({}, ref, Eigen::Vector3f::Zero(), o).found);
  EXPECT_FALSE(matchCorrelative(ref, {}, Eigen::Vector3f::Zero(), o).found);
  const CorrelativeResult nan = matchCorrelative(ref, ref, Eigen::Vector3f(NAN, 0, 0), o);
  EXPECT_FALSE(nan.found);
  EXPECT_FALSE(nan.why.empty());
  const CorrelativeResult away = matchCorrelative(ref, {{0.1f, 0.0f}}, Eigen::Vector3f(500, 500, 0), o);
  EXPECT_FALSE(away.found);
  EXPECT_NE(away.why.find("no reference point"), std::string::npos) << away.why;
  using Edit = void (*)(CorrelativeOptions&);
  for (Edit bad : {Edit([](CorrelativeOptions& x) { x.resolution = 0; }), Edit([](CorrelativeOptions& x) { x.minScore = 1.5f; }),
                   Edit([](CorrelativeOptions& x) { x.angularWindow = -1; }),
                   Edit([](CorrelativeOptions& x) { x.linearWindow = NAN; }),
                   Edit([](CorrelativeOptions& x) { x.maxSecondPeakRatio = 0; }),
                   Edit([](CorrelativeOptions& x) { x.peakSeparation = -1; })}) {
    CorrelativeOptions b;
    bad(b);
    std::string why;
    EXPECT_FALSE(b.IsValid(&why));
    EXPECT_FALSE(why.empty());
    EXPECT_THROW(matchCorrelative(ref, ref, Eigen::Vector3f::Zero(), b), ParameterError);
  }
}

}  // namespace
}  // namespace rtabmap
