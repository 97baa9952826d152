// The OctoMap's fast free-space path: VoxelBitset gives back exactly the keys set, in increasing
// Morton code (the octree's order), its table-driven trySet marks what set marks, and RayCaster gives the same free voxels as liboctomap's
// computeRayKeys into a hash set minus the occupied ones (as insertPointCloud does), sorted,
// with the bitset (small box, one and two threads) and with the hash set fallback (huge box).
#include <gtest/gtest.h>

#include <octomap/OcTree.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "../../src/maps/RayCaster.h"
#include "../../src/maps/VoxelBitset.h"
#include "common/TestData.h"

using rtabmap::maps_detail::mortonCode;
using rtabmap::maps_detail::RayCaster;
using rtabmap::maps_detail::VoxelBitset;

namespace {

std::vector<uint64_t> codes(const std::vector<octomap::OcTreeKey>& keys) {
  std::vector<uint64_t> out;
  for (const octomap::OcTreeKey& k : keys) out.push_back(mortonCode(k));
  return out;
}

// The straightforward free set, as sorted Morton codes.
std::vector<uint64_t> referenceFree(const octomap::OcTree& tree, const octomap::point3d& origin,
                                    const std::vector<octomap::point3d>& ends, float maxRange) {
  octomap::KeySet free, occupied;
  octomap::KeyRay ray;
  for (const octomap::point3d& e : ends) occupied.insert(tree.coordToKey(e));
  for (const octomap::point3d& e : ends) {
    octomap::point3d end = e;
    bool cut = false;
    const double len = (e - origin).norm();
    if (maxRange > 0.0f && len > maxRange) {
      end = origin + (e - origin) * static_cast<float>(maxRange / len);
      cut = true;
    }
    if (!tree.computeRayKeys(origin, end, ray)) continue;
    free.insert(ray.begin(), ray.end());
    if (cut) free.insert(tree.coordToKey(end));
  }
  std::vector<uint64_t> out;
  for (const octomap::OcTreeKey& k : free) {
    if (!occupied.count(k)) out.push_back(mortonCode(k));
  }
  std::sort(out.begin(), out.end());
  return out;
}

// End points on a sphere of the given radius around the origin (a room seen from its middle).
std::vector<octomap::point3d> sphere(const octomap::point3d& origin, float radius, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> n(0.0f, 1.0f);
  std::uniform_real_distribution<float> r(0.3f, 1.0f);
  std::vector<octomap::point3d> out;
  for (int i = 0; i < count; ++i) {
    octomap::point3d d{n(rng), n(rng), n(rng)};  // braces: drawn in order
    d.normalize();
    out.push_back(origin + d * (radius * r(rng)));
  }
  return out;
}

void expectSameAsReference(size_t rays, float radius, float maxRange) {
  const octomap::OcTree tree(0.05);
  const octomap::point3d origin(0.013f, -0.021f, 0.37f);  // across the keys' sign boundary
  const std::vector<octomap::point3d> ends = sphere(origin, radius, static_cast<int>(rays), rtabmap::test::drawSeed(7));
  std::vector<octomap::OcTreeKey> occupied;
  for (const octomap::point3d& e : ends) occupied.push_back(tree.coordToKey(e));
  RayCaster caster;
  std::vector<octomap::OcTreeKey> free;
  EXPECT_EQ(caster.cast(tree, origin, ends, occupied, maxRange, free), rays);
  const std::vector<uint64_t> got = codes(free);
  EXPECT_TRUE(std::is_sorted(got.begin(), got.end()));
  EXPECT_EQ(std::adjacent_find(got.begin(), got.end()), got.end()) << "a voxel came out twice";
  const std::vector<uint64_t> want = referenceFree(tree, origin, ends, maxRange);
  EXPECT_GT(want.size(), rays);
  EXPECT_TRUE(got == want) << got.size() << " free voxels vs " << want.size();
}

}  // namespace

TEST(OctoMapVoxelBitset, GivesBackTheKeysSetInMortonOrder) {
  std::mt19937 rng(rtabmap::test::drawSeed(3));
  std::uniform_int_distribution<int> d(-70, 70);
  const octomap::OcTreeKey lo(32768 - 70, 32768 - 70, 32768 - 70), hi(32768 + 70, 32768 + 70, 32768 + 70);
  VoxelBitset a, b, mask;
  ASSERT_TRUE(a.reset(lo, hi));
  ASSERT_TRUE(b.reset(lo, hi));
  ASSERT_TRUE(mask.reset(lo, hi));
  std::vector<uint64_t> want;
  std::vector<uint64_t> masked;
  for (int i = 0; i < 20000; ++i) {
    const octomap::OcTreeKey k{static_cast<octomap::key_type>(32768 + d(rng)), static_cast<octomap::key_type>(32768 + d(rng)),
                               static_cast<octomap::key_type>(32768 + d(rng))};
    ASSERT_TRUE(a.contains(k));
    if (i % 10 == 0) {
      mask.set(k);
      masked.push_back(mortonCode(k));
    }
    (i % 2 ? a : b).set(k);
    EXPECT_TRUE((i % 2 ? a : b).test(k));
    want.push_back(mortonCode(k));
  }
  std::sort(want.begin(), want.end());
  want.erase(std::unique(want.begin(), want.end()), want.end());
  std::sort(masked.begin(), masked.end());
  std::vector<uint64_t> wantMasked;
  std::set_difference(want.begin(), want.end(), masked.begin(), masked.end(), std::back_inserter(wantMasked));
  std::vector<octomap::OcTreeKey> keys;
  VoxelBitset::collect(a, &b, nullptr, keys);
  EXPECT_TRUE(codes(keys) == want);
  keys.clear();
  VoxelBitset::collect(a, &b, &mask, keys);
  EXPECT_TRUE(codes(keys) == wantMasked);
  EXPECT_FALSE(a.contains(octomap::OcTreeKey(32768 + 200, 32768, 32768)));
  // A box too large for bits is refused (the caller then uses a hash set).
  EXPECT_FALSE(a.reset(octomap::OcTreeKey(0, 0, 0), octomap::OcTreeKey(4000, 4000, 4000)));
}

TEST(OctoMapVoxelBitset, TrySetMarksWhatSetMarksAndRefusesKeysOutsideTheBox) {
  // A box not aligned on superbricks, keys across its edges: the per-axis tables must give the
  // same word and bit as set(), and every key just outside must be refused.
  const octomap::OcTreeKey lo(32768 - 37, 32768 + 5, 32768 - 70), hi(32768 + 21, 32768 + 90, 32768 - 2);
  VoxelBitset bySet, byTry;
  ASSERT_TRUE(bySet.reset(lo, hi));
  ASSERT_TRUE(byTry.reset(lo, hi));
  std::mt19937 rng(rtabmap::test::drawSeed(5));
  std::uniform_int_distribution<int> d(-40, 120);
  int inside = 0, outside = 0;
  for (int i = 0; i < 20000; ++i) {
    const octomap::OcTreeKey k{static_cast<octomap::key_type>(32768 + d(rng) - 40), static_cast<octomap::key_type>(32768 + d(rng)),
                               static_cast<octomap::key_type>(32768 + d(rng) - 100)};
    const bool in = bySet.contains(k);
    EXPECT_EQ(byTry.trySet(k[0], k[1], k[2]), in);
    if (!in) {
      ++outside;
      continue;
    }
    ++inside;
    bySet.set(k);
    EXPECT_TRUE(byTry.test(k));
  }
  EXPECT_GT(inside, 1000);
  EXPECT_GT(outside, 1000);
  std::vector<octomap::OcTreeKey> a, b;
  VoxelBitset::collect(bySet, nullptr, nullptr, a);
  VoxelBitset::collect(byTry, nullptr, nullptr, b);
  EXPECT_TRUE(codes(a) == codes(b));
}

TEST(OctoMapRayCaster, OneThreadBitsetMatchesComputeRayKeys) { expectSameAsReference(300, 3.0f, 0.0f); }

TEST(OctoMapRayCaster, TwoThreadsBitsetMatchesComputeRayKeys) {
  expectSameAsReference(4 * RayCaster::kMinRaysPerThread, 4.0f, 0.0f);
  expectSameAsReference(4 * RayCaster::kMinRaysPerThread, 4.0f, 2.5f);  // truncated rays keep their last voxel
}

TEST(OctoMapRayCaster, HugeBoxFallsBackToAHashSetWithTheSameResult) {
  // 30 m rays at 5 cm: a box of 1,200 voxels a side, more than a bitset takes.
  expectSameAsReference(600, 30.0f, 0.0f);
}
