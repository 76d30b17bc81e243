// Products with a narrow right-hand side (internal to libshared/nn): the mesh convolution's
// per-sample [V × c_in] · [c_in × c_out] and its weight gradients [c_in × V] · [V × c_out], with
// c_in, c_out = 9 on ACAP features (any up to 16 here). Eigen runs them as general products: it
// packs the [V × 9] operand into its blocked layout at every call (over 16,000 calls per BD-LSTM
// iteration on pcow) and its kernel is made for wide shapes — packing alone was 10% of a BD-LSTM
// iteration and 18% of an MSAE one. Here each output row is one or a few SIMD vectors, summed in
// registers over the c_in inputs, with the small weight matrix padded once per call.
//
// Every output element is one running sum in a fixed order, so results never depend on how the
// caller splits rows among threads.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "nn/tape.h"

namespace df::nn::detail {
using Eigen::Index;

/// The widest c_in and c_out the kernels take.
constexpr Index kNarrowMax = 16;
constexpr bool narrow_fits(Index k, Index n) {
  return k >= 1 && k <= kNarrowMax && n >= 1 && n <= kNarrowMax;
}

/// W [k × n] (or Wᵀ when `transpose`) as k rows of whole SIMD vectors, zero-padded.
template <class T>
struct NarrowRhs {
  Index k = 0, n = 0, stride = 0;
  std::vector<T> data;
};

template <class T>
NarrowRhs<T> pack_narrow(const Matrix<T>& w, bool transpose);

/// For rows r < m: C_r (+)= bias + A_r · W + B_r · U, where row r of A starts at a + r·lda
/// (W.k contiguous values), of B at b + r·ldb (U.k values), of C at c + r·ldc (W.n values). b, u
/// and bias may be null. Each element sums the bias, then A's terms, then B's, then is stored in
/// (or added to) C.
template <class T>
void narrow_product(T* c, Index ldc, Index m, const T* a, Index lda, const NarrowRhs<T>& w,
                    const T* b, Index ldb, const NarrowRhs<T>* u, const T* bias,
                    bool accumulate_into);

/// Over rows r < m (m ≥ 1; strides as above, G_r = n values at g + r·ldg): dW = Σ_r A_rᵀ G_r [k ×
/// n] and, where the pointers are not null, dU = Σ_r B_rᵀ G_r [k × n] and db = Σ_r G_r [n]; all
/// row-major, each element one running sum over r in order, stored in (or added to) the outputs.
template <class T>
void narrow_weight_gradients(T* dw, T* du, T* db, Index m, Index k, Index n, const T* a, Index lda,
                             const T* b, Index ldb, const T* g, Index ldg, bool accumulate_into);

}  // namespace df::nn::detail
