#include "models/actgan/network.h"

#include <fmt/format.h>

#include <algorithm>

#include "core/error.h"
#include "nn/ops.h"

namespace df::models {

using nn::Activation;

template <class T>
ActganGenerator<T>::ActganGenerator(const ActganConfig& c, Rng& rng) : config_(c) {
  lstm_ = nn::LstmCell<T>(store_, "gen.lstm", c.noise + c.classes, c.hidden, rng);
  if (c.generator == Generator::pose) {
    to_latent_ = nn::Linear<T>(store_, "gen.to_pose", c.hidden, c.pose, rng);
    return;
  }
  to_latent_ = nn::Linear<T>(store_, "gen.to_latent", c.hidden, c.latent, rng);
  if (c.step_init == StepInit::small) store_.value(to_latent_.w) *= T(0.01);
  decoder_ = nn::Mlp<T>(store_, "gen.decoder", {c.latent + c.classes, c.fc, c.pose},
                        Activation::relu, rng);
}

template <class T>
nn::Var<T> ActganGenerator<T>::decode(const nn::Bound<T>& p, Var h, Var y) const {
  if (config_.generator == Generator::pose)
    throw Error("internal: the pose baseline has no decoder");
  return decoder_(p, nn::concat_cols<T>({h, y}));
}

template <class T>
GeneratedSequences<T> ActganGenerator<T>::generate(const nn::Bound<T>& p, Var y, Var h1,
                                                   const std::vector<Var>& noise) const {
  nn::Tape<T>& tape = *y.tape;
  const Eigen::Index batch = y.rows();
  // The LSTM over every step's (xi_t, y) as one node; its outputs [steps·B, H] time-major.
  const nn::LstmState<T> zero{tape.constant(nn::Matrix<T>::Zero(batch, config_.hidden)),
                              tape.constant(nn::Matrix<T>::Zero(batch, config_.hidden))};
  const Var out =
      noise.empty()
          ? Var{}
          : to_latent_(p, lstm_.sequence(p, nn::concat_rows<T>(with_label(noise, y)), zero));
  auto step = [&](std::size_t t) {
    return nn::slice_rows(out, static_cast<Eigen::Index>(t) * batch, batch);
  };
  GeneratedSequences<T> g;
  if (config_.generator == Generator::pose) {
    for (std::size_t t = 0; t < noise.size(); ++t) g.frames.push_back(step(t));
    return g;
  }
  g.latents.push_back(h1);
  for (std::size_t t = 0; t < noise.size(); ++t)
    g.latents.push_back(config_.residual ? nn::add(g.latents.back(), step(t)) : step(t));
  // The shared decoder on every frame at once.
  const Var frames = decode(p, nn::concat_rows<T>(g.latents),
                            nn::concat_rows<T>(std::vector<Var>(g.latents.size(), y)));
  for (std::size_t t = 0; t < g.latents.size(); ++t)
    g.frames.push_back(nn::slice_rows(frames, static_cast<Eigen::Index>(t) * batch, batch));
  return g;
}

template <class T>
SequenceNet<T>::SequenceNet(const ActganConfig& c, Eigen::Index in, Eigen::Index out,
                            const std::string& name, Rng& rng, int pool_steps)
    : pool_steps_(pool_steps) {
  lstm_ = nn::BidirectionalLstm<T>(store_, name + ".lstm", in, c.hidden, 1, rng);
  const Eigen::Index features = 2 * c.hidden * std::max(1, pool_steps);
  head_ = nn::Mlp<T>(store_, name + ".head", {features, c.fc, out}, Activation::relu, rng);
}

template <class T>
nn::Var<T> SequenceNet<T>::pooled(const nn::Bound<T>& p, const std::vector<Var>& x) const {
  if (x.empty()) throw Error("internal: a sequence network on an empty sequence");
  const Eigen::Index batch = x.front().rows(), steps = static_cast<Eigen::Index>(x.size());
  if (pool_steps_ > 0 && steps != pool_steps_)
    throw Error(
        fmt::format("internal: a network of {}-frame sequences on {} frames", pool_steps_, steps));
  const auto h = lstm_.run(p, nn::concat_rows<T>(x), batch);
  if (pool_steps_ == 0)
    return nn::concat_cols<T>({nn::slice_rows(h.forward, (steps - 1) * batch, batch),
                               nn::slice_rows(h.backward, 0, batch)});
  std::vector<Var> every_step;  // [forward_1, backward_1, ..., forward_T, backward_T]
  for (Eigen::Index t = 0; t < steps; ++t) {
    every_step.push_back(nn::slice_rows(h.forward, t * batch, batch));
    every_step.push_back(nn::slice_rows(h.backward, t * batch, batch));
  }
  return nn::concat_cols<T>(every_step);
}

template <class T>
nn::Var<T> SequenceNet<T>::operator()(const nn::Bound<T>& p, const std::vector<Var>& x) const {
  return output(p, features(p, x));
}

template <class T>
nn::Var<T> SequenceNet<T>::features(const nn::Bound<T>& p, const std::vector<Var>& x) const {
  Var f = pooled(p, x);
  for (std::size_t k = 0; k + 1 < head_.layers.size(); ++k)
    f = nn::activate(head_.layers[k](p, f), head_.hidden, head_.leaky_slope);
  return f;
}

template <class T>
nn::Var<T> SequenceNet<T>::output(const nn::Bound<T>& p, Var features) const {
  return head_.layers.back()(p, features);
}

template <class T>
std::unique_ptr<SequenceNet<T>> make_discriminator(const ActganConfig& c, int length, Rng& rng) {
  if (c.disc_pool == DiscPool::all && length < 1)
    throw Error("internal: a discriminator over all steps needs the length");
  return std::make_unique<SequenceNet<T>>(c, discriminator_width(c), 1, "disc", rng,
                                          c.disc_pool == DiscPool::all ? length : 0);
}

template <class T>
Critic<T>::Critic(const ActganConfig& c, Eigen::Index width, const std::string& name, Rng& rng)
    : width_(width) {
  mlp_ = nn::Mlp<T>(store_, name, {width + c.classes, c.fc, 1}, Activation::relu, rng);
}

template <class T>
nn::Var<T> Critic<T>::operator()(const nn::Bound<T>& p, Var x, Var y) const {
  return mlp_(p, nn::concat_cols<T>({x, y}));
}

template <class T>
typename Critic<T>::Loss Critic<T>::wgan_gp_loss(const nn::Bound<T>& p, Var real, Var fake, Var y,
                                                 const nn::Matrix<T>& eps, T lambda) const {
  const nn::Matrix<T> e = eps.replicate(1, real.cols());
  const nn::Matrix<T> mixed =
      (e.array() * real.value().array() + (1 - e.array()) * fake.value().array()).matrix();
  Loss l;
  l.real_score = nn::mean((*this)(p, real, y));
  l.fake_score = nn::mean((*this)(p, fake, y));
  l.penalty = gradient_penalty(p, real.tape->constant(mixed), y);
  l.loss = nn::add(nn::sub(l.fake_score, l.real_score), nn::scale(l.penalty, lambda));
  return l;
}

template <class T>
nn::Var<T> Critic<T>::gradient_penalty(const nn::Bound<T>& p, Var x, Var y) const {
  const Var g = nn::slice_cols(mlp_.input_gradient(p, nn::concat_cols<T>({x, y})), 0, width_);
  const Var norm = nn::sqrt(nn::add_scalar(nn::sum_cols(nn::square(g)), T(1e-12)));
  return nn::mean(nn::square(nn::add_scalar(norm, T(-1))));
}

template <class T>
GeneratorNoise<T> draw_generator_noise(const ActganConfig& c, Eigen::Index n, int length,
                                       Rng& rng) {
  GeneratorNoise<T> g{nn::Matrix<T>(n, c.latent), {}};
  const bool normal = c.start == LatentStart::normal;
  for (Eigen::Index k = 0; k < g.h1.size(); ++k)
    g.h1.data()[k] = static_cast<T>(normal ? rng.normal() : rng.uniform(-1, 1));
  for (int t = c.generator == Generator::pose ? 0 : 1; t < length; ++t) {
    nn::Matrix<T> m(n, c.noise);
    for (Eigen::Index k = 0; k < m.size(); ++k) m.data()[k] = static_cast<T>(rng.normal());
    g.xi.push_back(std::move(m));
  }
  return g;
}

template <class T>
GeneratedSequences<T> generate_from_noise(const ActganGenerator<T>& g, const nn::Bound<T>& p,
                                          nn::Tape<T>& tape, const nn::Matrix<T>& y,
                                          const GeneratorNoise<T>& noise) {
  std::vector<nn::Var<T>> xi;
  for (const auto& m : noise.xi) xi.push_back(tape.constant(m));
  return g.generate(p, tape.constant(y), tape.constant(noise.h1), xi);
}

template <class T>
std::vector<nn::Var<T>> with_label(const std::vector<nn::Var<T>>& x, nn::Var<T> y) {
  std::vector<nn::Var<T>> out;
  for (const auto& f : x) out.push_back(nn::concat_cols<T>({f, y}));
  return out;
}

Eigen::Index discriminator_width(const ActganConfig& c) {
  return (c.disc_input == DiscInput::motion ? 2 * c.pose : c.pose) + c.classes;
}

template <class T>
std::vector<nn::Var<T>> discriminator_input(const ActganConfig& c, const std::vector<nn::Var<T>>& x,
                                            nn::Var<T> y) {
  if (c.disc_input == DiscInput::frames) return with_label(x, y);
  std::vector<nn::Var<T>> out;
  for (std::size_t t = 0; t < x.size(); ++t)
    out.push_back(nn::concat_cols<T>({x[t], nn::sub(x[t], x[t == 0 ? 0 : t - 1]), y}));
  return out;
}

template <class T>
nn::Var<T> smoothness(const ActganConfig& c, const GeneratedSequences<T>& g) {
  nn::Tape<T>& tape = *g.frames.front().tape;
  const T per_sequence = T(1) / static_cast<T>(g.frames.front().rows());
  const bool latent = (c.smoothness == Smoothness::both || c.smoothness == Smoothness::latent) &&
                      !g.latents.empty();
  const bool action = c.smoothness == Smoothness::both || c.smoothness == Smoothness::action;
  nn::Var<T> total = tape.constant(nn::Matrix<T>::Zero(1, 1));
  for (std::size_t t = 1; t < g.frames.size(); ++t) {
    if (latent)
      total = nn::add(total, nn::scale(nn::sum_squares(nn::sub(g.latents[t], g.latents[t - 1])),
                                       static_cast<T>(c.sigma1) * per_sequence));
    if (action)
      total = nn::add(total, nn::scale(nn::sum_squares(nn::sub(g.frames[t], g.frames[t - 1])),
                                       static_cast<T>(c.sigma2) * per_sequence));
  }
  return total;
}

template <class T>
nn::Matrix<T> one_hot(const std::vector<int>& labels, int classes) {
  nn::Matrix<T> y = nn::Matrix<T>::Zero(static_cast<Eigen::Index>(labels.size()), classes);
  for (std::size_t r = 0; r < labels.size(); ++r) {
    if (labels[r] < 0 || labels[r] >= classes) throw Error("internal: label out of range");
    y(static_cast<Eigen::Index>(r), labels[r]) = T(1);
  }
  return y;
}

#define DF_ACTGAN_NETWORK(T)                                                                      \
  template class ActganGenerator<T>;                                                              \
  template class SequenceNet<T>;                                                                  \
  template class Critic<T>;                                                                       \
  template std::vector<nn::Var<T>> with_label(const std::vector<nn::Var<T>>&, nn::Var<T>);        \
  template std::vector<nn::Var<T>> discriminator_input(                                           \
      const ActganConfig&, const std::vector<nn::Var<T>>&, nn::Var<T>);                           \
  template std::unique_ptr<SequenceNet<T>> make_discriminator<T>(const ActganConfig&, int, Rng&); \
  template nn::Var<T> smoothness(const ActganConfig&, const GeneratedSequences<T>&);              \
  template nn::Matrix<T> one_hot<T>(const std::vector<int>&, int);                                \
  template GeneratorNoise<T> draw_generator_noise<T>(const ActganConfig&, Eigen::Index, int,      \
                                                     Rng&);                                       \
  template GeneratedSequences<T> generate_from_noise(                                             \
      const ActganGenerator<T>&, const nn::Bound<T>&, nn::Tape<T>&, const nn::Matrix<T>&,         \
      const GeneratorNoise<T>&);
DF_ACTGAN_NETWORK(float)
DF_ACTGAN_NETWORK(double)

}  // namespace df::models
