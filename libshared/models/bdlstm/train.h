// train-bdlstm: trains the share-weight BD-LSTM (SPEC §6) on the normalized ACAP features of an
// acap file. Windows of `window` frames (every `stride`-th frame) are drawn from the training
// part of the sequences; a contiguous part of each sequence is held out for testing.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/tool.h"
#include "models/bdlstm/model.h"

namespace df::models {

struct BdlstmTrainOptions {
  std::string input, output;
  std::string checkpoint;      ///< "" = OUTPUT.ckpt (removed after success; a named one is kept)
  int checkpoint_every = 500;  ///< iterations between checkpoints (0 = none)
  bool resume = false;         ///< continue from the checkpoint when it exists
  int print_every = 100;       ///< iterations between loss lines (and training-log rows)
  BdlstmConfig net;
  BdlstmTraining training;
};

/// Splits each sequence (offsets as in the acap file) into a training part and a held-out
/// contiguous part of round(fraction × length) frames at its end, start, middle, or at a place
/// drawn from `seed` (random; the paper "randomly excludes a subsequence").
void split_sequences(const std::vector<std::int64_t>& offsets, double fraction, const std::string& part,
                     std::uint64_t seed, BdlstmSplit& split);
/// First frames of every window of `span` frames inside a training part and clear of its
/// sequence's held-out part, in sequence and frame order.
std::vector<std::int64_t> window_starts(const BdlstmSplit& split, std::int64_t span);

void train_bdlstm(const BdlstmTrainOptions& opt, const CommonOptions& common);

}  // namespace df::models
