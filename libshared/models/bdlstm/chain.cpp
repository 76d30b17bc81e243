#include "models/bdlstm/chain.h"

#include <algorithm>
#include <cmath>

namespace df::models {
namespace {
using Matrix = nn::Matrix<float>;
using Eigen::Index;
}  // namespace

ChainStepper::ChainStepper(const BdlstmNet<float>& net, int chain)
    : net_(net), chain_(chain), bound_(net.store().bind(tape_)), mark_(tape_.size()) {}

void ChainStepper::reset(Index rows, float value, double sigma, Rng& rng) {
  const auto hidden = static_cast<Index>(net_.config().hidden);
  h_.assign(static_cast<std::size_t>(net_.config().lstm_layers),
            Matrix::Constant(rows, hidden, value));
  c_ = h_;
  steps_ = 0;
  if (sigma > 0)
    for (auto* states : {&h_, &c_})
      for (auto& m : *states)
        for (Index k = 0; k < m.size(); ++k)
          m.data()[k] += static_cast<float>(sigma * rng.normal());
}

Matrix ChainStepper::step(const Matrix& x) {
  Rng unused;
  return step(x, LatentInput::mean, unused);
}

Matrix ChainStepper::step(const Matrix& x, LatentInput latent, Rng& rng) {
  tape_.truncate(mark_);
  auto states = net_.states_from(tape_, h_, c_);
  const nn::Var<float> xin = tape_.constant(x);
  // The carried motion and the motion input need the input of the step before (none at the
  // first step).
  const bool needs_previous = net_.config().needs_previous();
  nn::Var<float> previous;
  if (needs_previous && steps_ > 0) previous = tape_.constant(previous_);
  const nn::Var<float>* before = previous.tape ? &previous : nullptr;
  nn::Var<float> z;
  if (latent == LatentInput::mean || latent == LatentInput::sample) {
    auto [mu, logvar] = net_.encode(bound_, chain_, xin, before);
    z = mu;
    if (latent == LatentInput::sample && net_.config().kl) {  // z ~ q(z|x), as in training (a
      Matrix eps(x.rows(), net_.config().latent);             // deterministic encoder: the mean)
      for (Index k = 0; k < eps.size(); ++k) eps.data()[k] = static_cast<float>(rng.normal());
      z = nn::reparameterize(mu, logvar, eps);
    }
  } else {
    Matrix eps = Matrix::Zero(x.rows(), net_.config().latent);
    if (latent == LatentInput::prior)
      for (Index k = 0; k < eps.size(); ++k) eps.data()[k] = static_cast<float>(rng.normal());
    z = tape_.constant(eps);
  }
  const Matrix y = net_.decode_step(bound_, chain_, xin, z, states, before, steps_).value();
  ++steps_;
  for (std::size_t l = 0; l < states.size(); ++l)
    h_[l] = states[l].h.value(), c_[l] = states[l].c.value();
  if (needs_previous) previous_ = x;
  return y;
}

std::vector<double> probe_prediction_error(const BdlstmNet<float>& net, const Matrix& X,
                                           const std::vector<std::int64_t>& starts, int initial,
                                           int length, std::int64_t q, const LatentInput* latent,
                                           Rng& rng) {
  const auto rows = static_cast<Index>(starts.size());
  auto frame = [&](int t) {  // frame t of every window, [rows, 9V]
    Matrix x(rows, X.cols());
    for (Index r = 0; r < rows; ++r) x.row(r) = X.row(starts[static_cast<std::size_t>(r)] + t * q);
    return x;
  };
  auto error = [&](const Matrix& pred, const Matrix& truth) {
    double e = 0;
    for (Index r = 0; r < rows; ++r)
      e += (pred.row(r) - truth.row(r)).norm() / std::max(truth.row(r).norm(), 1e-12f);
    return e / static_cast<double>(rows);
  };
  std::vector<double> err;
  if (!latent) {  // zero motion: the last given frame
    const Matrix last = frame(initial - 1);
    for (int k = 1; k <= length; ++k) err.push_back(error(last, frame(initial - 1 + k)));
    return err;
  }
  ChainStepper chain(net, 0);
  chain.reset(rows, static_cast<float>(net.config().init_state), 0, rng);
  auto step = [&](const Matrix& x) { return chain.step(x, *latent, rng); };
  Matrix y;
  for (int t = 0; t < initial; ++t) y = step(frame(t));
  for (int k = 1; k <= length; ++k) {
    err.push_back(error(y, frame(initial - 1 + k)));
    if (k < length) y = step(y);
  }
  return err;
}

}  // namespace df::models
