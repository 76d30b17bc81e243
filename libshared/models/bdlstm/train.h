// train-bdlstm: trains the share-weight BD-LSTM (SPEC §6) on the normalized ACAP features of an
// acap file. Windows of `window` frames (every `stride`-th frame) are drawn from the training
// part of the sequences; a contiguous part of each sequence is held out for testing.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/common_options.h"
#include "models/bdlstm/model.h"
#include "models/common/frame_part.h"
#include "models/common/training.h"
#include "nn/tape.h"

namespace df::io {
class AcapReader;
}  // namespace df::io

namespace df::models {

struct BdlstmTrainOptions {
  std::string input, output;
  TrainingRun run;  ///< checkpoints, --resume, loss lines
  BdlstmConfig net;
  BdlstmTraining training;
  /// training.stopping_fraction is the tool's default, not asked for: sequences too short for
  /// the stopping part train without one, with a warning (asked for, it is an error).
  bool stopping_by_default = false;
  /// training.speeds is the tool's default: where no window fits at the fastest speed but one
  /// fits at the data's own pace, the speeds that fit are kept, with a warning.
  bool speeds_by_default = false;
};

/// Splits each sequence (offsets as in the acap file) into a training part and a held-out
/// contiguous part of round(fraction × length) frames at its end, start, middle, or at a place
/// drawn from `seed` (random; the paper "randomly excludes a subsequence").
/// Then, when validation_fraction > 0, a validation part of round(validation_fraction × length)
/// frames inside the training frames at a place drawn from `seed` (its own stream: the test part
/// and the training draws do not move); InvalidInput if the training frames have no room for it.
/// Then, when stopping_fraction > 0, a stopping part clear of the validation part, at an end of
/// a stretch of training frames (beside a part carved before or at an end of the training
/// frames: no stretch is cut in two) where it leaves the longest stretch, so long windows still
/// fit; ties drawn from `seed` (its own stream too: the test and validation parts do not move).
void split_sequences(const std::vector<std::int64_t>& offsets, double fraction, TestPart part,
                     std::uint64_t seed, BdlstmSplit& split, double validation_fraction = 0,
                     double stopping_fraction = 0);
/// First frames of every window of `span` frames inside a training part and clear of its
/// sequence's held-out, validation and stopping parts, in sequence and frame order.
std::vector<std::int64_t> window_starts(const BdlstmSplit& split, std::int64_t span);

/// First frames of windows of `span` frames inside one part of every sequence: train (as
/// window_starts), validation or test.
std::vector<std::int64_t> part_starts(const BdlstmSplit& split, FramePart part, std::int64_t span);
/// The same inside each sequence's range [begin[s], end[s]) (e.g. the stopping parts).
std::vector<std::int64_t> range_starts(const std::vector<std::int64_t>& begin,
                                       const std::vector<std::int64_t>& end, std::int64_t span);

/// Frame t of a window played at `speed` from frame `first` of `data` (one frame per row): the
/// data at first + t × stride × speed, interpolated linearly between frames (speed 0: the first
/// frame held still), written to row `row` of window[t] for every t of the window.
void play_window(const nn::Matrix<float>& data, std::int64_t first, int stride, double speed,
                 std::vector<nn::Matrix<float>>& window, Eigen::Index row);

/// Predicted steps of train-bdlstm's validation error (Table 1's horizon), fewer when the
/// validation part is shorter.
inline constexpr int kValidationSteps = 15;

/// The options' own rules: each setting's range (the settings table), then the rules between
/// settings (UsageError).
void check_bdlstm_options(const BdlstmTrainOptions& opt);

/// A BD-LSTM training run over run_trainer (models/common/training.h): the model the options and
/// the data describe (settings, template, normalization, split), the training windows and the
/// features, and its hooks — start, resume, step, validation, the collapse check, saving (the
/// model file without Adam's state, checkpoints with it). The job around it (options checked,
/// outputs claimed, the data opened, the run) is apps::train_bdlstm's.
class BdlstmTrainer {
 public:
  /// `features`: every frame's normalized features (models::training_features).
  BdlstmTrainer(const BdlstmTrainOptions& opt, const CommonOptions& common,
                const io::AcapReader& in, nn::Matrix<float> features);
  BdlstmTrainer(const BdlstmTrainer&) = delete;
  BdlstmTrainer& operator=(const BdlstmTrainer&) = delete;
  BdlstmModel& model() { return m_; }
  /// run_trainer's hooks; they refer to this trainer, which must outlive the run.
  Trainer hooks();

 private:
  LossTerms step(std::int64_t done);
  void check_collapse(const std::vector<double>& row);
  void keep_best(const std::vector<double>& row);
  void consider_weights(std::int64_t iteration, double error);
  void save(const std::string& path, bool force, BdlstmFile kind);

  const BdlstmTrainOptions& opt_;
  BdlstmModel m_;
  std::vector<std::int64_t> starts_;  ///< first frames of the training windows
  nn::Matrix<float> data_;            ///< the normalized features, one row per frame
  nn::Tape<float> tape_;
  std::vector<nn::Matrix<float>> window_;  ///< a batch of windows: [window] x [batch, 9V]
  /// The stopping part's error / zero motion's (empty without --stopping-fraction)
  std::function<double()> stopping_;
  double kl_nats_ = 0;  ///< Σ of the iterations' KL per frame since the last loss line
  long kl_steps_ = 0;
};

/// The collapse check of a loss line: true when the latent's KL per encoded frame is below
/// `threshold` while the reconstruction (`recon`) is not 10% below the first loss line's
/// (`first_recon`), i.e. the latent says (almost) nothing and the network has not learned to
/// predict without it — a model that predicts what the prior does.
bool latent_collapsed(double kl_per_frame, double recon, double first_recon, double threshold);

/// The remedies that train-bdlstm uses unless --paper-form (chosen on validation parts,
/// docs/bdlstm.md): KL warm-up over 500 iterations, 0.1 free nats per latent dimension, L_2 on the
/// weights only at 1/8 of the paper's weight, the last decoder convolution started small instead of
/// at zero, the encoder reading each step's motion, and training windows played at speeds 0,
/// 0.5, 1 and 1.5 (issue 67).
void apply_learning_defaults(BdlstmConfig& net, BdlstmTraining& training);
/// The paper's exact form of the same settings (eq. 3-5 as written).
void apply_paper_form(BdlstmConfig& net, BdlstmTraining& training);

}  // namespace df::models
