// The share-weight bidirectional LSTM of paper 1 (Qiao, Lai, Fu, Gao: "Synthesizing Mesh
// Deformation Sequences with Bidirectional LSTM"), SPEC §6, on the network engine.
//
// Step model (one time step of one chain), frames as rows of normalized ACAP features [B, 9V]:
//   z  = Conv(X_t)            3 × (mesh conv 9→9, tanh) → FC 9V → 2·latent (mean, log-variance),
//                             z sampled by reparameterisation while training (KL term)
//   z' = LSTM(z, s_t)         3 layers × 128 hidden
//   δX = tCnv(z')             tanh(FC latent→9V) → mesh conv+tanh → mesh conv+tanh → mesh conv
//   X_{t+1} = X_t + δX        generated frames are fed back as the next input
// Training (eq. 3-5): a forward chain from the first frame of a window (states +0.1) and a
// backward chain from its last frame (states −0.1), same weights, both free-running;
//   L = L_recon + α₁ L_bidir + α₂ (L_KL + L_2).
// Ablations (paper Table 2): unidirectional (forward chain only), standard BD-LSTM (separate
// weights per direction), no KL (deterministic encoder), no L2.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/choice.h"
#include "core/rng.h"
#include "nn/layers.h"

namespace df::models {

/// The modes of BdlstmConfig, each with its names (core/choice.h; the names are the model file's).
enum class Directions { shared, standard, unidirectional };
inline constexpr Named<Directions> kDirectionsNames[] = {
    {"shared", Directions::shared},
    {"standard", Directions::standard},
    {"unidirectional", Directions::unidirectional}};
constexpr std::span<const Named<Directions>> names_of(Directions) {
  return kDirectionsNames;
}
enum class L2Scope { all, weights, tf };
inline constexpr Named<L2Scope> kL2ScopeNames[] = {
    {"all", L2Scope::all}, {"weights", L2Scope::weights}, {"tf", L2Scope::tf}};
constexpr std::span<const Named<L2Scope>> names_of(L2Scope) {
  return kL2ScopeNames;
}
enum class DecoderInit { zero, small };
inline constexpr Named<DecoderInit> kDecoderInitNames[] = {{"zero", DecoderInit::zero},
                                                           {"small", DecoderInit::small}};
constexpr std::span<const Named<DecoderInit>> names_of(DecoderInit) {
  return kDecoderInitNames;
}
/// What z is when generating or probing a trained network: the encoder's mean (the default), a
/// draw from q(z|x) as in training (sample), a draw from the prior N(0, I) that ignores the
/// encoder, or zero. If "prior" or "zero" predict as well as "mean", the latent carries no
/// information (posterior collapse).
enum class LatentInput { mean, sample, prior, zero };
inline constexpr Named<LatentInput> kLatentInputNames[] = {{"mean", LatentInput::mean},
                                                           {"sample", LatentInput::sample},
                                                           {"prior", LatentInput::prior},
                                                           {"zero", LatentInput::zero}};
constexpr std::span<const Named<LatentInput>> names_of(LatentInput) {
  return kLatentInputNames;
}

/// Every hyper-parameter of the network and of its loss (stored in the model file's /config);
/// each is declared once, for the command line, the model file and the resume check, in
/// models/bdlstm/settings.cpp.
struct BdlstmConfig {
  int conv_layers = 3;  ///< mesh-conv layers in Conv (and in tCnv)
  int latent = 128;     ///< z (the FC gives mean and log-variance: 2·latent)
  int hidden = 128;     ///< LSTM hidden size (the LSTM's output feeds tCnv)
  int lstm_layers = 3;
  Directions directions = Directions::shared;
  bool kl = true;  ///< VAE encoder with the KL term; false: z = mean, no KL
  bool l2 = true;  ///< L_2 = Σ w² over all trainable weights
  double alpha_bidir = 0.5, alpha_reg = 0.1;
  double init_state = 0.1;  ///< s₀ᶠ = +init_state, s₀ᵇ = −init_state (h and c of every layer)
  // Remedies under study (issue: the latent collapses and L_2 pulls towards zero motion); the
  // defaults are the paper's form.
  /// L_2 over every trainable value ("all", the paper's Σw²), the weight matrices only
  /// ("weights": no biases, so the LSTM's forget-gate bias of 1 is not pulled to 0), or every
  /// value with the forget-gate biases measured from 1 ("tf": what the paper's TensorFlow cells
  /// do, whose forget_bias = 1 is a constant outside the trainable bias)
  L2Scope l2_scope = L2Scope::all;
  double l2_weight = 1;  ///< L_2's factor inside α₂ (L_KL + l2_weight · L_2)
  /// The last decoder convolution starts at "zero" (δX = 0, no reconstruction gradient reaches
  /// the encoder at first) or "small" (Glorot × 0.01)
  DecoderInit decoder_init = DecoderInit::zero;
  /// Free bits (Kingma et al. 2016): nats per latent dimension and frame that the KL term does not
  /// penalise — per step, each dimension's KL averaged over the rows counts as max(free_bits,
  /// KL_d). Below it the encoder may carry information at no cost (0 = the paper: every nat
  /// counts).
  double free_bits = 0;
  /// The motion a step carries over (issue 67: the model moved at a pace of its own, not the
  /// given frames'): X_{t+1} = X_t + carry (X_t − X_{t−1}) + δX, X_{t−1} the chain's previous
  /// input (none at its first step). 0 = the paper: X_{t+1} = X_t + δX; 1: δX corrects a constant
  /// velocity, so that still given frames start still and moving ones keep their pace.
  double carry = 0;
  /// The carry fades along a chain: at its step t (t = 1 the first with a step before) it is
  /// carry · carry_fade^(t−1), so a prediction starts at the given frames' pace and, far from
  /// them, moves by δX alone. 1 = never fades.
  double carry_fade = 1;
  /// The encoder reads the chain's motion beside its frame (issue 67): its first convolution
  /// takes X_t and motion_scale (X_t − X_{t−1}) (zero at a chain's first step), so that z can
  /// tell the given frames' pace and direction. false = the paper (X_t alone).
  bool motion_input = false;
  /// The motion's scale: 1 / the RMS of a training frame's change to the next, per feature (set
  /// by train-bdlstm from the training frames when motion_input is on, so that the motion comes
  /// in at the frames' own size on any set; stored in the model).
  double motion_scale = 1;
  /// The carry at a chain's step t (0 at its first step, which has no step before).
  double carry_at(int t) const;
  /// Whether a step needs the chain's previous input (carry or motion input).
  bool needs_previous() const { return carry != 0 || motion_input; }
};

/// The loss of one batch of windows, by term (each averaged over the windows of the batch).
struct BdlstmLossTerms {
  double total = 0, recon = 0, bidir = 0, kl = 0, l2 = 0;
  /// The KL of q(z|x) in nats per encoded frame, before free bits and the warm-up's weight (the
  /// latent's information: near 0 when it has collapsed to the prior); 0 without the KL term.
  double kl_per_frame = 0;
};

/// What a training loss gathers of the latent's KL term over the steps of its chains.
template <class T>
struct KlSum {
  nn::Var<T> penalised;  ///< Σ over steps and rows of the KL as the loss counts it (free bits)
  double nats = 0;       ///< Σ over steps and rows of the plain KL (a value, no gradient)
  long encodings = 0;    ///< rows encoded (frames × chains)
};

template <class T>
class BdlstmNet {
 public:
  using Matrix = nn::Matrix<T>;
  using Var = nn::Var<T>;
  using States = std::vector<nn::LstmState<T>>;

  /// @param edges  undirected edges of the template (the mesh-conv neighbourhoods)
  /// @param seed   initial weights come from Rng(seed, 0)
  BdlstmNet(const BdlstmConfig& config, int n_vertices,
            const std::vector<std::array<int, 2>>& edges, std::uint64_t seed);

  const BdlstmConfig& config() const { return config_; }
  int n_vertices() const { return n_vertices_; }
  int frame_size() const { return 9 * n_vertices_; }
  nn::ParameterStore<T>& store() { return store_; }
  const nn::ParameterStore<T>& store() const { return store_; }
  /// Chains with their own weights: 2 for the standard BD-LSTM, else 1.
  int n_chains() const { return static_cast<int>(chains_.size()); }

  /// LSTM states with every h and c row set to `value`.
  States constant_states(nn::Tape<T>& tape, Eigen::Index rows, T value) const;
  /// LSTM states from explicit matrices (per layer: h then c, each [rows, hidden]).
  States states_from(nn::Tape<T>& tape, const std::vector<Matrix>& h,
                     const std::vector<Matrix>& c) const;

  /// One time step of chain `chain` (0 = forward / shared, 1 = backward of the standard
  /// BD-LSTM) for frames x [rows, 9V]: returns X_{t+1}, updates `states`. With `eps`
  /// ([rows, latent] standard normal) z is sampled and Σ_rows KL is added to *kl_sum
  /// (when the config has KL); without, z is the mean.
  /// `previous`: the chain's input of the step before (for `carry` and `motion_input`; null at
  /// the first step); `t`: the chain's step (0 = its first; the carry fades with it).
  Var step(const nn::Bound<T>& p, int chain, Var x, States& states, const Matrix* eps,
           KlSum<T>* kl_sum, const Var* previous = nullptr, int t = 1) const;

  /// The encoder of chain `chain`: the latent mean and log-variance of frames x [rows, 9V]
  /// (each [rows, latent]; the log-variance is meaningless without KL). With `motion_input` it
  /// also reads the motion from `previous` (the chain's input of the step before; null: none, as
  /// at a chain's first step).
  std::pair<Var, Var> encode(const nn::Bound<T>& p, int chain, Var x,
                             const Var* previous = nullptr) const;
  /// One step with z given ([rows, latent]): LSTM, decoder, X_{t+1} = x + δX (+ carry_at(t)
  /// (x − previous) when the config carries motion and `previous` is given).
  Var decode_step(const nn::Bound<T>& p, int chain, Var x, Var z, States& states,
                  const Var* previous = nullptr, int t = 1) const;

  /// The training loss of a batch of windows. window[t] is frame t of every window
  /// ([batch, 9V], t = 0..n−1); the reparameterisation noise is drawn from `rng`. Each chain
  /// is fed its first `given` ground-truth frames (1 = the paper: free-running after the
  /// seed frame), as gen-bdlstm feeds --initial frames.
  /// `kl_weight` scales L_KL (a warm-up ramps it from 0 to 1; 1 = eq. 3).
  Var loss(nn::Tape<T>& tape, const nn::Bound<T>& p, const std::vector<Matrix>& window, Rng& rng,
           BdlstmLossTerms* terms = nullptr, int given = 1, T kl_weight = T(1)) const;

 private:
  struct Chain {
    std::vector<nn::MeshConv<T>> enc, dec;
    std::optional<nn::MeshConv<T>>
        enc_motion;  ///< the first convolution's motion part (motion input)
    nn::Linear<T> fc_enc, fc_dec;
    nn::StackedLstm<T> lstm;
  };
  /// Runs `steps` steps of `chain`: the inputs are given[0..] (ground truth), then its own
  /// outputs; returns the frames (given[0] first, then every step's output).
  std::vector<Var> run_chain(const nn::Bound<T>& p, int chain, const std::vector<Var>& given,
                             States states, int steps, Rng& rng, KlSum<T>* kl_sum) const;
  /// Both chains over a window from its first / last `given` frames: fwd[t] ≈ X_t,
  /// bwd[t] ≈ X_{n−1−t} (bwd empty with one direction).
  void run_window(nn::Tape<T>& tape, const nn::Bound<T>& p, const std::vector<Matrix>& window,
                  int given, Rng& rng, KlSum<T>& kl_sum, std::vector<Var>& fwd,
                  std::vector<Var>& bwd) const;
  /// Σ w² over the weights l2_scope names (not per window).
  Var l2_penalty(const nn::Bound<T>& p) const;

  BdlstmConfig config_;
  int n_vertices_;
  nn::ParameterStore<T> store_;
  std::shared_ptr<const nn::SparseMatrix<T>> adjacency_;
  std::vector<Chain> chains_;
};

extern template class BdlstmNet<float>;
extern template class BdlstmNet<double>;

}  // namespace df::models
