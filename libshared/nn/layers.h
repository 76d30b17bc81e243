// Layers over a ParameterStore: each layer owns parameter indices; calling it with a Bound
// (the store bound to a tape) records its ops. Shapes: batch rows.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "nn/ops.h"
#include "nn/parameters.h"

namespace df::nn {

enum class Activation { none, tanh, relu, leaky_relu, sigmoid };
template <class T>
Var<T> activate(Var<T> x, Activation a, T leaky_slope = T(0.2));

/// y = x W + b, W [in, out] (Glorot uniform), b [1, out] (zeros).
template <class T>
struct Linear {
  int w = -1, b = -1;
  Eigen::Index in = 0, out = 0;
  Linear() = default;
  Linear(ParameterStore<T>& s, const std::string& name, Eigen::Index in, Eigen::Index out, Rng& rng,
         bool bias = true);
  Var<T> operator()(const Bound<T>& p, Var<T> x) const;
  /// The same for a layer applied at every step of a sequence on one tape (matmul_repeated).
  Var<T> repeated(const Bound<T>& p, Var<T> x) const;
};

/// Linear layers with an activation after every hidden layer (none after the last).
template <class T>
struct Mlp {
  std::vector<Linear<T>> layers;
  Activation hidden = Activation::relu;
  T leaky_slope = T(0.2);
  Mlp() = default;
  /// sizes = {in, h1, ..., out}
  Mlp(ParameterStore<T>& s, const std::string& name, const std::vector<Eigen::Index>& sizes,
      Activation hidden, Rng& rng);
  Var<T> operator()(const Bound<T>& p, Var<T> x) const;
  /// ∇ₓ Σ_rows D(x) for a 1-output MLP, built from differentiable ops ([rows, in]): the
  /// WGAN-GP penalty's gradient w.r.t. the weights flows through it. (ReLU / leaky-ReLU
  /// derivatives are piecewise constant, tanh/sigmoid derivatives stay differentiable.)
  Var<T> input_gradient(const Bound<T>& p, Var<T> x) const;
};

/// The row-normalised adjacency of a mesh: A[i, j] = 1/d_i for j in the one-ring of i.
/// @param edges  undirected edges (i, j)
template <class T>
std::shared_ptr<const SparseMatrix<T>> neighbour_mean_operator(
    int n_vertices, const std::vector<std::array<int, 2>>& edges);

/// Mesh convolution (SPEC §5) as one fused op: for every sample row of x [B, V·cin] and vertex i,
/// y_i = W_pointᵀ x_i + W_nbᵀ (1/d_i) Σ_{j∈N(i)} x_j + b  →  [B, V·cout].
/// w_point, w_nb [cin, cout] (at most 16 channels each way: narrow_product.h); bias [1, cout]. A
/// transposed/tied variant passes transpose(W).
template <class T>
Var<T> mesh_conv(Var<T> x, Var<T> w_point, Var<T> w_nb, Var<T> bias,
                 std::shared_ptr<const SparseMatrix<T>> a);

template <class T>
struct MeshConv {
  int w_point = -1, w_nb = -1, b = -1;
  Eigen::Index in = 0, out = 0;
  std::shared_ptr<const SparseMatrix<T>> adjacency;
  MeshConv() = default;
  MeshConv(ParameterStore<T>& s, const std::string& name, Eigen::Index in, Eigen::Index out,
           std::shared_ptr<const SparseMatrix<T>> adjacency, Rng& rng);
  Var<T> operator()(const Bound<T>& p, Var<T> x) const;
  /// The mirrored (decoder) convolution with this layer's weights transposed: cout → cin.
  Var<T> tied_transpose(const Bound<T>& p, Var<T> x, Var<T> bias) const;
};

/// LSTM state of one layer.
template <class T>
struct LstmState {
  Var<T> h, c;
};

/// One LSTM layer (gates i, f, g, o as in PyTorch): W_x [in, 4H], W_h [H, 4H] (Glorot),
/// b [1, 4H] zero except the forget gate's 1.
template <class T>
struct LstmCell {
  int wx = -1, wh = -1, b = -1;
  Eigen::Index in = 0, hidden = 0;
  LstmCell() = default;
  LstmCell(ParameterStore<T>& s, const std::string& name, Eigen::Index in, Eigen::Index hidden,
           Rng& rng);
  LstmState<T> operator()(const Bound<T>& p, Var<T> x, LstmState<T> s) const;
  /// The layer over a whole sequence x [T·B, in] from state s (lstm_sequence): h of every step.
  Var<T> sequence(const Bound<T>& p, Var<T> x, LstmState<T> s, bool reverse = false) const;
};

/// One LSTM layer (LstmCell's equations) over a whole sequence as one tape node: x [T·B, in]
/// time-major (rows t·B .. t·B + B − 1 are step t), states h0, c0 [B, H]; returns h_t of every
/// step [T·B, H] in time order. reverse: the steps run from the last to the first (the
/// backward direction of a bidirectional LSTM). The input and weight products of all steps are
/// one matrix product each instead of one per step.
template <class T>
Var<T> lstm_sequence(Var<T> x, Var<T> wx, Var<T> wh, Var<T> b, Var<T> h0, Var<T> c0, bool reverse);

/// Stacked LSTM: one step feeds each layer's h into the next.
template <class T>
struct StackedLstm {
  std::vector<LstmCell<T>> cells;
  StackedLstm() = default;
  StackedLstm(ParameterStore<T>& s, const std::string& name, Eigen::Index in, Eigen::Index hidden,
              int layers, Rng& rng);
  /// One time step; `states` (one per layer) are updated; returns the top layer's h.
  Var<T> step(const Bound<T>& p, Var<T> x, std::vector<LstmState<T>>& states) const;
  /// Runs over a sequence (x[t] [B, in]) from `states`; returns the top h of every step.
  std::vector<Var<T>> run(const Bound<T>& p, const std::vector<Var<T>>& x,
                          std::vector<LstmState<T>>& states) const;
  /// The top layer's h of every step of x [T·B, in] (time-major, batch B) from zero states, each
  /// layer as one lstm_sequence node; reverse: from the last step to the first.
  Var<T> sequence(const Bound<T>& p, Var<T> x, Eigen::Index batch, bool reverse = false) const;
  /// States filled with a constant (e.g. ±0.1 for the share-weight BD-LSTM chains).
  std::vector<LstmState<T>> constant_states(Tape<T>& t, Eigen::Index batch, T value) const;
};

/// The share-weight bidirectional pattern (BD-LSTM, paper 1): ONE stacked LSTM runs forward
/// from the first element with `forward_init` states and backward from the last with
/// `backward_init` states (e.g. +0.1 / −0.1). Returns both output sequences, each in its own
/// running order (backward[0] belongs to the last input).
template <class T>
struct SharedBidirectional {
  std::vector<Var<T>> forward, backward;
};
template <class T>
SharedBidirectional<T> shared_bidirectional(const StackedLstm<T>& lstm, const Bound<T>& p,
                                            const std::vector<Var<T>>& x, T forward_init,
                                            T backward_init);

/// Standard bidirectional LSTM (separate weights per direction, zero initial states).
template <class T>
struct BidirectionalLstm {
  /// h of every step [T·B, H] of each direction, in time order: forward's last state is its
  /// last B rows, backward's its first B rows.
  struct Outputs {
    Var<T> forward, backward;
  };
  StackedLstm<T> forward, backward;
  BidirectionalLstm() = default;
  BidirectionalLstm(ParameterStore<T>& s, const std::string& name, Eigen::Index in,
                    Eigen::Index hidden, int layers, Rng& rng);
  /// Over x [T·B, in] (time-major, batch B).
  Outputs run(const Bound<T>& p, Var<T> x, Eigen::Index batch) const;
};

}  // namespace df::nn
