// The networks of paper 3 (Wang, Chang, Wang, Chen, Zhang, Carin: "Learning Diverse Stochastic
// Human-Action Generators by Learning Smooth Latent Transitions", AAAI 2020), SPEC §8, on the
// network engine. Poses are rows [B, P] (P = joints x 3, normalized), labels one-hot [B, C]:
//   generator      implicit LSTM over (xi_t, y) -> v_t = FC(o_t) [B, Z];
//                  h_1 ~ U(-1, 1), h_{t+1} = h_t + v_t (residual) or h_{t+1} = v_t (direct);
//                  shared frame decoder x_t = Dec(h_t, y) = MLP [Z + C, FC, P] (ReLU)
//   discriminator  bidirectional LSTM over [x_t, y] (or [x_t, x_t - x_{t-1}, y]) -> the last
//                  forward and backward states [B, 2H] (or every step's, [B, T·2H]) -> MLP
//                  [., FC, 1] (a logit)
//   classifier     the same over x_t -> MLP [2H, FC, C] (logits)
//   critic         MLP [P + C, FC, 1] on single frames (the decoder's WGAN-GP pre-training)
// and the baseline a reviewer asks for (generator "pose"): the same LSTM over (xi_t, y) whose
// output is the pose itself, x_t = FC(o_t) [B, P]: no latent transitions, no shared decoder.
// Each has its own parameter store (and optimizer): a step of one never moves another's weights.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/choice.h"
#include "core/rng.h"
#include "nn/layers.h"

namespace df::models {

/// The modes of ActganConfig, each with its names (core/choice.h; the names are the model file's).
enum class Generator { latent, pose };
inline constexpr Named<Generator> kGeneratorNames[] = {{"latent", Generator::latent},
                                                       {"pose", Generator::pose}};
constexpr std::span<const Named<Generator>> names_of(Generator) {
  return kGeneratorNames;
}
enum class StepInit { glorot, small };
inline constexpr Named<StepInit> kStepInitNames[] = {{"glorot", StepInit::glorot},
                                                     {"small", StepInit::small}};
constexpr std::span<const Named<StepInit>> names_of(StepInit) {
  return kStepInitNames;
}
enum class LatentStart { uniform, normal };
inline constexpr Named<LatentStart> kLatentStartNames[] = {{"uniform", LatentStart::uniform},
                                                           {"normal", LatentStart::normal}};
constexpr std::span<const Named<LatentStart>> names_of(LatentStart) {
  return kLatentStartNames;
}
enum class Smoothness { both, latent, action, none };
inline constexpr Named<Smoothness> kSmoothnessNames[] = {{"both", Smoothness::both},
                                                         {"latent", Smoothness::latent},
                                                         {"action", Smoothness::action},
                                                         {"none", Smoothness::none}};
constexpr std::span<const Named<Smoothness>> names_of(Smoothness) {
  return kSmoothnessNames;
}
enum class DiscInput { frames, motion };
inline constexpr Named<DiscInput> kDiscInputNames[] = {{"frames", DiscInput::frames},
                                                       {"motion", DiscInput::motion}};
constexpr std::span<const Named<DiscInput>> names_of(DiscInput) {
  return kDiscInputNames;
}
enum class DiscPool { last, all };
inline constexpr Named<DiscPool> kDiscPoolNames[] = {{"last", DiscPool::last},
                                                     {"all", DiscPool::all}};
constexpr std::span<const Named<DiscPool>> names_of(DiscPool) {
  return kDiscPoolNames;
}
enum class Discriminator { bilstm, critic };
inline constexpr Named<Discriminator> kDiscriminatorNames[] = {{"bilstm", Discriminator::bilstm},
                                                               {"critic", Discriminator::critic}};
constexpr std::span<const Named<Discriminator>> names_of(Discriminator) {
  return kDiscriminatorNames;
}

/// Every hyper-parameter of the networks and losses (stored in the model file's /config);
/// each is declared once, for the command line, the model file and the resume check, in
/// models/actgan/settings.cpp.
struct ActganConfig {
  int pose = 60;  ///< values per frame (joints x 3)
  int classes = 10;
  int noise = 64;    ///< xi_t
  int latent = 12;   ///< h_t
  int hidden = 256;  ///< LSTM hidden size (generator, discriminator, classifier)
  int fc = 1024;     ///< hidden layer of the decoder, the heads and the critic
  /// "latent": the paper's generator; "pose": the direct-pose RNN baseline (no decoder)
  Generator generator = Generator::latent;
  bool residual = true;  ///< h_{t+1} = h_t + v_t; false: the direct latent of paper Table 6
  /// The generator's output layer (v_t) at its Glorot draw ("glorot") or that draw x 0.01
  /// ("small"): with Glorot weights the untrained generator's steps add up, the latent's RMS
  /// growing from 0.57 to 2.5 over 30 frames before any training, out of the N(0, I) range the
  /// decoder was pre-trained on (its poses grow with the latent's radius)
  StepInit step_init = StepInit::glorot;
  /// Where each sequence's latent starts: h_1 ~ "uniform" U(-1, 1) per dimension (the authors'
  /// code; RMS 0.58, inside the range the decoder was pre-trained on, so the first poses are
  /// less varied than the data's) or "normal" N(0, I), the decoder's pre-training distribution.
  /// The direct-pose baseline draws it too and does not use it.
  LatentStart start = LatentStart::uniform;
  /// Omega = sigma1 sum |h_t - h_{t-1}|^2 + sigma2 sum |x_t - x_{t-1}|^2 per sequence; which
  /// terms: "both", "latent", "action" or "none" (paper Table 5)
  Smoothness smoothness = Smoothness::both;
  double sigma1 = 0.05, sigma2 = 5e-5;
  /// What the discriminator sees per frame: "frames" [x_t, y] or "motion" [x_t, x_t - x_{t-1}, y]
  /// (the first frame's difference 0), the frames and their differences as the authors' code
  DiscInput disc_input = DiscInput::frames;
  /// What the discriminator's head reads: "last", the last forward and backward states of its
  /// BiLSTM [B, 2H], or "all", every step's forward and backward outputs [B, T·2H] (the authors'
  /// code; the head's size then fixes the sequence length T). The classifier stays "last".
  DiscPool disc_pool = DiscPool::last;
  /// The GAN's discriminator: "bilstm", the paper's bidirectional LSTM trained on binary
  /// cross-entropy (disc_input, disc_pool), or "critic", a Wasserstein critic MLP on the whole
  /// clip [x_1 .. x_T, y] trained with the gradient penalty (gp_lambda) as the pre-training's
  /// (its gradient tells the generator where the data lies even where the two do not overlap)
  Discriminator discriminator = Discriminator::bilstm;
  double gamma = 0.1;      ///< weight of the classifier's cross-entropy (cycle loss, eq. 6)
  bool classifier = true;  ///< false: no classifier, no cycle loss (paper Table 2's ablation)
  double gp_lambda = 10;   ///< WGAN-GP gradient penalty
};

/// A generated batch: frames x_1..x_T and latents h_1..h_T, each [B, P] / [B, Z].
template <class T>
struct GeneratedSequences {
  std::vector<nn::Var<T>> frames, latents;
};

template <class T>
class ActganGenerator {
 public:
  using Var = nn::Var<T>;
  ActganGenerator(const ActganConfig& c, Rng& rng);
  nn::ParameterStore<T>& store() { return store_; }
  const nn::ParameterStore<T>& store() const { return store_; }
  /// x = Dec(h, y): [B, Z], [B, C] -> [B, P].
  Var decode(const nn::Bound<T>& p, Var h, Var y) const;
  /// T frames from h_1 [B, Z] and noise xi_1..xi_{T-1} [B, noise] (constants) for labels y;
  /// the pose baseline ignores h_1 and takes T noise steps (latents stay empty).
  GeneratedSequences<T> generate(const nn::Bound<T>& p, Var y, Var h1,
                                 const std::vector<Var>& noise) const;
  /// Parameter indices of the decoder (pre-trained alone).
  const nn::Mlp<T>& decoder() const { return decoder_; }

 private:
  ActganConfig config_;
  nn::ParameterStore<T> store_;
  nn::LstmCell<T> lstm_;
  nn::Linear<T> to_latent_;
  nn::Mlp<T> decoder_;
};

/// The discriminator (outputs 1, input discriminator_width) or the classifier (outputs C, input P).
template <class T>
class SequenceNet {
 public:
  using Var = nn::Var<T>;
  /// pool_steps 0: the head reads the last forward and backward states (any length); > 0: every
  /// step's outputs of sequences of exactly pool_steps frames.
  SequenceNet(const ActganConfig& c, Eigen::Index in, Eigen::Index out, const std::string& name,
              Rng& rng, int pool_steps = 0);
  nn::ParameterStore<T>& store() { return store_; }
  const nn::ParameterStore<T>& store() const { return store_; }
  /// Logits [B, out] of the sequence x_1..x_T (rows [B, in]).
  Var operator()(const nn::Bound<T>& p, const std::vector<Var>& x) const;
  /// What the head's output layer reads: its hidden layer's activations [B, fc] (a recogniser's
  /// features, for FID, diversity and multimodality of generated actions).
  Var features(const nn::Bound<T>& p, const std::vector<Var>& x) const;
  /// The head's output layer on features(): operator() is output(features(x)).
  Var output(const nn::Bound<T>& p, Var features) const;

 private:
  /// The BiLSTM's states the head reads: [B, 2H] or [B, T·2H].
  Var pooled(const nn::Bound<T>& p, const std::vector<Var>& x) const;

  nn::ParameterStore<T> store_;
  nn::BidirectionalLstm<T> lstm_;
  nn::Mlp<T> head_;
  int pool_steps_ = 0;
};

/// The discriminator of c (c.disc_input, c.disc_pool) for sequences of `length` frames.
template <class T>
std::unique_ptr<SequenceNet<T>> make_discriminator(const ActganConfig& c, int length, Rng& rng);

/// A conditional Wasserstein critic, an MLP on [x, y] (hidden layer c.fc): on single poses (width
/// P) in the pre-training, and on whole clips, their frames side by side [x_1 .. x_T] (width T·P),
/// as the GAN's discriminator with c.discriminator "critic".
template <class T>
class Critic {
 public:
  using Var = nn::Var<T>;
  Critic(const ActganConfig& c, Eigen::Index width, const std::string& name, Rng& rng);
  nn::ParameterStore<T>& store() { return store_; }
  const nn::ParameterStore<T>& store() const { return store_; }
  Var operator()(const nn::Bound<T>& p, Var x, Var y) const;  ///< scores [B, 1]
  /// The WGAN-GP loss mean critic(fake) - mean critic(real) + lambda x gradient_penalty at
  /// eps_r real_r + (1 - eps_r) fake_r (eps [B, 1] in [0, 1]), and its parts; real and fake are
  /// constants [B, width], scored in that order.
  struct Loss {
    Var loss, real_score, fake_score, penalty;
  };
  Loss wgan_gp_loss(const nn::Bound<T>& p, Var real, Var fake, Var y, const nn::Matrix<T>& eps,
                    T lambda) const;
  /// mean over rows of (|grad_x critic(x, y)| - 1)^2, differentiable w.r.t. the critic's weights.
  Var gradient_penalty(const nn::Bound<T>& p, Var x, Var y) const;

 private:
  Eigen::Index width_ = 0;
  nn::ParameterStore<T> store_;
  nn::Mlp<T> mlp_;
};

/// The generator's random inputs for n sequences of `length` frames: h_1 ~ U(-1, 1) [n, Z] and
/// xi_1..xi_{length-1} ~ N(0, I) [n, noise] (length steps for the pose baseline), drawn from rng
/// in this order.
template <class T>
struct GeneratorNoise {
  nn::Matrix<T> h1;
  std::vector<nn::Matrix<T>> xi;
};
template <class T>
GeneratorNoise<T> draw_generator_noise(const ActganConfig& c, Eigen::Index n, int length, Rng& rng);

/// g.generate on constants y and noise.
template <class T>
GeneratedSequences<T> generate_from_noise(const ActganGenerator<T>& g, const nn::Bound<T>& p,
                                          nn::Tape<T>& tape, const nn::Matrix<T>& y,
                                          const GeneratorNoise<T>& noise);

/// [x_t, y] per frame.
template <class T>
std::vector<nn::Var<T>> with_label(const std::vector<nn::Var<T>>& x, nn::Var<T> y);

/// The discriminator's input per frame: [x_t, y], or [x_t, x_t - x_{t-1}, y] (c.disc_input
/// "motion"), and its width.
template <class T>
std::vector<nn::Var<T>> discriminator_input(const ActganConfig& c, const std::vector<nn::Var<T>>& x,
                                            nn::Var<T> y);
Eigen::Index discriminator_width(const ActganConfig& c);

/// Omega of a generated batch (mean over sequences of the terms `c.smoothness` selects).
template <class T>
nn::Var<T> smoothness(const ActganConfig& c, const GeneratedSequences<T>& g);

/// One-hot rows [B, C] of the labels.
template <class T>
nn::Matrix<T> one_hot(const std::vector<int>& labels, int classes);

}  // namespace df::models
