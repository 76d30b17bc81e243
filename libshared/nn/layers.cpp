#include "nn/layers.h"

#include <fmt/format.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>

#include "core/error.h"
#include "nn/narrow_product.h"

namespace df::nn {
using Eigen::Index;

template <class T>
Var<T> activate(Var<T> x, Activation a, T leaky_slope) {
  switch (a) {
    case Activation::tanh:
      return tanh(x);
    case Activation::relu:
      return relu(x);
    case Activation::leaky_relu:
      return leaky_relu(x, leaky_slope);
    case Activation::sigmoid:
      return sigmoid(x);
    default:
      return x;
  }
}

// --- Linear

template <class T>
Linear<T>::Linear(ParameterStore<T>& s, const std::string& name, Index in_, Index out_, Rng& rng,
                  bool bias)
    : in(in_), out(out_) {
  w = s.add(name + ".weight", in, out);
  s.glorot_uniform(w, rng);
  if (bias) b = s.add(name + ".bias", 1, out);
}

template <class T>
Var<T> Linear<T>::operator()(const Bound<T>& p, Var<T> x) const {
  Var<T> y = matmul(x, p[w]);
  return b >= 0 ? add(y, p[b]) : y;
}

template <class T>
Var<T> Linear<T>::repeated(const Bound<T>& p, Var<T> x) const {
  Var<T> y = matmul_repeated(x, p[w]);
  return b >= 0 ? add(y, p[b]) : y;
}

// --- MLP

template <class T>
Mlp<T>::Mlp(ParameterStore<T>& s, const std::string& name, const std::vector<Index>& sizes,
            Activation hidden_, Rng& rng)
    : hidden(hidden_) {
  for (std::size_t k = 0; k + 1 < sizes.size(); ++k)
    layers.emplace_back(s, fmt::format("{}.{}", name, k), sizes[k], sizes[k + 1], rng);
}

template <class T>
Var<T> Mlp<T>::operator()(const Bound<T>& p, Var<T> x) const {
  for (std::size_t k = 0; k < layers.size(); ++k) {
    x = layers[k](p, x);
    if (k + 1 < layers.size()) x = activate(x, hidden, leaky_slope);
  }
  return x;
}

template <class T>
Var<T> Mlp<T>::input_gradient(const Bound<T>& p, Var<T> x) const {
  if (layers.empty() || layers.back().out != 1)
    throw Error("internal: input_gradient needs a 1-output MLP");
  Tape<T>& t = *x.tape;
  // Forward, keeping each hidden layer's derivative act'(pre).
  std::vector<Var<T>> slopes;
  Var<T> h = x;
  for (std::size_t k = 0; k + 1 < layers.size(); ++k) {
    Var<T> pre = layers[k](p, h);
    switch (hidden) {
      case Activation::relu:
      case Activation::leaky_relu: {  // piecewise constant: a constant mask
        const T low = hidden == Activation::relu ? T(0) : leaky_slope;
        slopes.push_back(
            t.constant(pre.value().unaryExpr([low](T v) { return v > 0 ? T(1) : low; })));
        break;
      }
      case Activation::tanh: {
        Var<T> y = tanh(pre);
        slopes.push_back(sub(t.constant(Matrix<T>::Ones(1, 1)), square(y)));
        break;
      }
      case Activation::sigmoid: {
        Var<T> y = sigmoid(pre);
        slopes.push_back(mul(y, sub(t.constant(Matrix<T>::Ones(1, 1)), y)));
        break;
      }
      default:
        slopes.push_back(t.constant(Matrix<T>::Ones(1, 1)));
    }
    h = activate(pre, hidden, leaky_slope);
  }
  // Backward by hand, as ops: g = w_Lᵀ, then g = (g ∘ act'_k) W_kᵀ down to the input.
  Var<T> g = transpose(p[layers.back().w]);  // [1, H_last]
  for (std::size_t k = layers.size() - 1; k-- > 0;) {
    g = mul(slopes[k], g);                     // [rows, H_k]
    g = matmul_transposed(g, p[layers[k].w]);  // [rows, H_{k-1}]
  }
  if (g.rows() != x.rows())
    g = add(g, t.constant(Matrix<T>::Zero(x.rows(), g.cols())));  // no hidden layer
  return g;
}

// --- mesh convolution

template <class T>
std::shared_ptr<const SparseMatrix<T>> neighbour_mean_operator(
    int n, const std::vector<std::array<int, 2>>& edges) {
  std::vector<int> degree(static_cast<std::size_t>(n), 0);
  for (const auto& e : edges) ++degree[e[0]], ++degree[e[1]];
  std::vector<Eigen::Triplet<T>> trip;
  for (const auto& e : edges) {
    trip.emplace_back(e[0], e[1], T(1) / static_cast<T>(degree[e[0]]));
    trip.emplace_back(e[1], e[0], T(1) / static_cast<T>(degree[e[1]]));
  }
  auto a = std::make_shared<SparseMatrix<T>>(n, n);
  a->setFromTriplets(trip.begin(), trip.end());
  a->makeCompressed();
  return a;
}

namespace {
// The convolution works one sample and one block of vertices at a time: a sample's rows [V, c]
// (ACAP's nine features: 105 KB on pcow) stay in L2 while its block's neighbour means are
// gathered from them into a buffer of the block, used at once and never stored. Before, the
// whole batch was copied vertex-major [V, B·c], its neighbour means computed as one sparse
// product and kept for backward: seven passes over a batch-sized array forward and ten backward,
// where this moves x and y forward and x, g and x's gradient backward (docs/speed.md).
// Blocks of a fixed size, each element one running sum in a fixed order: the same bits at any
// thread count. (Gathering for all samples of one vertex block at once, tried before, was 58%
// slower: every sample's rows, 100 KB apart, streamed for each block; here a group of four
// samples' rows stays in L2 while the group's blocks pass over it.)
constexpr Index kVertexBlock = 256;

// Eight values as one vector (GCC/Clang vector extensions: one AVX register of floats).
template <class T>
struct Lanes8;
template <>
struct Lanes8<float> {
  typedef float type __attribute__((vector_size(8 * sizeof(float))));
};
template <>
struct Lanes8<double> {
  typedef double type __attribute__((vector_size(8 * sizeof(double))));
};

// Neighbour means of S samples at once (sample j's rows at x + j·ldx, its means at n + j·ldn):
// n_j[r] = Σ_k a[v0 + r, k] · x_j[k] for r < nr, rows of c values, each sum over a's row in
// stored order from zero — the order of Eigen's sparse-dense product, so the same bits as the
// sparse product this replaced. Each non-zero's index and weight are read once for the S
// samples, whose S independent sums also hide the FMAs' latency.
template <class T, int S>
void gather_rows(T* n, Index ldn, const SparseMatrix<T>& a, Index v0, Index nr, const T* x,
                 Index ldx, Index c) {
  const auto* outer = a.outerIndexPtr();
  const auto* inner = a.innerIndexPtr();
  const T* w = a.valuePtr();
  if (c == 9) {  // ACAP's nine features: one 8-wide vector and one value per row
    using V8 = typename Lanes8<T>::type;
    for (Index r = 0; r < nr; ++r) {
      V8 lo[S];
      T hi[S];
      for (int j = 0; j < S; ++j) lo[j] = V8{}, hi[j] = T(0);
      for (auto k = outer[v0 + r]; k < outer[v0 + r + 1]; ++k) {
        const T wk = w[k];
        const T* xr = x + static_cast<Index>(inner[k]) * 9;
        for (int j = 0; j < S; ++j) {
          V8 xv;
          std::memcpy(&xv, xr + j * ldx, sizeof(xv));
          lo[j] += wk * xv;
          hi[j] += wk * xr[j * ldx + 8];
        }
      }
      for (int j = 0; j < S; ++j) {
        std::memcpy(n + j * ldn + r * 9, &lo[j], sizeof(V8));
        n[j * ldn + r * 9 + 8] = hi[j];
      }
    }
    return;
  }
  for (Index r = 0; r < nr; ++r)
    for (int j = 0; j < S; ++j) {
      T acc[detail::kNarrowMax] = {};
      for (auto k = outer[v0 + r]; k < outer[v0 + r + 1]; ++k) {
        const T wk = w[k];
        const T* xr = x + j * ldx + static_cast<Index>(inner[k]) * c;
        for (Index i = 0; i < c; ++i) acc[i] += wk * xr[i];
      }
      std::copy_n(acc, c, n + j * ldn + r * c);
    }
}

// Samples go through the gathers kGroup at a time (their rows together in L2: 4 × 105 KB on
// pcow, this machine's L2 512 KB).
constexpr Index kGroup = 4;

// gather_rows for `samples` (≤ kGroup) samples.
template <class T>
void neighbour_means(T* n, Index ldn, const SparseMatrix<T>& a, Index v0, Index nr, const T* x,
                     Index ldx, Index c, Index samples) {
  Index j = 0;
  for (; j + kGroup <= samples; j += kGroup)
    gather_rows<T, kGroup>(n + j * ldn, ldn, a, v0, nr, x + j * ldx, ldx, c);
  for (; j < samples; ++j) gather_rows<T, 1>(n + j * ldn, ldn, a, v0, nr, x + j * ldx, ldx, c);
}

// f(first sample, samples, first vertex, vertices) for every block of every group of samples, in
// parallel.
template <class F>
void for_sample_blocks(Index B, Index V, F f) {
  const Index blocks = (V + kVertexBlock - 1) / kVertexBlock, groups = (B + kGroup - 1) / kGroup;
  tbb::parallel_for(Index{0}, groups * blocks, [&](Index k) {
    const Index v0 = (k % blocks) * kVertexBlock, s0 = (k / blocks) * kGroup;
    f(s0, std::min(kGroup, B - s0), v0, std::min(kVertexBlock, V - v0));
  });
}

// f(block, first vertex, vertices) for every block, in parallel.
template <class F>
void for_vertex_blocks(Index V, F f) {
  tbb::parallel_for(Index{0}, (V + kVertexBlock - 1) / kVertexBlock, [&](Index k) {
    const Index v0 = k * kVertexBlock;
    f(k, v0, std::min(kVertexBlock, V - v0));
  });
}

// The input gradient of `m` (≤ kGroup) samples: gx_j (+)= g_j·W_pᵀ + Aᵀ (g_j·W_nᵀ), the second
// term gathered along the rows of at = Aᵀ (stored row-major) from the sample's whole g_j·W_nᵀ
// (in gn), each element's sum over at's row in stored order, then added.
template <class T>
void add_input_gradient(T* gx, const T* g, Index m, std::vector<T>& gn, std::vector<T>& sums,
                        const SparseMatrix<T>& at, const detail::NarrowRhs<T>& pt,
                        const detail::NarrowRhs<T>& nt, Index V, Index cin, Index cout) {
  const Index ld = V * cin, lds = kVertexBlock * cin;
  gn.resize(static_cast<std::size_t>(m * ld));
  sums.resize(static_cast<std::size_t>(m * lds));
  for (Index j = 0; j < m; ++j) {
    const T* gj = g + j * V * cout;
    detail::narrow_product<T>(gx + j * ld, cin, V, gj, cout, pt, nullptr, 0, nullptr, nullptr,
                              true);
    detail::narrow_product<T>(gn.data() + j * ld, cin, V, gj, cout, nt, nullptr, 0, nullptr,
                              nullptr, false);
  }
  for (Index v0 = 0; v0 < V; v0 += kVertexBlock) {
    const Index nr = std::min(kVertexBlock, V - v0);
    neighbour_means(sums.data(), lds, at, v0, nr, gn.data(), ld, cin, m);
    for (Index j = 0; j < m; ++j) {
      T* o = gx + j * ld + v0 * cin;
      const T* from = sums.data() + j * lds;
      for (Index i = 0; i < nr * cin; ++i) o[i] += from[i];
    }
  }
}
}  // namespace

template <class T>
Var<T> mesh_conv(Var<T> x, Var<T> wp, Var<T> wn, Var<T> bias,
                 std::shared_ptr<const SparseMatrix<T>> a) {
  Tape<T>& t = *x.tape;
  const Index V = a->rows(), cin = wp.rows(), cout = wp.cols(), B = x.rows();
  if (x.cols() != V * cin || wn.rows() != cin || wn.cols() != cout || bias.rows() != 1 ||
      bias.cols() != cout || !detail::narrow_fits(cin, cout))
    throw Error(
        fmt::format("internal: mesh_conv of x [{},{}] with V = {}, W [{},{}]/[{},{}], b [{},{}] "
                    "(at most {} channels)",
                    x.rows(), x.cols(), V, wp.rows(), wp.cols(), wn.rows(), wn.cols(), bias.rows(),
                    bias.cols(), detail::kNarrowMax));
  Matrix<T> out(B, V * cout);
  {
    const auto p = detail::pack_narrow(wp.value(), false),
               n = detail::pack_narrow(wn.value(), false);
    const T* X = x.value().data();
    // Y_s = b + X_s W_p + N_s W_n, a block of a group of samples' rows at a time.
    const Index ldx = V * cin, ldm = kVertexBlock * cin;
    tbb::enumerable_thread_specific<std::vector<T>> buffers(static_cast<std::size_t>(kGroup * ldm));
    for_sample_blocks(B, V, [&](Index s0, Index m, Index v0, Index nv) {
      T* means = buffers.local().data();
      neighbour_means(means, ldm, *a, v0, nv, X + s0 * ldx, ldx, cin, m);
      for (Index j = 0; j < m; ++j)
        detail::narrow_product<T>(out.data() + ((s0 + j) * V + v0) * cout, cout, nv,
                                  X + (s0 + j) * ldx + v0 * cin, cin, p, means + j * ldm, cin, &n,
                                  bias.value().data(), false);
    });
  }
  const int ix = x.id, ip = wp.id, in = wn.id, ib = bias.id, io = static_cast<int>(t.size());
  // The products: the neighbour means, then [x_v, n_v]·[W_p; W_n] per vertex (backward: twice).
  const double flops =
      2.0 * double(a->nonZeros()) * double(B * cin) + 4.0 * double(B * V * cin * cout);
  const bool rg =
      x.requires_grad() || wp.requires_grad() || wn.requires_grad() || bias.requires_grad();
  return t.record(
      std::move(out), rg,
      [&t, a, ix, ip, in, ib, io, B, V, cin, cout] {
        const T* G = t.grad(io).data();
        const T* X = t.value(ix).data();
        // Weight gradients: one partial per vertex block (in parallel) over its samples in order,
        // each sample's neighbour means of the block gathered again; the partials summed in block
        // order — the same bits at any thread count.
        const bool gp = t.requires_grad(ip), gn = t.requires_grad(in), gb = t.requires_grad(ib);
        if (gp || gn || gb) {
          const auto blocks = static_cast<std::size_t>((V + kVertexBlock - 1) / kVertexBlock);
          std::vector<Matrix<T>> dp(blocks, Matrix<T>::Zero(cin, cout)),
              dn(blocks, Matrix<T>::Zero(cin, cout)), db(blocks, Matrix<T>::Zero(1, cout));
          const Index ldx = V * cin, ldm = kVertexBlock * cin;
          tbb::enumerable_thread_specific<std::vector<T>> buffers(
              static_cast<std::size_t>(kGroup * ldm));
          for_vertex_blocks(V, [&](Index k, Index v0, Index nv) {
            const auto b = static_cast<std::size_t>(k);
            T* means = buffers.local().data();
            for (Index s0 = 0; s0 < B; s0 += kGroup) {
              const Index m = std::min(kGroup, B - s0);
              if (gn) neighbour_means(means, ldm, *a, v0, nv, X + s0 * ldx, ldx, cin, m);
              for (Index j = 0; j < m; ++j)
                detail::narrow_weight_gradients<T>(
                    dp[b].data(), gn ? dn[b].data() : nullptr, gb ? db[b].data() : nullptr, nv, cin,
                    cout, X + (s0 + j) * ldx + v0 * cin, cin, gn ? means + j * ldm : nullptr, cin,
                    G + ((s0 + j) * V + v0) * cout, cout, true);
            }
          });
          for (std::size_t b = 0; b < blocks; ++b) {
            if (gp) t.grad(ip) += dp[b];
            if (gn) t.grad(in) += dn[b];
            if (gb) t.grad(ib) += db[b];
          }
        }
        if (t.requires_grad(ix)) {
          T* GX = t.grad(ix).data();
          const auto pt = detail::pack_narrow(t.value(ip), true),
                     nt = detail::pack_narrow(t.value(in), true);
          // Aᵀ as its own row-major matrix, so every output row is a gather (transposing costs
          // under 1% of the step).
          const SparseMatrix<T> at = a->transpose();
          struct Buffers {
            std::vector<T> gn, sums;
          };
          tbb::enumerable_thread_specific<Buffers> buffers;
          tbb::parallel_for(Index{0}, (B + kGroup - 1) / kGroup, [&](Index k) {
            const Index s0 = k * kGroup;
            Buffers& u = buffers.local();
            add_input_gradient(GX + s0 * V * cin, G + s0 * V * cout, std::min(kGroup, B - s0), u.gn,
                               u.sums, at, pt, nt, V, cin, cout);
          });
        }
      },
      {flops, 2 * flops});
}

template <class T>
MeshConv<T>::MeshConv(ParameterStore<T>& s, const std::string& name, Index in_, Index out_,
                      std::shared_ptr<const SparseMatrix<T>> adjacency_, Rng& rng)
    : in(in_), out(out_), adjacency(std::move(adjacency_)) {
  w_point = s.add(name + ".point", in, out);
  w_nb = s.add(name + ".neighbour", in, out);
  b = s.add(name + ".bias", 1, out);
  s.glorot_uniform(w_point, rng);
  s.glorot_uniform(w_nb, rng);
}

template <class T>
Var<T> MeshConv<T>::operator()(const Bound<T>& p, Var<T> x) const {
  return mesh_conv(x, p[w_point], p[w_nb], p[b], adjacency);
}

template <class T>
Var<T> MeshConv<T>::tied_transpose(const Bound<T>& p, Var<T> x, Var<T> bias) const {
  return mesh_conv(x, transpose(p[w_point]), transpose(p[w_nb]), bias, adjacency);
}

// --- LSTM

template <class T>
LstmCell<T>::LstmCell(ParameterStore<T>& s, const std::string& name, Index in_, Index hidden_,
                      Rng& rng)
    : in(in_), hidden(hidden_) {
  wx = s.add(name + ".wx", in, 4 * hidden);
  wh = s.add(name + ".wh", hidden, 4 * hidden);
  b = s.add(name + ".bias", 1, 4 * hidden);
  s.glorot_uniform(wx, rng);
  s.glorot_uniform(wh, rng);
  s.value(b).middleCols(hidden, hidden).setOnes();  // forget-gate bias 1
}

template <class T>
LstmState<T> LstmCell<T>::operator()(const Bound<T>& p, Var<T> x, LstmState<T> s) const {
  Var<T> z = add(add(matmul(x, p[wx]), matmul(s.h, p[wh])), p[b]);
  Var<T> i = sigmoid(slice_cols(z, 0, hidden));
  Var<T> f = sigmoid(slice_cols(z, hidden, hidden));
  Var<T> g = tanh(slice_cols(z, 2 * hidden, hidden));
  Var<T> o = sigmoid(slice_cols(z, 3 * hidden, hidden));
  Var<T> c = add(mul(f, s.c), mul(i, g));
  return {mul(o, tanh(c)), c};
}

template <class T>
Var<T> LstmCell<T>::sequence(const Bound<T>& p, Var<T> x, LstmState<T> s, bool reverse) const {
  return lstm_sequence(x, p[wx], p[wh], p[b], s.h, s.c, reverse);
}

template <class T>
StackedLstm<T>::StackedLstm(ParameterStore<T>& s, const std::string& name, Index in, Index hidden,
                            int layers, Rng& rng) {
  for (int l = 0; l < layers; ++l)
    cells.emplace_back(s, fmt::format("{}.{}", name, l), l ? hidden : in, hidden, rng);
}

template <class T>
Var<T> StackedLstm<T>::step(const Bound<T>& p, Var<T> x, std::vector<LstmState<T>>& states) const {
  if (states.size() != cells.size()) throw Error("internal: one LSTM state per layer needed");
  for (std::size_t l = 0; l < cells.size(); ++l) {
    states[l] = cells[l](p, x, states[l]);
    x = states[l].h;
  }
  return x;
}

template <class T>
std::vector<Var<T>> StackedLstm<T>::run(const Bound<T>& p, const std::vector<Var<T>>& x,
                                        std::vector<LstmState<T>>& states) const {
  std::vector<Var<T>> out;
  for (const auto& xt : x) out.push_back(step(p, xt, states));
  return out;
}

template <class T>
Var<T> StackedLstm<T>::sequence(const Bound<T>& p, Var<T> x, Index batch, bool reverse) const {
  auto states = constant_states(*x.tape, batch, T(0));
  for (std::size_t l = 0; l < cells.size(); ++l) x = cells[l].sequence(p, x, states[l], reverse);
  return x;
}

template <class T>
std::vector<LstmState<T>> StackedLstm<T>::constant_states(Tape<T>& t, Index batch, T value) const {
  std::vector<LstmState<T>> s;
  for (const auto& c : cells) {
    Matrix<T> m = Matrix<T>::Constant(batch, c.hidden, value);
    s.push_back({t.constant(m), t.constant(m)});
  }
  return s;
}

template <class T>
SharedBidirectional<T> shared_bidirectional(const StackedLstm<T>& lstm, const Bound<T>& p,
                                            const std::vector<Var<T>>& x, T forward_init,
                                            T backward_init) {
  if (x.empty()) throw Error("internal: empty sequence");
  Tape<T>& t = *x[0].tape;
  auto sf = lstm.constant_states(t, x[0].rows(), forward_init);
  auto sb = lstm.constant_states(t, x[0].rows(), backward_init);
  SharedBidirectional<T> out;
  out.forward = lstm.run(p, x, sf);
  out.backward = lstm.run(p, std::vector<Var<T>>(x.rbegin(), x.rend()), sb);
  return out;
}

template <class T>
BidirectionalLstm<T>::BidirectionalLstm(ParameterStore<T>& s, const std::string& name, Index in,
                                        Index hidden, int layers, Rng& rng)
    : forward(s, name + ".fw", in, hidden, layers, rng),
      backward(s, name + ".bw", in, hidden, layers, rng) {}

template <class T>
typename BidirectionalLstm<T>::Outputs BidirectionalLstm<T>::run(const Bound<T>& p, Var<T> x,
                                                                 Index batch) const {
  return {forward.sequence(p, x, batch, false), backward.sequence(p, x, batch, true)};
}

#define DF_NN_LAYERS(T)                                                                        \
  template Var<T> activate(Var<T>, Activation, T);                                             \
  template struct Linear<T>;                                                                   \
  template struct Mlp<T>;                                                                      \
  template std::shared_ptr<const SparseMatrix<T>> neighbour_mean_operator<T>(                  \
      int, const std::vector<std::array<int, 2>>&);                                            \
  template Var<T> mesh_conv(Var<T>, Var<T>, Var<T>, Var<T>,                                    \
                            std::shared_ptr<const SparseMatrix<T>>);                           \
  template struct MeshConv<T>;                                                                 \
  template struct LstmCell<T>;                                                                 \
  template struct StackedLstm<T>;                                                              \
  template struct BidirectionalLstm<T>;                                                        \
  template SharedBidirectional<T> shared_bidirectional(const StackedLstm<T>&, const Bound<T>&, \
                                                       const std::vector<Var<T>>&, T, T);

DF_NN_LAYERS(float)
DF_NN_LAYERS(double)
#undef DF_NN_LAYERS

}  // namespace df::nn
