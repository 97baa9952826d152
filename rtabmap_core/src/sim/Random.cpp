#include "rtabmap_core/sim/Random.h"

#include <cmath>
#include <stdexcept>

namespace rtabmap::sim {

uint64_t mix64(uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

uint64_t hashCombine(uint64_t hash, uint64_t value) {
  return mix64(hash ^ (value + 0x9e3779b97f4a7c15ULL + (hash << 6) + (hash >> 2)));
}

uint64_t hashString(const std::string& text) {
  uint64_t h = 0xcbf29ce484222325ULL;
  for (unsigned char c : text) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return mix64(h);
}

Rng::Rng(uint64_t seed) : state_(mix64(seed ^ 0x243f6a8885a308d3ULL)) {}

Rng::Rng(uint64_t seed, const std::string& stream) : Rng(hashCombine(seed, hashString(stream))) {}

uint64_t Rng::next() {
  state_ += 0x9e3779b97f4a7c15ULL;
  return mix64(state_);
}

double Rng::uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

double Rng::uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

int Rng::uniformInt(int lo, int hi) {
  if (hi < lo) throw std::invalid_argument("Rng::uniformInt: empty range");
  const uint64_t span = static_cast<uint64_t>(static_cast<int64_t>(hi) - lo) + 1;
  // Multiply-shift: unbiased enough for the small spans the simulator draws from.
  const unsigned __int128 wide = static_cast<unsigned __int128>(next()) * span;
  return lo + static_cast<int>(static_cast<uint64_t>(wide >> 64));
}

bool Rng::chance(double probability) { return uniform() < probability; }

double Rng::normal() {
  if (hasSpare_) {
    hasSpare_ = false;
    return spare_;
  }
  double u1 = uniform();
  while (u1 <= 1e-300) u1 = uniform();
  const double u2 = uniform();
  const double radius = std::sqrt(-2.0 * std::log(u1));
  const double angle = 2.0 * M_PI * u2;
  spare_ = radius * std::sin(angle);
  hasSpare_ = true;
  return radius * std::cos(angle);
}

int Rng::weighted(const std::vector<double>& weights) {
  double total = 0.0;
  for (double w : weights) total += w;
  if (weights.empty() || total <= 0.0) throw std::invalid_argument("Rng::weighted: no positive weight");
  double r = uniform() * total;
  for (size_t i = 0; i < weights.size(); ++i) {
    if (r < weights[i]) return static_cast<int>(i);
    r -= weights[i];
  }
  return static_cast<int>(weights.size()) - 1;
}

}  // namespace rtabmap::sim
