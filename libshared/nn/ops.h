// Differentiable operations on Vars (see tape.h). Shapes are [rows, cols]; a batch has one
// sample per row. Element-wise binary ops broadcast an operand with 1 row and/or 1 column
// (a row vector over rows, a column over columns, a 1×1 scalar everywhere); its gradient is
// summed over the broadcast axes. Every op is instantiated for float and double and
// gradient-checked in double (tests/unit/nn).
#pragma once

#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "nn/tape.h"

namespace df::nn {

template <class T>
using SparseMatrix = Eigen::SparseMatrix<T, Eigen::RowMajor>;

// --- linear algebra
/// a [n,k] × b [k,m]
template <class T>
Var<T> matmul(Var<T> a, Var<T> b);
/// a [n,k] × bᵀ (b [m,k]) without forming the transpose
template <class T>
Var<T> matmul_transposed(Var<T> a, Var<T> b);
/// x [n,k] × w [k,m] for a w that the tape multiplies many times (a recurrent model's per-step
/// layer): w is packed once per tape for the forward products and wᵀ once for the backward ones,
/// and w's gradient from all of its products is one product over their stacked rows, run when
/// backward() reaches w. Same values as matmul up to float rounding.
template <class T>
Var<T> matmul_repeated(Var<T> x, Var<T> w);
/// Fixed sparse S [n,k] × x [k,m] (e.g. a mesh neighbourhood operator); no gradient for S.
template <class T>
Var<T> sparse_matmul(std::shared_ptr<const SparseMatrix<T>> s, Var<T> x);
template <class T>
Var<T> transpose(Var<T> a);

// --- element-wise with broadcasting
template <class T>
Var<T> add(Var<T> a, Var<T> b);
template <class T>
Var<T> sub(Var<T> a, Var<T> b);
template <class T>
Var<T> mul(Var<T> a, Var<T> b);
template <class T>
Var<T> div(Var<T> a, Var<T> b);
template <class T>
Var<T> scale(Var<T> a, T s);  ///< s·a
template <class T>
Var<T> add_scalar(Var<T> a, T s);  ///< a + s

// --- element-wise functions
template <class T>
Var<T> tanh(Var<T> a);
template <class T>
Var<T> sigmoid(Var<T> a);
template <class T>
Var<T> relu(Var<T> a);
template <class T>
Var<T> leaky_relu(Var<T> a, T slope);
template <class T>
Var<T> exp(Var<T> a);
template <class T>
Var<T> log(Var<T> a);
template <class T>
Var<T> abs(Var<T> a);  ///< subgradient 0 at 0
template <class T>
Var<T> square(Var<T> a);
template <class T>
Var<T> sqrt(Var<T> a);
template <class T>
Var<T> clamp(Var<T> a, T lo, T hi);  ///< gradient 0 outside [lo, hi]

// --- reductions
template <class T>
Var<T> sum(Var<T> a);  ///< 1×1
template <class T>
Var<T> mean(Var<T> a);  ///< 1×1
template <class T>
Var<T> sum_rows(Var<T> a);  ///< [1, cols]: sum over the rows
template <class T>
Var<T> sum_cols(Var<T> a);  ///< [rows, 1]: sum over the columns
template <class T>
Var<T> mean_rows(Var<T> a);  ///< [1, cols]
template <class T>
Var<T> mean_cols(Var<T> a);  ///< [rows, 1]
template <class T>
Var<T> max_rows(Var<T> a);  ///< [1, cols]: max over rows (gradient to the first argmax)
/// Σ w_r Σ_c a_rc² (1×1; w = 1 without row weights [rows, 1]), keeping nothing but a:
/// sum(square(a)) without a second matrix of a's size on the tape.
template <class T>
Var<T> sum_squares(Var<T> a, const Matrix<T>* row_weights = nullptr);
/// Σ a ⊙ c (1×1) for a constant c of a's shape: injects the gradient c into a (a gradient
/// computed elsewhere, e.g. a later stage's), without a product matrix on the tape.
template <class T>
Var<T> dot_constant(Var<T> a, Matrix<T> c);
template <class T>
Var<T> max_cols(Var<T> a);  ///< [rows, 1]

// --- structure
template <class T>
Var<T> slice_rows(Var<T> a, Eigen::Index first, Eigen::Index count);
template <class T>
Var<T> slice_cols(Var<T> a, Eigen::Index first, Eigen::Index count);
template <class T>
Var<T> concat_rows(const std::vector<Var<T>>& parts);  ///< stacked vertically
template <class T>
Var<T> concat_cols(const std::vector<Var<T>>& parts);  ///< side by side
/// Row-major reinterpretation as [rows, cols] (same number of elements).
template <class T>
Var<T> reshape(Var<T> a, Eigen::Index rows, Eigen::Index cols);
/// Rows a[index[k]] for k = 0..; gradients of repeated rows add up.
template <class T>
Var<T> gather_rows(Var<T> a, std::vector<int> index);
/// [n, cols]: row index[k] receives (adds) a's row k.
template <class T>
Var<T> scatter_rows(Var<T> a, std::vector<int> index, Eigen::Index n);
/// [rows, cols/g]: the L2 norm of each group of g consecutive columns (e.g. a vertex's 9
/// weights); the gradient at a zero group is 0.
template <class T>
Var<T> group_norm(Var<T> a, Eigen::Index g);

// --- losses (1×1 results)
/// Mean over rows of −log softmax(logits)[label]; fused and stable.
template <class T>
Var<T> softmax_cross_entropy(Var<T> logits, const std::vector<int>& labels);
/// Mean of max(x,0) − x·t + log(1 + e^−|x|) (targets t in [0, 1], a constant).
template <class T>
Var<T> bce_with_logits(Var<T> logits, const Matrix<T>& targets);
/// Mean of (a − b)² over all elements.
template <class T>
Var<T> mse(Var<T> a, Var<T> b);
/// KL(N(μ, e^logvar) ‖ N(0, I)) per element ([rows, cols], not 1×1):
/// −½ (1 + logvar − μ² − e^logvar), e.g. per latent dimension for free bits.
template <class T>
Var<T> gaussian_kl_elements(Var<T> mu, Var<T> logvar);
/// KL(N(μ, e^logvar) ‖ N(0, I)) summed over columns, averaged over rows:
/// −½ mean_rows Σ_cols (1 + logvar − μ² − e^logvar).
template <class T>
Var<T> gaussian_kl(Var<T> mu, Var<T> logvar);
/// μ + e^{½ logvar} ⊙ ε with ε a constant standard-normal sample (reparameterisation).
template <class T>
Var<T> reparameterize(Var<T> mu, Var<T> logvar, const Matrix<T>& eps);

/// Softmax over each row (not differentiable here: for predictions).
template <class T>
Matrix<T> softmax(const Matrix<T>& logits);

}  // namespace df::nn
