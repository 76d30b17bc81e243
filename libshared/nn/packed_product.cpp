// Panels and register tiles of packed_product.h, written with GCC/Clang vector extensions so the
// compiler picks the instructions (-march=native: AVX-512 where the machine has it).
#include "nn/packed_product.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "nn/vector_types.h"

namespace df::nn::detail {
namespace {

// A panel is two vectors wide; a tile is kTileRows rows of it: 16 accumulators of AVX-512's 32
// registers (12 of the 16 below it). Measured on the development machine (AMD EPYC, AVX-512,
// one core: 116 GFLOP/s of bare multiply-adds), best of 5 runs, GFLOP/s for [32 × 256] ·
// [256 × 1024] / [32 × 1024] · [1024 × 256] / [256 × 1600] · [1600 × 1024]: tiles of 4 rows
// 109 / 113 / 99, 8 rows 110 / 114 / 110, 12 rows 109 / 105 / 106, 16 rows 109 / 57 / 110;
// Eigen's product (with its packing) about 75. bench_packed_product measures the chosen tile.
template <class T>
constexpr Index kPanel = 2 * kLanes<T>;
constexpr Index kTileRows = kVectorBytes == 64 ? 8 : 6;
// Below this many multiply-adds a product runs on the calling thread.
constexpr double kParallelWork = 4e6;

// C[0..R) (+)= A[0..R) · panel over k in [k0, k1) of K; `cols` (≤ kPanel) of the tile are real
// columns. A tile that does not reach K leaves its running sums in `carry` (R × 2 vectors), and
// one that does not start at 0 continues from them: every element is the same one sum over k in
// order, whether the panel is walked in chunks or at once.
template <class T, Index R>
void tile(T* c, Index ldc, const T* a, Index rs, Index cs, const T* panel, Index k0, Index k1,
          Index K, Index cols, bool accumulate_into, typename Vector<T>::type* carry) {
  using V = typename Vector<T>::type;
  constexpr Index L = kLanes<T>;
  V acc[R][2];
  for (Index r = 0; r < R; ++r) {
    acc[r][0] = k0 > 0 ? carry[2 * r] : V{};
    acc[r][1] = k0 > 0 ? carry[2 * r + 1] : V{};
  }
  for (Index k = k0; k < k1; ++k) {
    V w0 = load(panel + k * 2 * L), w1 = load(panel + k * 2 * L + L);
#if defined(__x86_64__)
    // Keep the panel's row in two registers: left alone, GCC re-reads it from memory in every
    // row's multiply-add, and the loads set the pace (tiles of 4 rows: 57 GFLOP/s instead of 109).
    asm("" : "+v"(w0), "+v"(w1));
#endif
    for (Index r = 0; r < R; ++r) {
      const T s = a[r * rs + k * cs];
      acc[r][0] += s * w0;
      acc[r][1] += s * w1;
    }
  }
  if (k1 < K) {
    for (Index r = 0; r < R; ++r) {
      carry[2 * r] = acc[r][0];
      carry[2 * r + 1] = acc[r][1];
    }
    return;
  }
  for (Index r = 0; r < R; ++r) {
    T* row = c + r * ldc;
    T sums[2 * L];
    std::memcpy(sums, &acc[r][0], sizeof(V));
    std::memcpy(sums + L, &acc[r][1], sizeof(V));
    if (accumulate_into)
      for (Index j = 0; j < cols; ++j) row[j] += sums[j];
    else
      std::copy(sums, sums + cols, row);
  }
}

// The last `rows` (< kTileRows) rows: the tile of exactly that height.
template <class T, Index R>
void last_rows(T* c, Index ldc, const T* a, Index rs, Index cs, Index rows, const T* panel,
               Index k0, Index k1, Index K, Index cols, bool accumulate_into,
               typename Vector<T>::type* carry) {
  if constexpr (R > 0) {
    if (rows == R)
      tile<T, R>(c, ldc, a, rs, cs, panel, k0, k1, K, cols, accumulate_into, carry);
    else
      last_rows<T, R - 1>(c, ldc, a, rs, cs, rows, panel, k0, k1, K, cols, accumulate_into, carry);
  }
}

// Panel rows walked at a time when K is long (the BD-LSTM's 26,136-wide layers: a 3.3 MB panel):
// 2,048 rows of 32 floats (256 KB) stay in L2 while every row tile passes over them, where the
// whole panel was read again from L3 for each tile of 8 rows.
constexpr Index kPanelChunk = 2048;

// All rows of C against one panel, kTileRows at a time (in chunks of the panel's rows when K is
// long).
template <class T>
void panel_product(T* c, Index ldc, const T* a, Index rs, Index cs, Index m, const T* panel,
                   Index K, Index cols, bool accumulate_into) {
  using V = typename Vector<T>::type;
  const Index tiles = (m + kTileRows - 1) / kTileRows;
  std::vector<V> carry(K > kPanelChunk ? static_cast<std::size_t>(tiles * kTileRows * 2) : 0);
  Index k0 = 0;
  do {  // at least once: with K = 0 the tiles still write their zeros
    const Index k1 = std::min(K, k0 + kPanelChunk);
    Index r = 0;
    for (; r + kTileRows <= m; r += kTileRows)
      tile<T, kTileRows>(c + r * ldc, ldc, a + r * rs, rs, cs, panel, k0, k1, K, cols,
                         accumulate_into, carry.empty() ? nullptr : carry.data() + 2 * r);
    last_rows<T, kTileRows - 1>(c + r * ldc, ldc, a + r * rs, rs, cs, m - r, panel, k0, k1, K, cols,
                                accumulate_into, carry.empty() ? nullptr : carry.data() + 2 * r);
    k0 = k1;
  } while (k0 < K);
}

}  // namespace

template <class T>
PackedRhs<T> pack_rhs(const Matrix<T>& w, bool transpose) {
  PackedRhs<T> p;
  p.k = transpose ? w.cols() : w.rows();
  p.n = transpose ? w.rows() : w.cols();
  p.width = kPanel<T>;
  const Index panels = (p.n + p.width - 1) / p.width;
  p.data.assign(static_cast<std::size_t>(panels * p.k * p.width), T(0));
  for (Index q = 0; q < panels; ++q) {
    const Index j0 = q * p.width, cols = std::min(p.width, p.n - j0);
    T* panel = p.data.data() + q * p.k * p.width;
    if (transpose)  // column j of the panel is row j0 + j of W
      for (Index j = 0; j < cols; ++j)
        for (Index k = 0; k < p.k; ++k) panel[k * p.width + j] = w(j0 + j, k);
    else
      for (Index k = 0; k < p.k; ++k) std::copy_n(&w(k, j0), cols, panel + k * p.width);
  }
  return p;
}

template <class T>
void packed_product(T* c, Index ldc, const T* a, Index rs, Index cs, Index m, const PackedRhs<T>& w,
                    bool accumulate_into) {
  const Index panels = (w.n + w.width - 1) / w.width;
  const auto run = [&](Index q) {
    const Index j0 = q * w.width;
    panel_product(c + j0, ldc, a, rs, cs, m, w.data.data() + q * w.k * w.width, w.k,
                  std::min(w.width, w.n - j0), accumulate_into);
  };
  if (static_cast<double>(m) * static_cast<double>(w.k) * static_cast<double>(w.n) <
      kParallelWork) {
    for (Index q = 0; q < panels; ++q) run(q);
    return;
  }
  tbb::parallel_for(Index{0}, panels, run);
}

template struct PackedRhs<float>;
template struct PackedRhs<double>;
template PackedRhs<float> pack_rhs(const Matrix<float>&, bool);
template PackedRhs<double> pack_rhs(const Matrix<double>&, bool);
template void packed_product(float*, Index, const float*, Index, Index, Index,
                             const PackedRhs<float>&, bool);
template void packed_product(double*, Index, const double*, Index, Index, Index,
                             const PackedRhs<double>&, bool);

}  // namespace df::nn::detail
