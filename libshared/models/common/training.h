// What every trainer of the toolkit shares (train-bdlstm, train-msae, train-actgan):
// the iteration loop with its loss printing, the training log, checkpoints on printing
// boundaries, and the early output check. A trainer supplies one step (draw a batch with the
// model's RNG, take an optimizer step, return the loss terms) and one checkpoint writer.
#pragma once

#include <fmt/format.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/atomic_output.h"
#include "core/error.h"

namespace CLI {
class Option_group;
}

namespace df::models {

struct TrainingLoop {
  std::int64_t iterations = 0;  ///< train until the model has done this many
  int print_every = 100;        ///< average and print the loss terms every K iterations
  int checkpoint_every = 0;     ///< 0 = no checkpoints during the run
  std::string checkpoint_path;  ///< where checkpoint() writes (for messages)
  /// When set, called after each loss line with its log row [k, means..., evaluated...]
  /// (e.g. a check of what the model has learned so far that warns)
  std::function<void(const std::vector<double>& row)> after_row = {};
};

/// What every trainer's run shares: where and how often it checkpoints, --resume, loss lines.
struct TrainingRun {
  std::string checkpoint;      ///< "" = OUTPUT.ckpt (removed after success; a named one is kept)
  int checkpoint_every = 500;  ///< iterations between checkpoints (0 = none)
  bool resume = false;         ///< continue from the checkpoint when it exists
  int print_every = 100;       ///< iterations per loss line and log row
  /// The checkpoint file of a run that writes `output`.
  std::string checkpoint_path(const std::string& output) const;
  /// UsageError for a non-positive print_every or a negative checkpoint_every.
  void check() const;
  /// After the final model is written: removes our own OUTPUT.ckpt (one the user named is kept).
  void finish(const std::string& output) const;
};

/// Declares --print-every, --checkpoint, --checkpoint-every and --resume on a trainer's options.
void add_training_run_options(CLI::Option_group& group, TrainingRun& run);

/// Loss terms of one iteration; the first is the total that was minimised.
using LossTerms = std::vector<double>;

/// Runs iterations iteration+1 .. loop.iterations. Each calls step(k) with k the iteration it
/// completes (1-based) and gets its loss terms; a non-finite total stops with an Error. Every
/// print_every iterations (and at the last) the mean terms since the last print are appended to
/// `log` as one row [k, means...] and printed ("iteration k/K: loss ... (recon ..., ...)").
/// `iteration` is updated before any checkpoint, so a checkpoint records the iterations its state
/// holds; checkpoints fall on printing boundaries where a multiple of checkpoint_every was passed.
/// A stop request (SIGTERM, SIGUSR1: core/atomic_output.h) is honoured after the iteration in
/// progress: checkpoint, then Stopped. `unprinted` carries the iterations since the last log row
/// ([count, sums...]; empty at a row) into such a checkpoint and back, so a resumed run logs what
/// an uninterrupted one does.
/// @param names  the terms' names, as printed ("loss", "recon", ...)
/// @param evaluate  when set, called at every printing boundary; its values (named by
///                  `evaluate_names`, e.g. a validation error) follow the means in the log row
void run_training_loop(const TrainingLoop& loop, const std::vector<std::string>& names,
                       std::int64_t& iteration, std::vector<double>& log,
                       std::vector<double>& unprinted,
                       const std::function<LossTerms(std::int64_t)>& step,
                       const std::function<void()>& checkpoint,
                       const std::vector<std::string>& evaluate_names = {},
                       const std::function<LossTerms()>& evaluate = {});

/// --resume's guard: InvalidInput naming the checkpoint when a setting it was made with differs
/// from this run's (the result would be neither run).
template <class A, class B>
void require_same_setting(const char* what, const A& checkpoint, const B& now,
                          const std::string& path) {
  if (checkpoint != now)
    throw InvalidInput(
        fmt::format("checkpoint was made with {} = {}, this run has {}; remove it or use the "
                    "same settings",
                    what, checkpoint, now),
        path);
}

/// What a trainer claims before any work and holds for the whole run: its output and its
/// checkpoint (core/atomic_output.h's OutputClaim: a second run writing either fails at once,
/// and a directory that cannot be written fails now, not after hours of training).
struct TrainingClaims {
  OutputClaim output, checkpoint;
};

/// Claims a trainer's output and checkpoint. IOError if `output` exists without `force`, or is
/// `input`; IOError if the checkpoint of an earlier run exists and neither `run.resume`
/// (continue it) nor `force` (start over, replacing it: said with a warning) was given.
TrainingClaims claim_training_outputs(const std::string& output, const std::string& input,
                                      bool force, const TrainingRun& run);

}  // namespace df::models
