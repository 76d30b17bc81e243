// One chain of a trained BD-LSTM run step by step (generation, inspect-bdlstm, train-bdlstm's
// validation error), and the probe of its prediction error over windows of the data.
#pragma once

#include <cstdint>
#include <vector>

#include "core/rng.h"
#include "models/bdlstm/model.h"

namespace df::models {

/// Runs one chain of the network step by step without keeping the activations: parameters are
/// bound once, every step's nodes are dropped after it (generation and inspect-bdlstm).
class ChainStepper {
 public:
  ChainStepper(const BdlstmNet<float>& net, int chain);
  /// Initial states of `rows` rows: every h and c entry is `value` (+ N(0, sigma²) when sigma > 0).
  void reset(Eigen::Index rows, float value, double sigma, Rng& rng);
  /// X_{t+1} for frames x [rows, 9V], z the encoder's mean.
  nn::Matrix<float> step(const nn::Matrix<float>& x);
  /// The same with z chosen by `latent` (prior draws come from `rng`).
  nn::Matrix<float> step(const nn::Matrix<float>& x, LatentInput latent, Rng& rng);

 private:
  const BdlstmNet<float>& net_;
  int chain_;
  nn::Tape<float> tape_;
  nn::Bound<float> bound_;
  std::size_t mark_ = 0;
  std::vector<nn::Matrix<float>> h_, c_;
  nn::Matrix<float> previous_;  ///< the input of the step before (kept when the net needs it)
  int steps_ = 0;               ///< steps since reset (the carry fades with them)
};

/// Relative feature error ‖X̂_k − X_k‖ / ‖X_k‖ at steps k = 1..length, the mean over windows that
/// start at `starts` (frames q apart in X), of the forward chain (states +init_state) fed the
/// first `initial` frames of each window, then running free, with z chosen by `latent`; or of
/// zero motion (the last given frame repeated) when `latent` is null. Prior draws come from `rng`.
/// inspect-bdlstm's probes and train-bdlstm's validation error.
std::vector<double> probe_prediction_error(const BdlstmNet<float>& net, const nn::Matrix<float>& X,
                                           const std::vector<std::int64_t>& starts, int initial,
                                           int length, std::int64_t q, const LatentInput* latent,
                                           Rng& rng);

}  // namespace df::models
