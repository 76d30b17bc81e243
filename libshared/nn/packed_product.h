// The network engine's product with a right-hand matrix that is used many times in a row
// (internal to libshared/nn): an LSTM's recurrent weights, multiplied at every step of a
// sequence (forward h_{t-1} · W_h, backward dZ_t · W_hᵀ), and the sequence's input and weight
// products. Eigen packs both operands into its own blocked layout at every product — W_h [256 ×
// 1024] again at each of 50 steps; packing was about 16% of an ActGAN iteration — and its kernel
// ran these shapes at 64-82 GFLOP/s. Here op(W) is packed once into panels two vectors wide
// (k-major, zero-padded), and each product runs register tiles of a few rows × one panel over k
// (104-114 GFLOP/s on the same core; bench_packed_product, numbers in packed_product.cpp).
//
// Every output element is one running sum over k in order, added to (or stored in) C at the
// end, so results never depend on the thread count (threads share out whole panels).
#pragma once

#include <Eigen/Core>
#include <type_traits>
#include <vector>

#include "nn/tape.h"

namespace df::nn::detail {
using Eigen::Index;

/// op(W) [K × N] packed into panels of columns: panel p holds columns p·width .. p·width +
/// width − 1, row k of the panel at data[(p·K + k)·width].
template <class T>
struct PackedRhs {
  Index k = 0, n = 0, width = 0;
  std::vector<T> data;
};

/// Packs W (or Wᵀ when `transpose`).
template <class T>
PackedRhs<T> pack_rhs(const Matrix<T>& w, bool transpose);

/// C (+)= A · op(W) for A [m × K] with element (r, k) at a[r·rs + k·cs] and row-major C [m × N]
/// (row stride ldc).
template <class T>
void packed_product(T* c, Index ldc, const T* a, Index rs, Index cs, Index m, const PackedRhs<T>& w,
                    bool accumulate_into);

/// The same on Eigen blocks: C row-major with contiguous rows (a Matrix<T> or its middleRows),
/// A any directly stored matrix (also the transpose of one).
template <class T, class Dst, class Lhs>
void packed_product(Dst&& c, const Lhs& a, const PackedRhs<T>& w, bool accumulate_into) {
  static_assert(std::decay_t<Dst>::IsRowMajor, "row-major destination");
  eigen_assert(a.cols() == w.k && c.cols() == w.n && c.rows() == a.rows() && c.innerStride() == 1);
  const Index rs = Lhs::IsRowMajor ? a.outerStride() : a.innerStride();
  const Index cs = Lhs::IsRowMajor ? a.innerStride() : a.outerStride();
  packed_product(c.data(), c.outerStride(), a.data(), rs, cs, a.rows(), w, accumulate_into);
}

/// Node id's gradient (+)= A · op(W) (= on its first use).
template <class T, class Lhs>
void packed_product_into_grad(Tape<T>& t, int id, const Lhs& a, const PackedRhs<T>& w) {
  bool add = false;
  Matrix<T>& g = t.grad_to_update(id, add);
  packed_product<T>(g, a, w, add);
}

}  // namespace df::nn::detail
