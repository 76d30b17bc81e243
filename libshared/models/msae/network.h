// The multiscale attention autoencoder of paper 2 (Yang, Gao, Lai, Gao, Xia: "Multiscale Mesh
// Deformation Component Analysis with Attention-based Autoencoders"), SPEC §7, on the network
// engine. Shapes are rows of normalized ACAP features [B, 9V].
//
// An AE block with K_z components (§4.1):
//   h = tanh(conv(x))   z = h Cᵀ   y = tanh(z C)   x̂ = tanh(conv'(y))
// (z = tanh(h Cᵀ) with --latent tanh, the paper's "tanh everywhere" taken literally; y = z C with
// --decoder-fc linear, as the convMesh code of Tan et al.)
// C [K_z, 9V] has no bias and is shared by encoder and decoder; conv' is the mesh convolution
// with the encoder's weights transposed (--decoder-conv transposed) or as they are (shared, as the
// convMesh code the paper builds on reuses them) and its own bias. Loss of a block: λ₁ L_recon + λ₂
// Ω(C) + V(Z), with
//   L_recon = mean over the batch of ‖x − x̂‖²,
//   Ω(C) = (1/K_z) Σ_k Σ_i Λ_ik ‖C_{k,i}‖ (Λ_ik = 1 where d(i, c_k) ≥ d, c_k = argmax_i ‖C_{k,i}‖),
//   V(Z) = (1/K_z) Σ_j max(max_batch |z_j| − θ, 0).
// Levels (§4.2): level 0 is one block; with attention every block of level l has K_z(l) children
// at level l + 1, child k fed diag(AM_k)·(x − x̂) of its parent, AM the parent's attention masks
// (am_{k,i} = ‖C_{k,i}‖², AM_{k,i} = am_{k,i} / Σ_k am_{k,i}: they sum to 1 per vertex, so the
// children's inputs sum to the parent's residual). Without attention level l is one block with as
// many components as the attention tree has at that level, fed the whole residual. The
// reconstruction through the first L levels is the sum of their blocks' outputs.
//
// Training memory: a block's activations are ~10 matrices of B × 9V floats (115 MB each for a
// 12,500-vertex mesh and B = 256). loss_and_gradient therefore works block by block, depth first,
// each block on its own tape: a child's input is passed as a value, and the gradient it returns
// reaches the parent's residual and attention masks through a surrogate term
// ⟨residual, G_r⟩ + ⟨AM, G_AM⟩, so at most one tape per level is alive. loss() builds the same
// loss on one tape (small problems, gradient checks); tests check that both agree.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/choice.h"
#include "core/rng.h"
#include "nn/adam.h"
#include "nn/layers.h"

namespace df::models {

/// The modes of MsaeConfig, each with its names (core/choice.h; the names are the model file's).
enum class MsaeActivation { tanh, linear };
inline constexpr Named<MsaeActivation> kMsaeActivationNames[] = {
    {"tanh", MsaeActivation::tanh}, {"linear", MsaeActivation::linear}};
constexpr std::span<const Named<MsaeActivation>> names_of(MsaeActivation) {
  return kMsaeActivationNames;
}
enum class DecoderConv { transposed, shared };
inline constexpr Named<DecoderConv> kDecoderConvNames[] = {{"transposed", DecoderConv::transposed},
                                                           {"shared", DecoderConv::shared}};
constexpr std::span<const Named<DecoderConv>> names_of(DecoderConv) {
  return kDecoderConvNames;
}
enum class MsaeInit { glorot, normal, small, local, local_all };
inline constexpr Named<MsaeInit> kMsaeInitNames[] = {{"glorot", MsaeInit::glorot},
                                                     {"normal", MsaeInit::normal},
                                                     {"small", MsaeInit::small},
                                                     {"local", MsaeInit::local},
                                                     {"local-all", MsaeInit::local_all}};
constexpr std::span<const Named<MsaeInit>> names_of(MsaeInit) {
  return kMsaeInitNames;
}
enum class Centres { random, spread };
inline constexpr Named<Centres> kCentresNames[] = {{"random", Centres::random},
                                                   {"spread", Centres::spread}};
constexpr std::span<const Named<Centres>> names_of(Centres) {
  return kCentresNames;
}
enum class Support { soft, proximal, hard };
inline constexpr Named<Support> kSupportNames[] = {
    {"soft", Support::soft}, {"proximal", Support::proximal}, {"hard", Support::hard}};
constexpr std::span<const Named<Support>> names_of(Support) {
  return kSupportNames;
}

/// Every hyper-parameter of the network and of its loss (stored in the model file's /config);
/// each is declared once, for the command line, the model file and the resume check, in
/// models/msae/settings.cpp.
struct MsaeConfig {
  std::vector<int> kz = {10, 5};       ///< components of each block, per level
  std::vector<double> d = {0.4, 0.2};  ///< Ω's normalized geodesic radius, per level
  bool attention = true;               ///< false: one block per level on the whole residual
  /// The codes z = act(h Cᵀ): "linear" (unbounded codes, which V(Z)'s θ = 5 bounds) or "tanh"
  /// (the paper's "tanh everywhere" taken literally: V(Z) can never act, and on real meshes AE₀'s
  /// codes saturate at ±1 and stop learning — chosen on validation parts, docs/msae.md)
  MsaeActivation latent = MsaeActivation::linear;
  /// The decoder's fully connected layer y = act(z C): "tanh" (the paper's "tanh everywhere") or
  /// "linear" (as the convMesh code of Tan et al. has it: only the convolutions end in tanh)
  MsaeActivation decoder_fc = MsaeActivation::tanh;
  /// The decoder's convolution: "transposed" (the encoder's weights transposed) or "shared" (the
  /// encoder's weights as they are, as the convMesh code reuses them; both are 9 × 9)
  DecoderConv decoder_conv = DecoderConv::transposed;
  /// Initial weights: "glorot" (uniform ±sqrt(6 / (fan_in + fan_out))), "normal" (N(0, 0.02²)
  /// for C and the convolutions, as the convMesh code), "small" (C at Glorot × 0.01: a
  /// component that no training shape asks for stays near zero instead of projecting unseen
  /// shapes onto a random direction), "local" ("glorot", then train-msae starts level 0 from
  /// the training shapes' SPLOCS components: start_block) or "local-all" (every level so, each
  /// block from SPLOCS on what it is fed)
  MsaeInit init = MsaeInit::glorot;
  /// Where the components' centres start: "random" (wherever the initial weights peak; the
  /// reconstruction gradient then draws them to the most deforming vertices, often all to one)
  /// or "spread" (farthest-point sampling by geodesic distance: level 0 over the whole mesh, a
  /// child block within its parent component's radius), after which the centres follow the weights
  /// (centre_separation)
  Centres centres = Centres::random;
  /// How the centres follow the weights every iteration: 0 = c_k = argmax_i ‖C_{k,i}‖ (the paper);
  /// s > 0 = a block's components, strongest first, each take the argmax among the vertices at
  /// least s·d (geodesic) from the centres its block has already given out (the plain argmax when
  /// none is left), so that two components cannot share a centre
  double centre_separation = 0;
  /// Ω's step function as a penalty only ("soft", the paper) or also as a hard support ("hard"):
  /// after every optimizer step the groups of C where Λ_ik = 1 (outside the component's radius)
  /// are set to zero — Ω's limit of infinite weight, strictly local components
  Support support = Support::soft;
  /// With support proximal: a group's shrink per step is at most proximal_cap × its coordinates'
  /// rate (0: no cap). The threshold η·λ/K_z uses Adam's step sizes η = rate / √v̂, which grow
  /// without bound where the reconstruction's gradient is small — where a started block already
  /// fits — so one step zeroes every group outside the masks there (bumps12, --init local-all:
  /// validation E_rms 0.461 → 1.20 in one step; docs/msae.md). Capped, a group shrinks at most as
  /// fast as Adam moves a weight, and the reconstruction can hold up what it needs.
  double proximal_cap = 0;
  /// Subtract a fixed offset (the training shapes' mean features, set by train-msae) from AE₀'s
  /// input and add it back to its output, so that the autoencoders model deviations from the mean
  /// shape and no component is spent on the mean deformation itself (the diagnosis found one
  /// level-0 component carrying a constant offset; docs/msae.md). Stored as a parameter that
  /// never receives a gradient.
  bool centre_features = false;
  /// The attention masks from am_k,i^p instead of am_k,i (eq. 5-6; p = 1, the paper, 2 or 4): where
  /// overlapping level-0 components spread a vertex's mask thin, p > 1 gives more of its residual
  /// to the component that owns it most (the masks still sum to 1 per vertex; docs/msae.md)
  int attention_sharpness = 1;
  double lambda_recon = 10, lambda_sparse = 1, theta = 5;
  /// Weight of the whole reconstruction's MSE, λ_w · mean ‖x − Σ_b x̂_b‖² over the blocks of the
  /// levels in training and those above them, added to the blocks' own losses (0 = none, the
  /// paper). Each second-level block reconstructs only its masked share of the residual; this
  /// term trains the children on their sum, as fitted codes fit it (on pcow it validated worse
  /// at weights 1 and 10; docs/msae.md)
  double lambda_whole = 0;
  int levels() const { return static_cast<int>(kz.size()); }
  /// How many levels (from level 0) `init` starts from the local decomposition: 0 (glorot,
  /// normal, small), 1 (local) or all of them (local-all).
  int started_levels() const {
    return init == MsaeInit::local_all ? levels() : init == MsaeInit::local ? 1 : 0;
  }
};

/// Loss terms summed over the blocks of a batch (the first is what is minimised).
struct MsaeLossTerms {
  double total = 0, recon = 0, sparsity = 0, latent = 0;
  double whole =
      0;  ///< mean ‖x − Σ_b x̂_b‖² over the batch, rows weighted as in L_recon (lambda_whole > 0)
};

template <class T>
class MsaeNet {
 public:
  using Matrix = nn::Matrix<T>;
  using Var = nn::Var<T>;

  struct Block {
    int level = 0;
    int parent = -1;  ///< block index, -1 for level 0
    int slot = 0;     ///< with attention: which of the parent's masks weights its input
    int kz = 0;
    nn::MeshConv<T> conv;
    int c = -1;      ///< C [kz, 9V]
    int b_dec = -1;  ///< bias of the decoder's convolution [1, 9]
    std::vector<int> children;
    /// Its parameters' indices in the store.
    std::vector<int> parameters() const { return {conv.w_point, conv.w_nb, conv.b, c, b_dec}; }
  };

  /// @param edges  undirected edges of the template (the mesh-conv neighbourhoods)
  /// @param seed   initial weights come from Rng(seed, 0)
  MsaeNet(const MsaeConfig& config, int n_vertices, const std::vector<std::array<int, 2>>& edges,
          std::uint64_t seed);

  const MsaeConfig& config() const { return config_; }
  int n_vertices() const { return n_vertices_; }
  int frame_size() const { return 9 * n_vertices_; }
  nn::ParameterStore<T>& store() { return store_; }
  const nn::ParameterStore<T>& store() const { return store_; }
  const std::vector<Block>& blocks() const { return blocks_; }
  /// Index of the first block of each level, and one past the last block ([levels + 1]).
  const std::vector<int>& level_begin() const { return level_begin_; }

  /// Indices (into store()) of the parameters of the blocks of one level.
  std::vector<int> level_parameters(int level) const;
  /// Per block, its centres c_k = argmax_i ‖C_{k,i}‖ from the current weights ([kz] each).
  std::vector<std::vector<int>> centres() const;
  /// With config().centre_separation > 0 (the separated centres Ω uses then; centres() stays the
  /// components' peaks): per block, components in order of their largest group norm, each c_k the
  /// strongest vertex at least separation·d from the centres already given out in the block (the
  /// plain argmax when none is left). @param distance  as for sparsity_masks
  template <class Distance>
  std::vector<std::vector<int>> separated_centres(Distance&& distance) const {
    std::vector<std::vector<int>> out;
    for (const Block& b : blocks_) {
      const double apart = config_.centre_separation * config_.d[static_cast<std::size_t>(b.level)];
      const auto C = store_.value(b.c);
      Matrix norms(b.kz, n_vertices_);
      for (int k = 0; k < b.kz; ++k)
        for (int i = 0; i < n_vertices_; ++i)
          norms(k, i) = C.row(k).segment(9 * Eigen::Index{i}, 9).squaredNorm();
      std::vector<int> peak(static_cast<std::size_t>(b.kz)), order(peak.size());
      for (int k = 0; k < b.kz; ++k) {
        norms.row(k).maxCoeff(&peak[static_cast<std::size_t>(k)]);
        order[static_cast<std::size_t>(k)] = k;
      }
      std::stable_sort(order.begin(), order.end(), [&](int p, int q) {
        return norms(p, peak[static_cast<std::size_t>(p)]) >
               norms(q, peak[static_cast<std::size_t>(q)]);
      });
      std::vector<int> c(peak.size());
      std::vector<char> open(static_cast<std::size_t>(n_vertices_), 1);
      for (int k : order) {
        int best = -1;
        for (int i = 0; i < n_vertices_; ++i)
          if (open[static_cast<std::size_t>(i)] && (best < 0 || norms(k, i) > norms(k, best)))
            best = i;
        c[static_cast<std::size_t>(k)] = best >= 0 ? best : peak[static_cast<std::size_t>(k)];
        const auto& row = distance(c[static_cast<std::size_t>(k)]);
        for (int i = 0; i < n_vertices_; ++i)
          if (row[i] < apart) open[static_cast<std::size_t>(i)] = 0;
      }
      out.push_back(std::move(c));
    }
    return out;
  }
  /// Per block, Ω's mask Λ [kz, V] (1 where the normalized distance to the centre is ≥ d).
  /// @param distance  distance(c) = the normalized geodesic distances from vertex c (#V)
  template <class Distance>
  std::vector<Matrix> sparsity_masks(const std::vector<std::vector<int>>& centres,
                                     Distance&& distance) const {
    std::vector<Matrix> masks;
    for (std::size_t b = 0; b < blocks_.size(); ++b) {
      const double d = config_.d[static_cast<std::size_t>(blocks_[b].level)];
      Matrix lam(blocks_[b].kz, n_vertices_);
      for (int k = 0; k < blocks_[b].kz; ++k) {
        const auto& row = distance(centres[b][static_cast<std::size_t>(k)]);
        for (int i = 0; i < n_vertices_; ++i) lam(k, i) = row[i] >= d ? T(1) : T(0);
      }
      masks.push_back(std::move(lam));
    }
    return masks;
  }
  /// --support hard: zeroes every block's groups C_{k,i} where its mask Λ_ik is 1.
  void project_onto_support(const std::vector<Matrix>& lambda);
  /// --support proximal: Ω's proximal step, after an optimizer step whose gradient left Ω out.
  /// Each group C_{k,i} with Λ_ik > 0 shrinks towards zero by τ = η·λ_sparse·Λ_ik / K_z (Ω's
  /// gradient norm in the loss times η, the mean of its coordinates' step sizes in the last
  /// Adam step) and is exactly zero where its norm is at most τ. The soft penalty's gradient
  /// never zeroes a group: it leaves weights of the order of the step size all over the mesh,
  /// which eq. 7 counts (docs/msae.md). With config().proximal_cap > 0, τ is at most the cap times
  /// the mean rate of the group's coordinates (Λ_ik times it). Only blocks of `levels` (empty:
  /// all) — a level frozen in separate training keeps its weights.
  void proximal_sparsity(const std::vector<Matrix>& lambda,
                         const typename nn::Adam<T>::StepSizes& eta,
                         const std::vector<int>& levels);
  /// Makes vertex `vertices[b][k]` the centre of component k of block b (its group of C becomes
  /// twice the row's largest group norm): where the centres start with --centres spread.
  void place_centres(const std::vector<std::vector<int>>& vertices);
  /// With config().centre_features: sets the offset AE₀ subtracts and adds back ([1, 9V]).
  void set_offset(const Matrix& mean);
  /// --init local: block b's components become `components` [K_z, 9V] (rows of a linear basis
  /// of its inputs) and its convolutions the identity (point weights I, neighbour weights and
  /// biases 0), so that the block starts as the tied linear autoencoder of that basis up to its
  /// two tanh; the other blocks keep their weights. With `scale` s < 1 the convolutions' point
  /// weights start as s·I and C as components / s: with a linear decoder_fc the encoder's tanh
  /// acts on s·x and the block starts as the projection bent by its output's tanh alone.
  void start_block(int b, const Matrix& components, double scale = 1);
  /// The attention masks AM [kz, V] of a block from its C (eq. 5-6): each column sums to 1.
  Matrix attention_masks(int block) const;
  /// Input of `child` from its parent's residual [B, 9V]: diag(AM_slot)·residual with the parent's
  /// attention masks [kz, V], the residual whole when `masks` is null (no attention).
  Matrix child_input(const Block& child, const Matrix& residual, const Matrix* masks) const;

  /// The training loss of a batch x [B, 9V] on one tape (every block's activations alive at once).
  /// @param lambda   Ω's masks, one per block (sparsity_masks)
  /// @param levels   train only these levels' losses (separate training: {l}); empty = all
  /// @param weights  [B, 1] how many times each row stands in the batch (null = once each): a
  ///                 batch drawn with replacement from a few shapes is computed once per distinct
  ///                 shape with the same loss and gradient (L_recon divides by Σ weights; V(Z)'s
  ///                 maximum does not depend on repeats)
  Var loss(nn::Tape<T>& tape, const nn::Bound<T>& p, const Matrix& x,
           const std::vector<Matrix>& lambda, MsaeLossTerms* terms = nullptr,
           const std::vector<int>& levels = {}, const Matrix* weights = nullptr) const;
  /// The same loss with its gradient added into store().grads(), block by block (see above).
  MsaeLossTerms loss_and_gradient(const Matrix& x, const std::vector<Matrix>& lambda,
                                  const std::vector<int>& levels = {},
                                  const Matrix* weights = nullptr);

  /// The reconstruction of x [B, 9V] through the first `levels` levels (1..levels()) and the
  /// latent codes of every block ([B, kz] each; blocks beyond `levels` are left empty).
  /// `inputs`, when given, gets what every block run was fed (x for AE₀; a child's masked share
  /// of its parent's residual), empty for the blocks not run.
  Matrix reconstruct(const Matrix& x, int levels, std::vector<Matrix>* codes = nullptr,
                     std::vector<Matrix>* inputs = nullptr) const;
  /// The decoder of one block applied to latent codes z [rows, kz] → [rows, 9V].
  Matrix decode(int block, const Matrix& z) const;
  /// `count` shapes [count, 9V] the decoders of every level make from recombined codes of x
  /// [B, 9V]: each code of every block is the same code of a row of x (encoded as reconstruct()
  /// does) drawn with `rng`, independently per code. With one row they are its reconstruction;
  /// train-msae --synthetic adds them to batches (docs/msae.md).
  Matrix recombined_shapes(const Matrix& x, int count, Rng& rng) const;
  /// The codes that reconstruct x [B, 9V] best through the decoders of the first `levels` levels
  /// (least squares: min over every block's z_b of ‖x − Σ_b Dec_b(z_b)‖², each shape on its own),
  /// a diagnostic and the baselines' protocol (PCA and SPLOCS fit each test shape). `codes` come
  /// in as the starting point (reconstruct()'s encoder codes) and go out fitted; `iterations`
  /// Adam steps (rate `lr`, decayed tenfold over the run). Returns the fitted reconstruction.
  Matrix fit_codes(const Matrix& x, int levels, std::vector<Matrix>& codes, int iterations,
                   double lr) const;

 private:
  struct BlockOutput {
    Var z;  ///< latent codes [B, kz]
    Var xhat;
    Var residual;  ///< x − x̂
    Var masks;     ///< attention masks [kz, V] (with attention and children)
  };
  /// One block's forward pass on x; adds its loss terms (when its level trains) into *loss.
  BlockOutput forward_block(const nn::Bound<T>& p, int b, Var x, const Matrix* lambda, Var* loss,
                            MsaeLossTerms* terms, const Matrix* weights = nullptr) const;
  Var masks_of(const nn::Bound<T>& p, int b) const;
  /// The decoder of block b on codes z: tanh(conv'(act(z C))), plus the offset for AE₀.
  Var decoder(const nn::Bound<T>& p, int b, Var z) const;
  /// Only block b's parameters as leaves of `tape` (variables when gradients are wanted, else
  /// constants); the other entries stay empty — binding the whole store would copy every block's
  /// weights once per block.
  nn::Bound<T> bind_block(nn::Tape<T>& tape, int b, bool variables) const;
  /// loss_and_gradient's recursion: processes block b and its subtree on input x; returns
  /// ∂(subtree loss)/∂x when `want_input_gradient`.
  /// `g_whole` (null without lambda_whole) is the whole-reconstruction term's gradient with
  /// respect to every output x̂_b of the levels up to the deepest in training.
  Matrix subtree(int b, const Matrix& x, const std::vector<Matrix>& lambda,
                 const std::vector<char>& trains, bool want_input_gradient, MsaeLossTerms& terms,
                 const Matrix* weights, const Matrix* g_whole);

  MsaeConfig config_;
  int n_vertices_;
  nn::ParameterStore<T> store_;
  std::shared_ptr<const nn::SparseMatrix<T>> adjacency_;
  std::vector<Block> blocks_;
  std::vector<int> level_begin_;
  int offset_ = -1;  ///< store index of the features' offset [1, 9V] (centre_features), else -1
};

extern template class MsaeNet<float>;
extern template class MsaeNet<double>;

}  // namespace df::models
