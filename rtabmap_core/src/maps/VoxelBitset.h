#pragma once
// A set of OcTree keys inside a box, one bit per voxel, laid out in the tree's own order so
// that it can be read back sorted by Morton code (the order OctreeBatch descends in) without a
// sort of the voxels. Internal to the maps area.
//
// Layout: "superbricks" of 16x16x16 voxels aligned on multiples of 16 keys, each 64 words of 64
// bits. Inside a superbrick the word is the Morton code of the 4x4x4 brick (key bits 2-3) and
// the bit the Morton code of the voxel in its brick (key bits 0-1): reading a superbrick's words
// and bits in increasing order gives its voxels in increasing Morton code. Superbricks are
// aligned octree nodes, so sorting the few non-empty ones by their own Morton code orders all.
//
// Why bits rather than a hash set or a stamp per voxel: a ray marks a voxel with one OR, without
// a test, and consecutive voxels of a ray lie in the same 512-byte superbrick, so the set of a
// whole 4 m frame (a few MB of voxels) stays in cache.
#include <octomap/OcTreeKey.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace rtabmap::maps_detail {

// The 16 bits of v spread to every third bit (bit i -> bit 3i).
inline uint64_t spreadBits3(uint64_t v) {
  v &= 0xFFFFull;
  v = (v | (v << 16)) & 0x0000FF0000FFull;
  v = (v | (v << 8)) & 0x00F00F00F00Full;
  v = (v | (v << 4)) & 0x0C30C30C30C3ull;
  v = (v | (v << 2)) & 0x249249249249ull;
  return v;
}

// Morton code of a key: 3 bits per level, root level first; each 3-bit group is the child index
// OcTree uses at that level (bit 0 from x, 1 from y, 2 from z).
inline uint64_t mortonCode(const octomap::OcTreeKey& k) {
  return spreadBits3(k[0]) | (spreadBits3(k[1]) << 1) | (spreadBits3(k[2]) << 2);
}

// The 2 bits of v spread to bits 0 and 3.
inline unsigned spread2(unsigned v) { return (v & 1u) | ((v & 2u) << 2); }

class VoxelBitset {
 public:
  static constexpr unsigned kSuperShift = 4;  // 16 voxels per superbrick side
  static constexpr size_t kWordsPerSuper = 64;
  // Boxes up to this many superbricks (64 M voxels, 8 MB of bits) use a bitset.
  static constexpr size_t kMaxSupers = size_t(16) << 10;

  // Covers the keys lo..hi (inclusive) and empties the set. False when the box is too large.
  bool reset(const octomap::OcTreeKey& lo, const octomap::OcTreeKey& hi) {
    size_t n = 1;
    for (int a = 0; a < 3; ++a) {
      lo_[a] = lo[a] >> kSuperShift;
      size_[a] = (hi[a] >> kSuperShift) - lo_[a] + 1u;
      n *= size_[a];
    }
    if (n > kMaxSupers) return false;
    words_.assign(n * kWordsPerSuper, 0u);
    buildAxisTables();
    return true;
  }
  // set(k) when k is in the box, else false. For walks that mark one voxel per step: the word
  // and bit come from three small per-axis tables (a few hundred entries each, in L1) instead of
  // being computed from the key's bits every step.
  bool trySet(unsigned k0, unsigned k1, unsigned k2) {
    const unsigned i0 = k0 - base_[0], i1 = k1 - base_[1], i2 = k2 - base_[2];
    if (i0 >= extent_[0] || i1 >= extent_[1] || i2 >= extent_[2]) return false;
    words_[wordPart_[0][i0] + wordPart_[1][i1] + wordPart_[2][i2]] |=
        uint64_t(1) << (bitPart_[0][i0] | bitPart_[1][i1] | bitPart_[2][i2]);
    return true;
  }
  bool contains(const octomap::OcTreeKey& k) const {
    for (int a = 0; a < 3; ++a) {
      const unsigned s = k[a] >> kSuperShift;
      if (s < lo_[a] || s - lo_[a] >= size_[a]) return false;
    }
    return true;
  }
  // k must be in the box (contains()).
  void set(const octomap::OcTreeKey& k) { words_[word(k)] |= bit(k); }
  bool test(const octomap::OcTreeKey& k) const { return (words_[word(k)] & bit(k)) != 0; }

  // Keys of (a | b) & ~mask (three sets over the same box; b and mask may be null), appended to
  // `out` in increasing Morton code.
  static void collect(const VoxelBitset& a, const VoxelBitset* b, const VoxelBitset* mask,
                      std::vector<octomap::OcTreeKey>& out);

 private:
  size_t word(const octomap::OcTreeKey& k) const {
    const size_t super =
        (size_t((k[0] >> kSuperShift) - lo_[0]) * size_[1] + size_t((k[1] >> kSuperShift) - lo_[1])) * size_[2] +
        size_t((k[2] >> kSuperShift) - lo_[2]);
    const unsigned brick = spread2((k[0] >> 2) & 3u) | (spread2((k[1] >> 2) & 3u) << 1) | (spread2((k[2] >> 2) & 3u) << 2);
    return super * kWordsPerSuper + brick;
  }
  static uint64_t bit(const octomap::OcTreeKey& k) {
    return uint64_t(1) << (spread2(k[0] & 3u) | (spread2(k[1] & 3u) << 1) | (spread2(k[2] & 3u) << 2));
  }

  // Each axis's share of word() and of bit()'s shift, by key offset from the box's first key.
  void buildAxisTables() {
    const size_t stride[3] = {size_t(size_[1]) * size_[2], size_[2], 1};
    for (int a = 0; a < 3; ++a) {
      base_[a] = lo_[a] << kSuperShift;
      extent_[a] = size_[a] << kSuperShift;
      wordPart_[a].resize(extent_[a]);
      bitPart_[a].resize(extent_[a]);
      for (unsigned i = 0; i < extent_[a]; ++i) {
        wordPart_[a][i] = (i >> kSuperShift) * stride[a] * kWordsPerSuper + (spread2((i >> 2) & 3u) << a);
        bitPart_[a][i] = static_cast<uint8_t>(spread2(i & 3u) << a);
      }
    }
  }

  std::vector<uint64_t> words_;
  unsigned lo_[3] = {0, 0, 0};
  unsigned size_[3] = {0, 0, 0};
  unsigned base_[3] = {0, 0, 0};
  unsigned extent_[3] = {0, 0, 0};
  std::vector<size_t> wordPart_[3];
  std::vector<uint8_t> bitPart_[3];
};

// The 6-bit Morton code m split back into its 2-bit x, y, z parts.
inline void unspread2(unsigned m, unsigned& x, unsigned& y, unsigned& z) {
  x = (m & 1u) | ((m >> 2) & 2u);
  y = ((m >> 1) & 1u) | ((m >> 3) & 2u);
  z = ((m >> 2) & 1u) | ((m >> 4) & 2u);
}

inline void VoxelBitset::collect(const VoxelBitset& a, const VoxelBitset* b, const VoxelBitset* mask,
                                 std::vector<octomap::OcTreeKey>& out) {
  // Non-empty superbricks sorted by their Morton code.
  struct Super {
    uint64_t morton;
    size_t index;
    unsigned s[3];
  };
  std::vector<Super> supers;
  size_t index = 0;
  for (unsigned sx = 0; sx < a.size_[0]; ++sx) {
    for (unsigned sy = 0; sy < a.size_[1]; ++sy) {
      for (unsigned sz = 0; sz < a.size_[2]; ++sz, ++index) {
        uint64_t any = 0;
        const size_t w0 = index * kWordsPerSuper;
        for (size_t w = w0; w < w0 + kWordsPerSuper; ++w) any |= a.words_[w] | (b ? b->words_[w] : 0u);
        if (!any) continue;
        Super s{0, index, {a.lo_[0] + sx, a.lo_[1] + sy, a.lo_[2] + sz}};
        s.morton = spreadBits3(s.s[0]) | (spreadBits3(s.s[1]) << 1) | (spreadBits3(s.s[2]) << 2);
        supers.push_back(s);
      }
    }
  }
  std::sort(supers.begin(), supers.end(), [](const Super& l, const Super& r) { return l.morton < r.morton; });
  for (const Super& s : supers) {
    const size_t w0 = s.index * kWordsPerSuper;
    for (unsigned brick = 0; brick < kWordsPerSuper; ++brick) {
      uint64_t bits = a.words_[w0 + brick] | (b ? b->words_[w0 + brick] : 0u);
      if (mask) bits &= ~mask->words_[w0 + brick];
      if (!bits) continue;
      unsigned bx, by, bz;
      unspread2(brick, bx, by, bz);
      while (bits) {
        const unsigned v = static_cast<unsigned>(__builtin_ctzll(bits));
        bits &= bits - 1;
        unsigned vx, vy, vz;
        unspread2(v, vx, vy, vz);
        out.emplace_back(static_cast<octomap::key_type>((s.s[0] << kSuperShift) | (bx << 2) | vx),
                         static_cast<octomap::key_type>((s.s[1] << kSuperShift) | (by << 2) | vy),
                         static_cast<octomap::key_type>((s.s[2] << kSuperShift) | (bz << 2) | vz));
      }
    }
  }
}

}  // namespace rtabmap::maps_detail
