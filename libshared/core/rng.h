// Deterministic random streams keyed by (seed, index), never by thread: work item i always
// draws from Rng(seed, i), so results do not depend on the thread count. The generator is
// xoshiro256** (Blackman & Vigna) seeded through SplitMix64; its whole state is 4 words, so a
// training run can save and restore it bit-exactly.
#pragma once

#include <array>
#include <cstdint>

namespace df {

class Rng {
 public:
  using State = std::array<std::uint64_t, 4>;
  using result_type = std::uint64_t;

  /// Stream `index` of `seed`. Different (seed, index) pairs give independent streams.
  explicit Rng(std::uint64_t seed = 0, std::uint64_t index = 0);

  std::uint64_t next();
  std::uint64_t operator()() { return next(); }
  static constexpr std::uint64_t min() { return 0; }
  static constexpr std::uint64_t max() { return ~std::uint64_t{0}; }

  /// Uniform in [0, 1) with 53 random bits.
  double uniform();
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n) without modulo bias. n > 0.
  std::uint64_t below(std::uint64_t n);
  /// Standard normal (Box-Muller; the second value of each pair is kept for the next call).
  double normal();
  double normal(double mean, double stddev) { return mean + stddev * normal(); }

  /// The full state, for checkpoints. restore(state()) continues the same sequence.
  State state() const { return s_; }
  bool has_spare_normal() const { return has_spare_; }
  double spare_normal() const { return spare_; }
  void restore(const State& s, bool has_spare = false, double spare = 0.0);

 private:
  State s_{};
  bool has_spare_ = false;
  double spare_ = 0.0;
};

/// SplitMix64 step: a good 64-bit mixing function.
std::uint64_t splitmix64(std::uint64_t& x);

}  // namespace df
