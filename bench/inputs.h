// Random inputs for the benchmarks: float matrices of N(0, 1) entries from the project's Rng.
#pragma once
#include "core/rng.h"
#include "nn/tape.h"

namespace df::bench {

inline nn::Matrix<float> randn(Eigen::Index rows, Eigen::Index cols, Rng& rng) {
  nn::Matrix<float> m(rows, cols);
  for (Eigen::Index k = 0; k < m.size(); ++k) m.data()[k] = static_cast<float>(rng.normal());
  return m;
}

}  // namespace df::bench
