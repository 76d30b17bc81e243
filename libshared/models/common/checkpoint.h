// Checkpoints: parameters (by name), Adam's state, the RNG state and the iteration, in the
// `nn-checkpoint` layout (schemas/nn-checkpoint.json) that every model file extends. Writing
// is atomic, so a training run killed at any moment resumes from its last complete
// checkpoint and ends with weights bit-identical to an uninterrupted run.
#pragma once

#include <cstdint>
#include <string>

#include "core/rng.h"
#include "io/h5.h"
#include "io/model_file.h"
#include "nn/adam.h"
#include "nn/parameters.h"

namespace df::models {

/// Writes the training state into an open file (groups /params, /optimizer, /rng and the root
/// attribute `iteration`); the caller writes the header and anything model-specific. `adam`
/// null: no /optimizer (a finished model file that keeps what it needs to run, not to train on:
/// Adam's two moments are twice the parameters' size).
void write_training_state(h5::File& f, const nn::ParameterStore<float>& params,
                          const nn::Adam<float>* adam, const Rng& rng, std::int64_t iteration);

/// Restores it. The file's parameters must match the store's names and shapes exactly. A file
/// without /optimizer (has_optimizer_state) leaves `adam` as it is.
/// @return the iteration
std::int64_t read_training_state(const h5::File& f, nn::ParameterStore<float>& params,
                                 nn::Adam<float>& adam, Rng& rng);
/// Whether the file holds Adam's state (/optimizer): a checkpoint does, a finished BD-LSTM model
/// file does not.
bool has_optimizer_state(const h5::File& f);

/// Sets an optimizer's or a generator's state to one read from a file (io/model_file.h).
void restore_adam(nn::Adam<float>& adam, const io::AdamState& s);
void restore_rng(Rng& rng, const io::RngState& s);

/// A complete checkpoint file of kind `nn-checkpoint`, written atomically.
void save_checkpoint(const std::string& path, const nn::ParameterStore<float>& params,
                     const nn::Adam<float>& adam, const Rng& rng, std::int64_t iteration);
std::int64_t load_checkpoint(const std::string& path, nn::ParameterStore<float>& params,
                             nn::Adam<float>& adam, Rng& rng);

}  // namespace df::models
