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
#include "core/rng.h"

namespace CLI {
class Option_group;
}

namespace df::models {

/// Loss terms of one iteration; the first is the total that was minimised.
using LossTerms = std::vector<double>;

/// What a model carries of its training run besides its weights and settings: the iterations
/// done, the training log, Adam's state and the RNG its batches are drawn from — what a checkpoint
/// holds so that a resumed run goes on as an uninterrupted one. Every model derives from it
/// (`Optimizers`: one Adam, or ActGAN's five), so --resume takes a checkpoint's state over in one
/// assignment (take_training_state) and the loop (run_training_loop) reads and advances it.
struct TrainingProgress {
  std::int64_t iteration = 0;     ///< iterations done
  std::vector<double> log;        ///< rows of the model's log_columns(), flat
  std::vector<double> unprinted;  ///< a checkpoint's iterations after the last log row
};

template <class Optimizers>
struct TrainingState : TrainingProgress {
  Optimizers adam;
  Rng rng;  ///< batches and noise

  /// A fresh run: no iterations, an empty log, `fresh` optimizers, the seed's batch stream.
  void restart(Optimizers fresh, std::uint64_t seed) {
    static_cast<TrainingProgress&>(*this) = {};
    adam = std::move(fresh);
    rng = Rng(seed, 1);
  }
};

/// --resume: the checkpoint's training state (iteration, log, optimizers, RNG) replaces the
/// model's.
template <class Optimizers>
void take_training_state(TrainingState<Optimizers>& model, TrainingState<Optimizers>&& checkpoint) {
  model = std::move(checkpoint);
}

/// A validation measure logged at every loss line: its columns' names and the values.
struct Validation {
  std::vector<std::string> names;
  std::function<LossTerms()> measure;  ///< empty: no validation columns
};

/// One run of training iterations: how far and how often, and what a trainer supplies.
struct TrainingLoop {
  std::int64_t iterations = 0;     ///< train until the model has done this many
  int print_every = 100;           ///< average and print the loss terms every K iterations
  int checkpoint_every = 0;        ///< 0 = no checkpoints during the run
  std::string checkpoint_path;     ///< where checkpoint() writes (for messages)
  std::vector<std::string> names;  ///< the loss terms, as printed ("loss", ...)
  std::function<LossTerms(std::int64_t)> step;  ///< iteration k (1-based): its loss terms
  std::function<void()> checkpoint;             ///< writes the checkpoint
  Validation validation = {};                   ///< evaluated at every loss line
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
/// `model_is_checkpoint`: the tool's model file holds all a checkpoint does (the help says so);
/// false for train-bdlstm's, which leaves out Adam's state.
void add_training_run_options(CLI::Option_group& group, TrainingRun& run,
                              bool model_is_checkpoint = true);

/// Runs iterations state.iteration+1 .. loop.iterations. Each calls loop.step(k) with k the
/// iteration it completes (1-based) and gets its loss terms; a non-finite total stops with an
/// Error. Every print_every iterations (and at the last) the mean terms since the last print are
/// appended to `state.log` as one row [k, means..., validation...] and printed ("iteration k/K:
/// loss ... (recon ..., ...)"). `state.iteration` is updated before any checkpoint, so a
/// checkpoint records the iterations its state holds; checkpoints fall on printing boundaries where
/// a multiple of checkpoint_every was passed. A stop request (SIGTERM, SIGUSR1:
/// core/atomic_output.h) is honoured after the iteration in progress: checkpoint, then Stopped.
/// `state.unprinted` carries the iterations since the last log row ([count, sums...]; empty at a
/// row) into such a checkpoint and back, so a resumed run logs what an uninterrupted one does.
void run_training_loop(const TrainingLoop& loop, TrainingProgress& state);

/// What a model's trainer supplies to run_trainer: the steps that differ between models.
struct Trainer {
  std::string output;           ///< the model file written at the end
  std::int64_t iterations = 0;  ///< the run trains until the model has done this many
  /// The option(s) that set `iterations`, for the message when a checkpoint is past them
  const char* iterations_option = "--iterations";
  /// A new model: weights and optimizers from the seed.
  std::function<void()> initialise;
  /// --resume with a checkpoint there: read it, refuse it (InvalidInput) when it was made with
  /// other settings or data, and take its state over.
  std::function<void(const std::string& checkpoint)> resume;
  /// After the start, before the first iteration (optional): what depends on whether the model is
  /// new (a fresh model's data-dependent start) and the line describing the run.
  std::function<void()> prepare = {};
  /// After prepare (optional): the validation measure of the loss lines.
  std::function<Validation()> validation = {};
  std::vector<std::string> names;               ///< the loss terms (TrainingLoop::names)
  std::function<LossTerms(std::int64_t)> step;  ///< one iteration (TrainingLoop::step)
  std::function<void(const std::vector<double>&)> after_row = {};  ///< TrainingLoop::after_row
  /// Writes the model (the checkpoints and the final file): `force` replaces an existing file.
  std::function<void(const std::string& path, bool force)> save;
  /// Writes a checkpoint when the model file does not hold all a checkpoint needs (BD-LSTM's
  /// leaves out Adam's state); empty: `save`. Then a checkpoint named with --checkpoint (kept)
  /// also takes the final state, so that training can go on from it later.
  std::function<void(const std::string& path, bool force)> save_checkpoint = {};
  /// After the last iteration, before the model is written (optional; e.g. a final warning).
  std::function<void()> finished = {};
};

/// Every trainer's run after its options are checked, its outputs claimed and its model
/// described: continues the checkpoint (--resume, when it exists) or starts afresh, refuses a
/// checkpoint past the iteration count, prepares, runs the iterations (loss lines, validation,
/// checkpoints, stop requests), writes the model to `t.output` and removes its own checkpoint.
void run_trainer(const Trainer& t, TrainingProgress& state, const TrainingRun& run, bool force);

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
