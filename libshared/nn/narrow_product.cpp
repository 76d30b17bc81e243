// Kernels of narrow_product.h. The product's output width and the weight gradients' c_in are
// template parameters (1..16): rows are stored with whole-vector moves, and the weight gradients'
// accumulators stay in registers.
#include "nn/narrow_product.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include "nn/vector_types.h"

namespace df::nn::detail {
namespace {

template <class T>
using V = typename Vector<T>::type;
// Rows summed side by side in narrow_product: independent chains of multiply-adds hide their
// latency.
constexpr Index kRows = 4;

// The first `count` lanes of v into p (= or +=).
template <class T>
void store(T* p, const V<T>& v, Index count, bool accumulate_into) {
  constexpr Index L = kLanes<T>;
  T lanes[L];
  std::memcpy(lanes, &v, sizeof(v));
  if (accumulate_into)
    for (Index j = 0; j < count; ++j) p[j] += lanes[j];
  else
    std::copy_n(lanes, count, p);
}

// The same with a compile-time count: whole-vector moves instead of a call to memmove per row.
template <class T, Index Count>
void store(T* p, const V<T>& v, bool accumulate_into) {
  if (accumulate_into) {
    T lanes[Count];
    std::memcpy(lanes, &v, sizeof(lanes));
    for (Index j = 0; j < Count; ++j) p[j] += lanes[j];
  } else {
    std::memcpy(p, &v, Count * sizeof(T));
  }
}

// R rows of C; N (the output width) fixed, so every row is NV vectors and the last one's count
// is known.
// KFixed > 0: k known at compile time (the loops unroll, the accumulators stay in registers);
// HasB: b (and u) known present. 0 / false: both decided at run time.
template <class T, Index N, Index R, Index KFixed, bool HasB>
void rows_tile(T* c, Index ldc, const T* a, Index lda, Index k_runtime, const T* w, const T* b,
               Index ldb, const T* u, const T* bias, bool accumulate_into) {
  constexpr Index L = kLanes<T>, NV = (N + L - 1) / L;
  const Index k = KFixed > 0 ? KFixed : k_runtime;
  V<T> acc[R][NV];
  for (Index j = 0; j < NV; ++j) {
    const V<T> start = bias ? load(bias + j * L) : V<T>{};
    for (Index r = 0; r < R; ++r) acc[r][j] = start;
  }
  for (Index i = 0; i < k; ++i)
    for (Index j = 0; j < NV; ++j) {
      const V<T> wv = load(w + (i * NV + j) * L);
      for (Index r = 0; r < R; ++r) acc[r][j] += a[r * lda + i] * wv;
    }
  if (HasB || b)
    for (Index i = 0; i < k; ++i)
      for (Index j = 0; j < NV; ++j) {
        const V<T> uv = load(u + (i * NV + j) * L);
        for (Index r = 0; r < R; ++r) acc[r][j] += b[r * ldb + i] * uv;
      }
  for (Index r = 0; r < R; ++r) {
    for (Index j = 0; j + 1 < NV; ++j) store<T, L>(c + r * ldc + j * L, acc[r][j], accumulate_into);
    store<T, N - (NV - 1) * L>(c + r * ldc + (NV - 1) * L, acc[r][NV - 1], accumulate_into);
  }
}

template <class T, Index N, Index KFixed = 0, bool HasB = false>
void product(T* c, Index ldc, Index m, const T* a, Index lda, Index k, const T* w, const T* b,
             Index ldb, const T* u, const T* bias, bool accumulate_into) {
  Index r = 0;
  for (; r + kRows <= m; r += kRows)
    rows_tile<T, N, kRows, KFixed, HasB>(c + r * ldc, ldc, a + r * lda, lda, k, w,
                                         b ? b + r * ldb : nullptr, ldb, u, bias, accumulate_into);
  for (; r < m; ++r)
    rows_tile<T, N, 1, KFixed, HasB>(c + r * ldc, ldc, a + r * lda, lda, k, w,
                                     b ? b + r * ldb : nullptr, ldb, u, bias, accumulate_into);
}

template <class T, Index K, Index NV, bool UB>
void weight_gradients(T* dw, T* du, T* db, Index m, Index n, const T* a, Index lda, const T* b,
                      Index ldb, const T* g, Index ldg, bool accumulate_into) {
  constexpr Index L = kLanes<T>;
  V<T> aw[K][NV]{}, au[K][NV]{}, ab[NV]{};
  const bool want_u = UB || du, want_b = UB || db;
  auto add_row = [&](Index r, const V<T>(&gv)[NV]) __attribute__((always_inline)) {
    for (Index i = 0; i < K; ++i) {
      const T x = a[r * lda + i];
      for (Index j = 0; j < NV; ++j) aw[i][j] += x * gv[j];
    }
    if (want_u)
      for (Index i = 0; i < K; ++i) {
        const T x = b[r * ldb + i];
        for (Index j = 0; j < NV; ++j) au[i][j] += x * gv[j];
      }
    if (want_b)
      for (Index j = 0; j < NV; ++j) ab[j] += gv[j];
  };
  // Rows whose whole vectors lie inside G are loaded directly (lanes past n carry the next row's
  // values, which only reach lanes that are never stored); the last rows are copied first.
  const Index last = (m - 1) * ldg + n;  // one past G's last element
  Index r = 0;
  for (; r < m && r * ldg + NV * L <= last; ++r) {
    V<T> gv[NV];
    for (Index j = 0; j < NV; ++j) gv[j] = load(g + r * ldg + j * L);
    add_row(r, gv);
  }
  for (; r < m; ++r) {
    T padded[NV * L] = {};
    std::copy_n(g + r * ldg, n, padded);
    V<T> gv[NV];
    for (Index j = 0; j < NV; ++j) gv[j] = load(padded + j * L);
    add_row(r, gv);
  }
  for (Index i = 0; i < K; ++i)
    for (Index j = 0; j < NV; ++j) {
      const Index count = std::min(L, n - j * L);
      store(dw + i * n + j * L, aw[i][j], count, accumulate_into);
      if (want_u) store(du + i * n + j * L, au[i][j], count, accumulate_into);
    }
  if (want_b)
    for (Index j = 0; j < NV; ++j)
      store(db + j * L, ab[j], std::min(L, n - j * L), accumulate_into);
}

template <class T>
Index vectors_for(Index n) {
  return (n + kLanes<T> - 1) / kLanes<T>;
}

// Calls f.template operator()<K, NV>() for the runtime k (1..kNarrowMax) and nv (1..the vectors
// of kNarrowMax values: 1 for float with AVX-512, up to 8 for double with SSE2).
template <class T, Index NV = 1, class F>
void with_vectors(Index nv, F&& f) {
  if constexpr (NV <= (kNarrowMax + kLanes<T> - 1) / kLanes<T>) {
    if (nv == NV)
      f.template operator()<NV>();
    else
      with_vectors<T, NV + 1>(nv, std::forward<F>(f));
  }
}

template <class T, class F, Index... Ks>
void with_sizes(Index k, Index nv, F&& f, std::integer_sequence<Index, Ks...>) {
  auto for_k = [&]<Index K>() {
    with_vectors<T>(nv, [&]<Index NV>() { f.template operator()<K, NV>(); });
  };
  (void)((k == Ks + 1 ? (for_k.template operator()<Ks + 1>(), true) : false) || ...);
}

template <class T, class F>
void with_sizes(Index k, Index nv, F&& f) {
  with_sizes<T>(k, nv, std::forward<F>(f), std::make_integer_sequence<Index, kNarrowMax>{});
}

// Calls f.template operator()<N>() for the runtime n (1..kNarrowMax).
template <class F, Index... Ns>
void with_width(Index n, F&& f, std::integer_sequence<Index, Ns...>) {
  (void)((n == Ns + 1 ? (f.template operator()<Ns + 1>(), true) : false) || ...);
}

}  // namespace

template <class T>
NarrowRhs<T> pack_narrow(const Matrix<T>& w, bool transpose) {
  NarrowRhs<T> p;
  p.k = transpose ? w.cols() : w.rows();
  p.n = transpose ? w.rows() : w.cols();
  p.stride = vectors_for<T>(p.n) * kLanes<T>;
  p.data.assign(static_cast<std::size_t>(p.k * p.stride), T(0));
  for (Index i = 0; i < p.k; ++i)
    for (Index j = 0; j < p.n; ++j)
      p.data[static_cast<std::size_t>(i * p.stride + j)] = transpose ? w(j, i) : w(i, j);
  return p;
}

template <class T>
void narrow_product(T* c, Index ldc, Index m, const T* a, Index lda, const NarrowRhs<T>& w,
                    const T* b, Index ldb, const NarrowRhs<T>* u, const T* bias,
                    bool accumulate_into) {
  eigen_assert(narrow_fits(w.k, w.n) && (!b || (u && u->k == w.k && u->n == w.n)));
  // The bias padded to whole vectors like W's rows.
  T padded_bias[kNarrowMax + kLanes<T>] = {};
  if (bias) std::copy_n(bias, w.n, padded_bias);
  // ACAP's nine features in and out (mesh_conv's forward, with neighbours, and its input gradient,
  // without): k known at compile time, so the loops unroll and the accumulators stay in registers.
  if (w.k == 9 && w.n == 9) {
    if (b)
      product<T, 9, 9, true>(c, ldc, m, a, lda, w.k, w.data.data(), b, ldb, u->data.data(),
                             bias ? padded_bias : nullptr, accumulate_into);
    else
      product<T, 9, 9, false>(c, ldc, m, a, lda, w.k, w.data.data(), nullptr, ldb, nullptr,
                              bias ? padded_bias : nullptr, accumulate_into);
    return;
  }
  with_width(
      w.n,
      [&]<Index N>() {
        product<T, N>(c, ldc, m, a, lda, w.k, w.data.data(), b, ldb, b ? u->data.data() : nullptr,
                      bias ? padded_bias : nullptr, accumulate_into);
      },
      std::make_integer_sequence<Index, kNarrowMax>{});
}

template <class T>
void narrow_weight_gradients(T* dw, T* du, T* db, Index m, Index k, Index n, const T* a, Index lda,
                             const T* b, Index ldb, const T* g, Index ldg, bool accumulate_into) {
  eigen_assert(narrow_fits(k, n) && m >= 1);
  with_sizes<T>(k, vectors_for<T>(n), [&]<Index K, Index NV>() {
    if (du && db)
      weight_gradients<T, K, NV, true>(dw, du, db, m, n, a, lda, b, ldb, g, ldg, accumulate_into);
    else
      weight_gradients<T, K, NV, false>(dw, du, db, m, n, a, lda, b, ldb, g, ldg, accumulate_into);
  });
}

#define DF_NARROW(T)                                                                             \
  template struct NarrowRhs<T>;                                                                  \
  template NarrowRhs<T> pack_narrow(const Matrix<T>&, bool);                                     \
  template void narrow_product(T*, Index, Index, const T*, Index, const NarrowRhs<T>&, const T*, \
                               Index, const NarrowRhs<T>*, const T*, bool);                      \
  template void narrow_weight_gradients(T*, T*, T*, Index, Index, Index, const T*, Index,        \
                                        const T*, Index, const T*, Index, bool);
DF_NARROW(float)
DF_NARROW(double)
#undef DF_NARROW

}  // namespace df::nn::detail
