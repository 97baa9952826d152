#pragma once
// Deterministic randomness for the simulator. A seed must give the same world, trajectory and
// sensor noise on every run, so nothing here depends on std::random_device, on thread timing,
// or on the standard library's distributions (whose algorithms are implementation-defined and
// differ between libstdc++ and libc++). The generator is SplitMix64; uniform numbers take its
// top 53 bits; normal numbers come from the Box-Muller transform.
//
// Independent sub-streams are derived from the seed and a name ("odometry", "imu", ...), so
// adding a sensor or drawing one more number in one module never shifts the numbers of another.
#include <cstdint>
#include <string>
#include <vector>

namespace rtabmap::sim {

// SplitMix64 finaliser: every input bit flips about half of the output bits.
uint64_t mix64(uint64_t x);
// Hash of a value into a running hash (order matters).
uint64_t hashCombine(uint64_t hash, uint64_t value);
// FNV-1a of the bytes, then mix64: names of sub-streams.
uint64_t hashString(const std::string& text);
// Fast 32-bit hash of a lattice point, for procedural textures (called per texel).
inline uint32_t hash2D(int32_t x, int32_t y, uint32_t seed) {
  uint32_t h = static_cast<uint32_t>(x) * 0x8da6b343u ^ static_cast<uint32_t>(y) * 0xd8163841u ^
               seed * 0xcb1ab31fu;
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return h;
}
// [0, 1) from a 32-bit hash.
inline float hashUnit(uint32_t h) { return static_cast<float>(h >> 8) * (1.0f / 16777216.0f); }

class Rng {
 public:
  explicit Rng(uint64_t seed);
  // The sub-stream `stream` of `seed`.
  Rng(uint64_t seed, const std::string& stream);

  uint64_t next();
  double uniform();                      // [0, 1)
  double uniform(double lo, double hi);  // [lo, hi)
  int uniformInt(int lo, int hi);        // [lo, hi], both included
  bool chance(double probability);
  double normal();  // N(0, 1)
  double normal(double mean, double sigma) { return mean + sigma * normal(); }
  // A seed for a child generator or a procedural texture.
  uint32_t seed32() { return static_cast<uint32_t>(next() >> 32); }

  template <class T>
  const T& pick(const std::vector<T>& values) {
    return values[static_cast<size_t>(uniformInt(0, static_cast<int>(values.size()) - 1))];
  }
  // Index drawn with probability proportional to its weight (weights >= 0, not all 0).
  int weighted(const std::vector<double>& weights);

 private:
  uint64_t state_;
  bool hasSpare_ = false;
  double spare_ = 0.0;
};

}  // namespace rtabmap::sim
