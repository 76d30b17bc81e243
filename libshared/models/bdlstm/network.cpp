#include "models/bdlstm/network.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace df::models {

using Eigen::Index;

double BdlstmConfig::carry_at(int t) const {
  return t < 1 || carry == 0 ? 0 : carry * std::pow(carry_fade, t - 1);
}

template <class T>
BdlstmNet<T>::BdlstmNet(const BdlstmConfig& config, int n_vertices,
                        const std::vector<std::array<int, 2>>& edges, std::uint64_t seed)
    : config_(config), n_vertices_(n_vertices) {
  if (config.conv_layers < 1 || config.latent < 1 || config.hidden < 1 || config.lstm_layers < 1)
    throw UsageError("BD-LSTM sizes must be positive");
  if (!(config.l2_weight >= 0)) throw UsageError("--l2-weight must not be negative");
  if (!(config.free_bits >= 0)) throw UsageError("--kl-free-bits must not be negative");
  if (!(config.motion_scale > 0 && std::isfinite(config.motion_scale)))
    throw InvalidInput("the motion scale must be a positive number");
  adjacency_ = nn::neighbour_mean_operator<T>(n_vertices, edges);
  Rng rng(seed, 0);
  const int n = config.directions == Directions::standard ? 2 : 1;
  const Index v9 = frame_size();
  for (int c = 0; c < n; ++c) {
    const std::string prefix = n == 1 ? "" : (c == 0 ? "forward/" : "backward/");
    Chain ch;
    for (int l = 0; l < config.conv_layers; ++l)
      ch.enc.emplace_back(store_, prefix + "conv" + std::to_string(l), 9, 9, adjacency_, rng);
    ch.fc_enc = nn::Linear<T>(store_, prefix + "fc_enc", v9, 2 * config.latent, rng);
    ch.lstm = nn::StackedLstm<T>(store_, prefix + "lstm", config.latent, config.hidden,
                                 config.lstm_layers, rng);
    ch.fc_dec = nn::Linear<T>(store_, prefix + "fc_dec", config.hidden, v9, rng);
    for (int l = 0; l < config.conv_layers; ++l)
      ch.dec.emplace_back(store_, prefix + "tconv" + std::to_string(l), 9, 9, adjacency_, rng);
    // δX starts at 0: with Glorot weights the last convolution's initial output is O(1) per
    // feature while real frame-to-frame changes are ~0.01, and Adam (steps of ~lr per weight)
    // took thousands of iterations to shrink it.
    if (config.decoder_init == DecoderInit::zero) {
      store_.constant(ch.dec.back().w_point, T(0));
      store_.constant(ch.dec.back().w_nb, T(0));
    } else {  // small: the Glorot draw scaled down, so the encoder gets a gradient from the start
      for (int w : {ch.dec.back().w_point, ch.dec.back().w_nb}) store_.value(w) *= T(0.01);
    }
    // Last, so that every other weight starts as without it.
    if (config.motion_input)
      ch.enc_motion.emplace(store_, prefix + "conv0_motion", 9, 9, adjacency_, rng);
    chains_.push_back(std::move(ch));
  }
}

template <class T>
typename BdlstmNet<T>::States BdlstmNet<T>::constant_states(nn::Tape<T>& tape, Index rows,
                                                            T value) const {
  return chains_[0].lstm.constant_states(tape, rows, value);
}

template <class T>
typename BdlstmNet<T>::States BdlstmNet<T>::states_from(nn::Tape<T>& tape,
                                                        const std::vector<Matrix>& h,
                                                        const std::vector<Matrix>& c) const {
  if (h.size() != static_cast<std::size_t>(config_.lstm_layers) || c.size() != h.size())
    throw Error("internal: one LSTM state per layer needed");
  States s;
  for (std::size_t l = 0; l < h.size(); ++l)
    s.push_back({tape.constant(h[l]), tape.constant(c[l])});
  return s;
}

template <class T>
std::pair<typename BdlstmNet<T>::Var, typename BdlstmNet<T>::Var> BdlstmNet<T>::encode(
    const nn::Bound<T>& p, int chain, Var x, const Var* previous) const {
  const Chain& ch = chains_[static_cast<std::size_t>(chain)];
  Var h = x;
  for (std::size_t l = 0; l < ch.enc.size(); ++l) {
    Var a = ch.enc[l](p, h);
    if (l == 0 && ch.enc_motion) {  // one convolution over [X_t, s (X_t − X_t−1)]
      Var motion = previous ? nn::scale(nn::sub(x, *previous), static_cast<T>(config_.motion_scale))
                            : x.tape->constant(Matrix::Zero(x.rows(), x.cols()));
      a = nn::add(a, (*ch.enc_motion)(p, motion));
    }
    h = nn::tanh(a);
  }
  Var ml = ch.fc_enc.repeated(p, h);
  return {nn::slice_cols(ml, 0, config_.latent),
          nn::slice_cols(ml, config_.latent, config_.latent)};
}

template <class T>
typename BdlstmNet<T>::Var BdlstmNet<T>::decode_step(const nn::Bound<T>& p, int chain, Var x, Var z,
                                                     States& states, const Var* previous,
                                                     int t) const {
  const Chain& ch = chains_[static_cast<std::size_t>(chain)];
  Var out = ch.lstm.step(p, z, states);
  Var d = nn::tanh(ch.fc_dec.repeated(p, out));
  for (std::size_t l = 0; l < ch.dec.size(); ++l) {
    d = ch.dec[l](p, d);
    if (l + 1 < ch.dec.size()) d = nn::tanh(d);
  }
  if (const double carry = config_.carry_at(t); carry != 0 && previous)       // the motion of the
    d = nn::add(d, nn::scale(nn::sub(x, *previous), static_cast<T>(carry)));  // step before
  return nn::add(x, d);
}

template <class T>
typename BdlstmNet<T>::Var BdlstmNet<T>::step(const nn::Bound<T>& p, int chain, Var x,
                                              States& states, const Matrix* eps, KlSum<T>* kl_sum,
                                              const Var* previous, int t) const {
  auto [mu, logvar] = encode(p, chain, x, previous);
  Var z = mu;
  if (config_.kl && eps) {
    z = nn::reparameterize(mu, logvar, *eps);
    if (kl_sum) {
      const T rows = static_cast<T>(x.rows());
      Var kl;                       // Σ over rows
      if (config_.free_bits > 0) {  // Σ_d max(λ, mean_rows KL_d), times the rows
        Var elements = nn::gaussian_kl_elements(mu, logvar);
        kl_sum->nats += static_cast<double>(elements.value().sum());
        Var per_dim = nn::clamp(nn::mean_rows(elements), static_cast<T>(config_.free_bits),
                                std::numeric_limits<T>::max());
        kl = nn::scale(nn::sum(per_dim), rows);
      } else {
        kl = nn::scale(nn::gaussian_kl(mu, logvar), rows);
        kl_sum->nats += static_cast<double>(kl.value()(0, 0));
      }
      kl_sum->encodings += static_cast<long>(x.rows());
      kl_sum->penalised = kl_sum->penalised.tape ? nn::add(kl_sum->penalised, kl) : kl;
    }
  }
  return decode_step(p, chain, x, z, states, previous, t);
}

template <class T>
std::vector<typename BdlstmNet<T>::Var> BdlstmNet<T>::run_chain(const nn::Bound<T>& p, int chain,
                                                                const std::vector<Var>& given,
                                                                States states, int steps, Rng& rng,
                                                                KlSum<T>* kl_sum) const {
  std::vector<Var> frames{given.front()};
  Var previous;  // the input of the step before (carry, motion input)
  Matrix eps(given.front().rows(), config_.latent);
  for (int t = 0; t < steps; ++t) {
    if (config_.kl)
      for (Index k = 0; k < eps.size(); ++k) eps.data()[k] = static_cast<T>(rng.normal());
    Var in = static_cast<std::size_t>(t) < given.size() ? given[static_cast<std::size_t>(t)]
                                                        : frames.back();
    frames.push_back(step(p, chain, in, states, config_.kl ? &eps : nullptr, kl_sum,
                          t ? &previous : nullptr, t));
    previous = in;
  }
  return frames;
}

template <class T>
void BdlstmNet<T>::run_window(nn::Tape<T>& tape, const nn::Bound<T>& p,
                              const std::vector<Matrix>& window, int given, Rng& rng,
                              KlSum<T>& kl_sum, std::vector<Var>& fwd,
                              std::vector<Var>& bwd) const {
  const int n = static_cast<int>(window.size());
  const Index batch = window[0].rows(), v9 = frame_size();
  const T init = static_cast<T>(config_.init_state);
  if (config_.directions == Directions::shared) {
    // Both chains as one batch of 2B rows: forward rows first.
    std::vector<Var> inputs;
    for (int t = 0; t < given; ++t) {
      Matrix x(2 * batch, v9);
      x.topRows(batch) = window[static_cast<std::size_t>(t)];
      x.bottomRows(batch) = window[static_cast<std::size_t>(n - 1 - t)];
      inputs.push_back(tape.constant(std::move(x)));
    }
    Matrix s0(2 * batch, config_.hidden);
    s0.topRows(batch).setConstant(init);
    s0.bottomRows(batch).setConstant(-init);
    std::vector<Matrix> s(static_cast<std::size_t>(config_.lstm_layers), s0);
    auto frames = run_chain(p, 0, inputs, states_from(tape, s, s), n - 1, rng, &kl_sum);
    for (auto& f : frames) {
      fwd.push_back(nn::slice_rows(f, 0, batch));
      bwd.push_back(nn::slice_rows(f, batch, batch));
    }
    return;
  }
  std::vector<Var> f_in, b_in;
  for (int t = 0; t < given; ++t) {
    f_in.push_back(tape.constant(window[static_cast<std::size_t>(t)]));
    b_in.push_back(tape.constant(window[static_cast<std::size_t>(n - 1 - t)]));
  }
  fwd = run_chain(p, 0, f_in, constant_states(tape, batch, init), n - 1, rng, &kl_sum);
  if (config_.directions == Directions::standard)
    bwd = run_chain(p, 1, b_in, constant_states(tape, batch, -init), n - 1, rng, &kl_sum);
}

template <class T>
typename BdlstmNet<T>::Var BdlstmNet<T>::l2_penalty(const nn::Bound<T>& p) const {
  std::vector<Var> squares;
  const auto& views = store_.views();
  // "tf": every trainable value, but each LSTM forget-gate bias measured from its initial 1
  // (TensorFlow's LSTM cells add forget_bias = 1 as a constant outside the trainable bias, so
  // decaying that bias decays towards 1): Σ b_f² − 2 Σ b_f + H = Σ (b_f − 1)².
  std::vector<int> lstm_biases;
  if (config_.l2_scope == L2Scope::tf)
    for (const auto& ch : chains_)
      for (const auto& cell : ch.lstm.cells) lstm_biases.push_back(cell.b);
  for (std::size_t k = 0; k < p.vars.size(); ++k) {
    if (config_.l2_scope == L2Scope::weights && views[k].name.ends_with(".bias")) continue;
    Var sq = nn::sum(nn::square(p.vars[k]));
    if (std::find(lstm_biases.begin(), lstm_biases.end(), static_cast<int>(k)) !=
        lstm_biases.end()) {
      const Index h = config_.hidden;
      sq = nn::add_scalar(nn::add(sq, nn::scale(nn::sum(nn::slice_cols(p.vars[k], h, h)), T(-2))),
                          static_cast<T>(h));
    }
    squares.push_back(sq);
  }
  Var s = squares[0];
  for (std::size_t k = 1; k < squares.size(); ++k) s = nn::add(s, squares[k]);
  return s;
}

template <class T>
typename BdlstmNet<T>::Var BdlstmNet<T>::loss(nn::Tape<T>& tape, const nn::Bound<T>& p,
                                              const std::vector<Matrix>& window, Rng& rng,
                                              BdlstmLossTerms* terms, int given,
                                              T kl_weight) const {
  const int n = static_cast<int>(window.size());
  if (n < 2) throw UsageError("a training window needs at least 2 frames");
  if (given < 1 || given >= n)
    throw UsageError("the given frames must be at least 1 and fewer than the window");
  const Index batch = window[0].rows(), v9 = frame_size();
  for (const auto& w : window)
    if (w.rows() != batch || w.cols() != v9)
      throw Error("internal: window frames of different shapes");
  const T inv_batch = T(1) / static_cast<T>(batch);
  auto frame_norms = [&](Var a) { return nn::sum(nn::group_norm(a, v9)); };  // Σ_rows ‖row‖₂

  KlSum<T> kl_sum;            // Σ over steps and rows
  std::vector<Var> fwd, bwd;  // fwd[t] ≈ X_t, bwd[t] ≈ X_{n−1−t}, each [batch, 9V]
  run_window(tape, p, window, given, rng, kl_sum, fwd, bwd);

  // L_recon (eq. 4): frame 0 of each chain is its ground-truth seed, so its term is 0; frames
  // 1..given−1 are one-step predictions from ground truth.
  std::vector<Var> recon, bidir;
  for (int t = 1; t < n; ++t) {
    recon.push_back(frame_norms(nn::sub(fwd[static_cast<std::size_t>(t)],
                                        tape.constant(window[static_cast<std::size_t>(t)]))));
    if (!bwd.empty())
      recon.push_back(
          frame_norms(nn::sub(bwd[static_cast<std::size_t>(t)],
                              tape.constant(window[static_cast<std::size_t>(n - 1 - t)]))));
  }
  // L_bidir (eq. 5): S^f_i against S^b_{n+1−i}.
  if (!bwd.empty())
    for (int t = 0; t < n; ++t)
      bidir.push_back(frame_norms(
          nn::sub(fwd[static_cast<std::size_t>(t)], bwd[static_cast<std::size_t>(n - 1 - t)])));
  auto total_of = [&](const std::vector<Var>& parts) {  // per window
    Var s = parts[0];
    for (std::size_t k = 1; k < parts.size(); ++k) s = nn::add(s, parts[k]);
    return nn::scale(s, inv_batch);
  };
  Var l_recon = total_of(recon);
  Var total = l_recon;
  Var l_bidir, l_kl, l_2;
  if (!bidir.empty()) {
    l_bidir = total_of(bidir);
    total = nn::add(total, nn::scale(l_bidir, static_cast<T>(config_.alpha_bidir)));
  }
  Var reg;
  if (kl_sum.penalised.tape) {
    l_kl = nn::scale(kl_sum.penalised, inv_batch);
    reg = kl_weight == T(1) ? l_kl : nn::scale(l_kl, kl_weight);
  }
  if (config_.l2) {
    l_2 = l2_penalty(p);
    const Var weighted =
        config_.l2_weight == 1 ? l_2 : nn::scale(l_2, static_cast<T>(config_.l2_weight));
    reg = reg.tape ? nn::add(reg, weighted) : weighted;
  }
  if (reg.tape) total = nn::add(total, nn::scale(reg, static_cast<T>(config_.alpha_reg)));
  if (terms) {
    auto value = [](const Var& v) { return v.tape ? static_cast<double>(v.value()(0, 0)) : 0.0; };
    terms->total = value(total);
    terms->recon = value(l_recon);
    terms->bidir = value(l_bidir);
    terms->kl = value(l_kl);
    terms->l2 = value(l_2);
    terms->kl_per_frame =
        kl_sum.encodings ? kl_sum.nats / static_cast<double>(kl_sum.encodings) : 0.0;
  }
  return total;
}

template class BdlstmNet<float>;
template class BdlstmNet<double>;

}  // namespace df::models
