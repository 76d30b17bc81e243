#include "nn/layers.h"

#include <fmt/format.h>
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
// Neighbour means of all samples with one sparse product: the samples' [V, c] blocks side by
// side as [V, B·c] (vertex-major, so every non-zero adds a B·c-wide row: vectorised), rows
// split into fixed blocks (the same sums at any thread count). (Gathering straight from the
// sample-major x instead, without the copy, made mesh_conv's forward 58% slower on BD-LSTM's pcow
// step: eight scattered 9-value reads per non-zero instead of one contiguous row.)
template <class T>
Matrix<T> vertex_major(const Eigen::Map<const Matrix<T>>& x, Index B, Index V) {
  constexpr Index kBlock = 256;
  const Index c = x.cols();
  Matrix<T> out(V, B * c);
  // By blocks of output rows, each row written whole (per-sample column blocks wrote every row
  // in eight 36-byte pieces: 2.6 GB/s).
  auto copy_rows = [&]<Index C>(Index c_runtime) {
    const Index cc = C > 0 ? C : c_runtime;
    tbb::parallel_for(Index{0}, (V + kBlock - 1) / kBlock, [&](Index b) {
      const Index v1 = std::min(V, (b + 1) * kBlock);
      for (Index v = b * kBlock; v < v1; ++v)
        for (Index s = 0; s < B; ++s) {
          const T* from = x.data() + (s * V + v) * cc;
          // B reading streams, one per sample, 104 KB apart with MSAE's pcow: more than the
          // hardware prefetchers follow; fetching eight rows ahead took mesh_conv's forward from
          // 469 to 350 ms in the MSAE pcow step (profile of three steps, one thread).
          if (v + 8 < v1) __builtin_prefetch(from + 8 * cc);
          T* to = out.data() + (v * B + s) * cc;
          // ACAP's nine features: a copy of known size is two vector moves, where a call to
          // memmove per 36-byte row was 13% of an MSAE step (perf).
          if constexpr (C > 0)
            std::memcpy(to, from, C * sizeof(T));
          else
            std::copy_n(from, cc, to);
        }
    });
  };
  if (c == 9)
    copy_rows.template operator()<9>(c);
  else
    copy_rows.template operator()<0>(c);
  return out;
}

template <class T>
Matrix<T> sparse_rows_product(const SparseMatrix<T>& a, const Matrix<T>& x) {
  constexpr Index kBlock = 256;
  Matrix<T> out(a.rows(), x.cols());
  tbb::parallel_for(Index{0}, (a.rows() + kBlock - 1) / kBlock, [&](Index b) {
    const Index r0 = b * kBlock, n = std::min(kBlock, a.rows() - r0);
    out.middleRows(r0, n).noalias() = a.middleRows(r0, n) * x;
  });
  return out;
}

// The adjoint: gx [B·V, c] (sample-major) += aᵀ · g for a vertex-major g [V, B·c], with `at` =
// aᵀ stored row-major, so every output row is a gather (a product with a->transpose() scatters,
// 3x slower); each element one sum over at's row in stored order, then added. One pass: the
// product's [V, B·c] result and the strided add back into sample-major rows were 12% of
// mesh_conv's backward on BD-LSTM's pcow step.
template <class T>
void add_neighbour_means_adjoint(T* gx, const SparseMatrix<T>& at, const Matrix<T>& g, Index B,
                                 Index V, Index c) {
  constexpr Index kBlock = 256;
  const Index ld = B * c;
  const auto* outer = at.outerIndexPtr();
  const auto* inner = at.innerIndexPtr();
  const T* w = at.valuePtr();
  tbb::parallel_for(Index{0}, (at.rows() + kBlock - 1) / kBlock, [&](Index b) {
    std::vector<T> acc(static_cast<std::size_t>(ld));
    const Index r1 = std::min(at.rows(), (b + 1) * kBlock);
    for (Index r = b * kBlock; r < r1; ++r) {
      std::fill(acc.begin(), acc.end(), T(0));
      for (auto k = outer[r]; k < outer[r + 1]; ++k) {
        const T wk = w[k];
        const T* gr = g.data() + static_cast<Index>(inner[k]) * ld;
        for (Index i = 0; i < ld; ++i) acc[static_cast<std::size_t>(i)] += wk * gr[i];
      }
      for (Index s = 0; s < B; ++s) {
        T* o = gx + (s * V + r) * c;
        if (r + 8 < r1) __builtin_prefetch(o + 8 * c, 1);  // as vertex_major's reads: backward -5%
        const T* from = acc.data() + s * c;
        for (Index i = 0; i < c; ++i) o[i] += from[i];
      }
    }
  });
}
}  // namespace

namespace {
// The per-vertex products run in fixed blocks of vertices, all samples of a block together: the
// neighbour means are vertex-major, so a sample's rows lie B·c_in values apart (9 KB with MSAE's
// batch of 256), and walking one sample over all vertices touched a new page per row (10% slower
// on MSAE's pcow step). Blocks of 64 to 1,024 vertices ran within 6% of each other (BD-LSTM
// and MSAE on pcow).
constexpr Index kVertexBlock = 256;

// f(block, first vertex, vertices) for every block, in parallel.
template <class F>
void for_vertex_blocks(Index V, F f) {
  tbb::parallel_for(Index{0}, (V + kVertexBlock - 1) / kVertexBlock, [&](Index k) {
    const Index v0 = k * kVertexBlock;
    f(k, v0, std::min(kVertexBlock, V - v0));
  });
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
  using ConstMap = Eigen::Map<const Matrix<T>>;
  ConstMap X(x.value().data(), B * V, cin);  // a sample row [V·cin] is V rows of cin
  // Neighbour means, vertex-major [V, B·cin] (sample s in columns s·cin ..), kept for backward.
  auto Nv = std::make_shared<const Matrix<T>>(sparse_rows_product(*a, vertex_major(X, B, V)));
  const Index ldn = B * cin;
  Matrix<T> out(B, V * cout);
  {
    const auto p = detail::pack_narrow(wp.value(), false),
               n = detail::pack_narrow(wn.value(), false);
    // Y_s = b + X_s W_p + N_s W_n, row by row.
    for_vertex_blocks(V, [&](Index, Index v0, Index nv) {
      for (Index s = 0; s < B; ++s)
        detail::narrow_product<T>(
            out.data() + (s * V + v0) * cout, cout, nv, X.data() + (s * V + v0) * cin, cin, p,
            Nv->data() + v0 * ldn + s * cin, ldn, &n, bias.value().data(), false);
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
      [&t, a, Nv, ix, ip, in, ib, io, B, V, cin, cout, ldn] {
        const T* G = t.grad(io).data();
        const T* X = t.value(ix).data();
        // Weight gradients: one partial per vertex block (in parallel) over its samples in order,
        // the partials summed in block order — the same bits at any thread count.
        const bool gp = t.requires_grad(ip), gn = t.requires_grad(in), gb = t.requires_grad(ib);
        if (gp || gn || gb) {
          const auto blocks = static_cast<std::size_t>((V + kVertexBlock - 1) / kVertexBlock);
          std::vector<Matrix<T>> dp(blocks, Matrix<T>::Zero(cin, cout)),
              dn(blocks, Matrix<T>::Zero(cin, cout)), db(blocks, Matrix<T>::Zero(1, cout));
          for_vertex_blocks(V, [&](Index k, Index v0, Index nv) {
            const auto b = static_cast<std::size_t>(k);
            for (Index s = 0; s < B; ++s)
              detail::narrow_weight_gradients<T>(
                  dp[b].data(), gn ? dn[b].data() : nullptr, gb ? db[b].data() : nullptr, nv, cin,
                  cout, X + (s * V + v0) * cin, cin, Nv->data() + v0 * ldn + s * cin, ldn,
                  G + (s * V + v0) * cout, cout, true);
          });
          for (std::size_t b = 0; b < blocks; ++b) {
            if (gp) t.grad(ip) += dp[b];
            if (gn) t.grad(in) += dn[b];
            if (gb) t.grad(ib) += db[b];
          }
        }
        if (t.requires_grad(ix)) {
          T* GX = t.grad(ix).data();
          Matrix<T> GNv(V, ldn);  // ∂/∂(neighbour means), vertex-major
          const auto pt = detail::pack_narrow(t.value(ip), true),
                     nt = detail::pack_narrow(t.value(in), true);
          for_vertex_blocks(V, [&](Index, Index v0, Index nv) {
            for (Index s = 0; s < B; ++s) {
              const T* g = G + (s * V + v0) * cout;
              detail::narrow_product<T>(GX + (s * V + v0) * cin, cin, nv, g, cout, pt, nullptr, 0,
                                        nullptr, nullptr, true);
              detail::narrow_product<T>(GNv.data() + v0 * ldn + s * cin, ldn, nv, g, cout, nt,
                                        nullptr, 0, nullptr, nullptr, false);
            }
          });
          // Aᵀ as its own row-major matrix (transposing costs under 1% of the step).
          const SparseMatrix<T> at = a->transpose();
          add_neighbour_means_adjoint(GX, at, GNv, B, V, cin);
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
