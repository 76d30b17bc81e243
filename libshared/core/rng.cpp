#include "core/rng.h"

#include <cmath>
#include <numbers>

namespace df {

std::uint64_t splitmix64(std::uint64_t& x) {
  std::uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

Rng::Rng(std::uint64_t seed, std::uint64_t index) {
  // Mix seed and index separately so (s, i) and (s', i') collide only by chance.
  std::uint64_t a = seed;
  std::uint64_t key = splitmix64(a);
  std::uint64_t b = index ^ 0x6a09e667f3bcc909ULL;
  key ^= splitmix64(b) * 0x9e3779b97f4a7c15ULL;
  for (auto& w : s_) w = splitmix64(key);
}

static inline std::uint64_t rotl(std::uint64_t x, int k) {
  return (x << k) | (x >> (64 - k));
}

std::uint64_t Rng::next() {
  const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
  const std::uint64_t t = s_[1] << 17;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = rotl(s_[3], 45);
  return result;
}

double Rng::uniform() {
  return static_cast<double>(next() >> 11) * 0x1.0p-53;
}

std::uint64_t Rng::below(std::uint64_t n) {
  // Rejection sampling: draws in the last incomplete block of n are redrawn (no modulo bias).
  const std::uint64_t limit = max() - max() % n;
  std::uint64_t x = next();
  while (x >= limit) x = next();
  return x % n;
}

double Rng::normal() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  double u1 = 0.0;
  while (u1 <= 0.0) u1 = uniform();
  double u2 = uniform();
  double r = std::sqrt(-2.0 * std::log(u1));
  double a = 2.0 * std::numbers::pi * u2;
  spare_ = r * std::sin(a);
  has_spare_ = true;
  return r * std::cos(a);
}

void Rng::restore(const State& s, bool has_spare, double spare) {
  s_ = s;
  has_spare_ = has_spare;
  spare_ = spare;
}

}  // namespace df
