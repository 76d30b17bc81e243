// The network engine's matrix product (internal to libshared/nn): C (+)= op(A) · op(B) split
// into blocks that never depend on the thread count, so results are the same at any --threads.
#pragma once

#include <tbb/parallel_for.h>

#include <Eigen/Core>

#include "nn/tape.h"

namespace df::nn::detail {
using Eigen::Index;

// C (+)= op(A) · op(B), split into fixed blocks of output rows (or, for few rows, of output
// columns: the BD-LSTM's [16 × 26136] × [26136 × 256]) computed in parallel. The block size
// never depends on the thread count, so every element is summed in the same order at any
// --threads (Eigen's blocking depends on the block's shape only).
constexpr Index kRowBlock = 64, kColBlock = 128;

template <class T, class DstXpr, class LhsXpr, class RhsXpr>
void parallel_product(DstXpr&& dst, const LhsXpr& lhs, const RhsXpr& rhs, bool accumulate_into) {
  const Index rows = dst.rows(), cols = dst.cols();
  const double work =
      static_cast<double>(rows) * static_cast<double>(cols) * static_cast<double>(lhs.cols());
  if (rows < 2 * kRowBlock && cols >= 2 * kColBlock && work >= 4e6) {
    tbb::parallel_for(Index{0}, (cols + kColBlock - 1) / kColBlock, [&](Index b) {
      const Index c0 = b * kColBlock, n = std::min(kColBlock, cols - c0);
      if (accumulate_into)
        dst.middleCols(c0, n).noalias() += lhs * rhs.middleCols(c0, n);
      else
        dst.middleCols(c0, n).noalias() = lhs * rhs.middleCols(c0, n);
    });
    return;
  }
  if (rows < 2 * kRowBlock || work < 4e6) {  // small: one product
    if (accumulate_into)
      dst.noalias() += lhs * rhs;
    else
      dst.noalias() = lhs * rhs;
    return;
  }
  const Index blocks = (rows + kRowBlock - 1) / kRowBlock;
  tbb::parallel_for(Index{0}, blocks, [&](Index b) {
    const Index r0 = b * kRowBlock, n = std::min(kRowBlock, rows - r0);
    if (accumulate_into)
      dst.middleRows(r0, n).noalias() += lhs.middleRows(r0, n) * rhs;
    else
      dst.middleRows(r0, n).noalias() = lhs.middleRows(r0, n) * rhs;
  });
}

// Node id's gradient (+)= op(A) · op(B) (= on its first use).
template <class T, class LhsXpr, class RhsXpr>
void product_into_grad(Tape<T>& t, int id, const LhsXpr& lhs, const RhsXpr& rhs) {
  bool add = false;
  Matrix<T>& g = t.grad_to_update(id, add);
  parallel_product<T>(g, lhs, rhs, add);
}

}  // namespace df::nn::detail
