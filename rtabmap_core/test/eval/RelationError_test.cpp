// The Kuemmerle et al. 2009 relation metric on a hand-made example.
#include "rtabmap_core/eval/RelationError.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/TestData.h"
#include "eval/EvalTestUtil.h"
#include "rtabmap_core/common/Error.h"

using rtabmap::FormatError;
using rtabmap::Relation;
using rtabmap::Trajectory;
using rtabmap::Transform;
using rtabmap::test::TempDir;
using rtabmap::test::writeText;

namespace {

// x1 at the origin, x2 one metre ahead turned left 90 degrees, x3 one metre further along
// x2's heading (world +y). Relations: 1->2 exact; 2->3 claims (1, 0.1, yaw 0.05): the
// estimate's (1, 0, 0) is 0.1 m and 0.05 rad off; 1->4 has no pose at 4 (skipped).
Trajectory estimate() {
  Trajectory t;
  t.add(3.0, Transform(1, 1, M_PI / 2));  // unsorted on purpose
  t.add(1.0, Transform(0, 0, 0));
  t.add(2.0, Transform(1, 0, M_PI / 2));
  return t;
}

}  // namespace

TEST(RelationError, ByHand) {
  TempDir dir;
  writeText(dir.file("r.relations"),
            "# t1 t2 x y z roll pitch yaw\n"
            "1.0 2.0 1 0 0 0 0 1.5707963267948966\n"
            "2.0 3.0 1 0.1 0 0 0 0.05\n"
            "\n"
            "1.0 4.0 1 0 0 0 0 0\n");
  const std::vector<Relation> relations = rtabmap::readRelations(dir.file("r.relations"));
  ASSERT_EQ(relations.size(), 3u);
  EXPECT_EQ(relations[2].line, 5);
  EXPECT_DOUBLE_EQ(relations[1].pose.theta(), 0.05);

  const rtabmap::RelationResult r = rtabmap::computeRelationError(estimate(), relations);
  EXPECT_EQ(r.relations, 3u);
  EXPECT_EQ(r.used, 2u);
  EXPECT_EQ(r.skipped, 1u);
  ASSERT_EQ(r.skippedRelations.size(), 1u);
  EXPECT_EQ(r.skippedRelations[0], 2u);
  ASSERT_EQ(r.translationErrors.size(), 2u);
  EXPECT_NEAR(r.translationErrors[0], 0.0, 1e-12);
  EXPECT_NEAR(r.translationErrors[1], 0.1, 1e-12);
  EXPECT_NEAR(r.rotationErrors[1], 0.05 * 180 / M_PI, 1e-9);
  EXPECT_NEAR(r.translation.mean, 0.05, 1e-12);
  EXPECT_NEAR(r.translation.std, 0.05, 1e-12);
  EXPECT_NEAR(r.rotation.mean, 0.025 * 180 / M_PI, 1e-9);
  EXPECT_NEAR(r.rotation.std, 0.025 * 180 / M_PI, 1e-9);
  EXPECT_NEAR(r.translationSquaredMean, 0.005, 1e-12);

  // Stamps are matched within the tolerance only.
  rtabmap::RelationOptions tight;
  Trajectory shifted;
  for (const auto& p : estimate().poses) shifted.add(p.stamp + 0.002, p.pose);
  EXPECT_THROW(rtabmap::computeRelationError(shifted, relations, tight), FormatError);
  tight.maxTimeDifference = 0.003;
  EXPECT_EQ(rtabmap::computeRelationError(shifted, relations, tight).used, 2u);
}

// Local (short in time) and loop relations are scored apart as well as together.
TEST(RelationError, LocalAndLoopRelationsApart) {
  TempDir dir;
  writeText(dir.file("r.relations"),
            "1.0 2.0 1 0 0 0 0 1.5707963267948966\n"  // 1 s apart, exact
            "2.0 3.0 1 0.1 0 0 0 0.05\n"              // 1 s apart, 0.1 m / 0.05 rad off
            "1.0 3.0 1 1.3 0 0 0 1.5707963267948966\n");  // 2 s apart, 0.3 m off
  const std::vector<Relation> relations = rtabmap::readRelations(dir.file("r.relations"));
  rtabmap::RelationOptions options;
  options.localSpan = 1.5;
  const rtabmap::RelationResult r = rtabmap::computeRelationError(estimate(), relations, options);
  ASSERT_EQ(r.used, 3u);
  EXPECT_EQ(r.localTranslation.count, 2u);
  EXPECT_NEAR(r.localTranslation.mean, 0.05, 1e-12);
  EXPECT_NEAR(r.localRotation.max, 0.05 * 180 / M_PI, 1e-9);
  EXPECT_EQ(r.loopTranslation.count, 1u);
  EXPECT_NEAR(r.loopTranslation.mean, 0.3, 1e-12);
  EXPECT_NEAR(r.loopRotation.mean, 0.0, 1e-9);
  EXPECT_NEAR(r.translation.mean, 0.4 / 3, 1e-12);  // the whole is unchanged by the split

  options.localSpan = 2.0;  // the span is inclusive
  EXPECT_EQ(rtabmap::computeRelationError(estimate(), relations, options).localTranslation.count, 3u);
  options.localSpan = 0.0;  // no split
  const rtabmap::RelationResult none = rtabmap::computeRelationError(estimate(), relations, options);
  EXPECT_EQ(none.localTranslation.count + none.loopTranslation.count, 0u);
}

TEST(RelationError, RelationsAreFrameIndependent) {
  // The same estimate moved anywhere in the world scores the same.
  TempDir dir;
  writeText(dir.file("r.relations"), "1.0 2.0 1 0 0 0 0 1.5707963267948966\n2.0 3.0 1 0.1 0 0 0 0.05\n");
  const auto relations = rtabmap::readRelations(dir.file("r.relations"));
  Trajectory moved;
  const Transform T(5, -3, 0.7);
  for (const auto& p : estimate().poses) moved.add(p.stamp, T * p.pose);
  const auto a = rtabmap::computeRelationError(estimate(), relations);
  const auto b = rtabmap::computeRelationError(moved, relations);
  EXPECT_NEAR(a.translation.mean, b.translation.mean, 1e-12);
  EXPECT_NEAR(a.rotation.mean, b.rotation.mean, 1e-9);
}

// Triangles of a relations file: the sides a->b, b->c, a->c of a consistent file compose to the
// identity, whichever way a side is given; a side off by 3 cm shows as 3 cm; instants match
// within the stamp tolerance; pairs without a third side are no triangle.
TEST(RelationError, ReferenceConsistencyFromTriangles) {
  const Transform x1(0, 0, 0), x2(1, 0, M_PI / 2), x3(1, 1, M_PI / 2), x4(3, 1, 0);
  auto relation = [](double t1, double t2, const Transform& a, const Transform& b) {
    Relation r;
    r.stamp1 = t1;
    r.stamp2 = t2;
    r.pose = a.inverse() * b;
    return r;
  };
  std::vector<Relation> rel = {relation(1, 2, x1, x2), relation(2, 3, x2, x3), relation(3.0005, 1, x3, x1),
                               relation(3, 4, x3, x4)};
  rtabmap::RelationConsistency c = rtabmap::relationConsistency(rel);
  EXPECT_EQ(c.triangles, 1u);
  EXPECT_NEAR(c.translation.max, 0.0, 1e-12);
  EXPECT_NEAR(c.rotation.max, 0.0, 1e-9);

  rel[1].pose = Transform(0, 0.03, 0) * rel[1].pose;  // b->c 3 cm off
  c = rtabmap::relationConsistency(rel);
  ASSERT_EQ(c.triangles, 1u);
  EXPECT_NEAR(c.translation.mean, 0.03, 1e-9);
  EXPECT_NEAR(c.relationRms, 0.03 / std::sqrt(3.0), 1e-9);

  rel.push_back(relation(1, 4, x1, x4));  // a second triangle 1-3-4, without the bad side
  c = rtabmap::relationConsistency(rel);
  EXPECT_EQ(c.triangles, 2u);
  EXPECT_NEAR(c.translation.max, 0.03, 1e-9);
  EXPECT_NEAR(c.translation.min, 0.0, 1e-9);

  // 3.0005 is no longer instant 3: neither triangle has its side 1-3.
  EXPECT_EQ(rtabmap::relationConsistency(rel, 1e-4).triangles, 0u);
  EXPECT_EQ(rtabmap::relationConsistency({relation(1, 2, x1, x2), relation(2, 3, x2, x3)}).triangles, 0u);
}

TEST(RelationError, MalformedRelationsNameFileAndLine) {
  TempDir dir;
  writeText(dir.file("bad.relations"), "1.0 2.0 1 0 0 0 0 0\n1.0 2.0 1 0 0 0 0\n");
  try {
    rtabmap::readRelations(dir.file("bad.relations"));
    ADD_FAILURE();
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.relations:2:"), std::string::npos) << e.what();
  }
  writeText(dir.file("empty.relations"), "# none\n");
  EXPECT_THROW(rtabmap::readRelations(dir.file("empty.relations")), FormatError);
}

TEST(RelationError, WorstRelationsLargestFirstAndIndexTheInput) {
  // Relations 0 (0.25 m off), 1 (skipped: no pose at 9), 2 (exact), 3 (0.5 m off), 4 (0.25 m
  // off; binary fractions, so the two ties are exact).
  Trajectory t;
  t.add(1.0, Transform(0, 0, 0));
  t.add(2.0, Transform(1, 0, 0));
  const auto rel = [](double t1, double t2, double x) {
    Relation r;
    r.stamp1 = t1;
    r.stamp2 = t2;
    r.pose = Transform(x, 0, 0);
    return r;
  };
  const std::vector<Relation> relations = {rel(1, 2, 1.25), rel(1, 9, 1), rel(1, 2, 1), rel(1, 2, 0.5),
                                           rel(1, 2, 0.75)};
  const rtabmap::RelationResult r = rtabmap::computeRelationError(t, relations);
  ASSERT_EQ(r.usedRelations, (std::vector<size_t>{0, 2, 3, 4}));
  const std::vector<size_t> worst = rtabmap::worstRelations(r, 3);
  // Result indices: 0.5 m (input 3), then the two 0.25 m ones in input order (0, then 4).
  ASSERT_EQ(worst, (std::vector<size_t>{2, 0, 3}));
  EXPECT_NEAR(r.translationErrors[worst[0]], 0.5, 1e-12);
  EXPECT_EQ(r.usedRelations[worst[0]], 3u);
  EXPECT_EQ(r.usedRelations[worst[2]], 4u);
  EXPECT_EQ(rtabmap::worstRelations(r, 10).size(), 4u);  // never more than the used ones
  EXPECT_TRUE(rtabmap::worstRelations(r, 0).empty());
}
