// The bdlstm-model file kind (schemas/bdlstm-model.json): the network's configuration, weights,
// Adam and RNG state (enough to resume training bit-exactly), the template and normalization of
// the training data, the train/test split and the training log. Written by train-bdlstm (final
// model and periodic checkpoints), read by gen-bdlstm.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "geometry/acap_features.h"
#include "io/mesh_io.h"
#include "models/bdlstm/network.h"
#include "models/common/training.h"
#include "nn/adam.h"

namespace df::models {

/// Where train-bdlstm's held-out part of each sequence lies (names as core/choice.h).
enum class TestPart { end, start, middle, random };
inline constexpr Named<TestPart> kTestPartNames[] = {{"end", TestPart::end},
                                                     {"start", TestPart::start},
                                                     {"middle", TestPart::middle},
                                                     {"random", TestPart::random}};
constexpr std::span<const Named<TestPart>> names_of(TestPart) {
  return kTestPartNames;
}

/// How the model was trained (recorded in /config; checked on --resume; declared in
/// models/bdlstm/settings.cpp).
struct BdlstmTraining {
  int window = 32;  ///< frames per training window
  int batch = 8;    ///< windows per iteration
  int stride = 1;   ///< take every stride-th frame (2 for slow data)
  std::int64_t iterations = 7000;
  double lr =
      1e-4;  // 1e-3 (common default) diverges on 2,904-vertex pcow within 6 iterations (KL 3e11)
  double test_fraction = 0.2;          ///< held-out contiguous part of each sequence
  TestPart test_part = TestPart::end;  ///< where the held-out part lies
  /// A validation part of round(fraction × length) frames carved out of each sequence's training
  /// frames, placed by the seed (0 = none): no training window crosses it; remedies and iteration
  /// counts are chosen on it, never on the test part.
  double validation_fraction = 0;
  /// A stopping part of round(fraction × length) frames carved out of each sequence's training
  /// frames after the validation part, placed by the seed (0 = none, the paper): no training
  /// window crosses it; the model file keeps the weights of the loss line at which the prediction
  /// error on its windows (relative to zero motion's) was lowest.
  double stopping_fraction = 0;
  /// With a stopping part: its error is also checked every this many iterations, not only at the
  /// loss lines, and the kept weights are the best of every check (0 = at the loss lines only).
  int stopping_every = 0;
  /// With a stopping part: the untrained network (before the first iteration) is checked too
  /// and kept if no later check beats it, so the model is never worse there than what it starts
  /// from (with --decoder-init zero: dX = 0, the carried motion alone).
  bool stopping_untrained = false;
  /// Each iteration feeds u ground-truth frames, u uniform in 1..teacher_frames, before the
  /// chains run free (1 = the paper: only the seed frame).
  int teacher_frames = 1;
  /// Each training window plays its frames at a speed drawn uniformly from this list: frame t of
  /// the window is the data at first + t × stride × speed, linearly interpolated between frames
  /// (0: the first frame held still). {1} = the data's own pace (no draw; the paper).
  std::vector<double> speeds = {1};
  /// The KL weight rises linearly from 0 to 1 over this many iterations (0 = always 1, the
  /// paper), a common remedy when the latent collapses to the prior.
  std::int64_t kl_warmup = 0;
  /// A loss line warns that the latent has collapsed when the KL per encoded frame (nats, before
  /// free bits and warm-up) is below this while the reconstruction has not improved by 10% over
  /// the first loss line (not stored: a check, not a setting of the model)
  double collapse_threshold = 0.5;
  std::uint64_t seed = 0;
};

/// Frames of each sequence of the training data used for training and held out for testing
/// (global frame indices of the data file, half-open ranges). The frames trained on are the
/// train range minus the test range (a held-out part inside a sequence splits its training part
/// in two; no window crosses it).
struct BdlstmSplit {
  std::string data;  ///< the data file's name as given
  std::vector<std::string> sequences;
  std::vector<std::int64_t> train_begin, train_end, test_begin, test_end;
  /// Per sequence, the validation part inside the training frames ([b, b) when none).
  std::vector<std::int64_t> validation_begin, validation_end;
  /// Per sequence, the stopping part inside the training frames ([b, b) when none).
  std::vector<std::int64_t> stopping_begin, stopping_end;
};

/// The model and its training state (models/common/training.h: iteration, log, Adam, RNG of the
/// windows and the reparameterisation noise).
struct BdlstmModel : TrainingState<std::unique_ptr<nn::Adam<float>>> {
  BdlstmConfig config;
  BdlstmTraining training;
  Mesh tmpl;
  geometry::Normalization normalization;
  BdlstmSplit split;
  /// The training log's columns: iteration total recon bidir kl l2, and validation (the error on
  /// the validation windows relative to zero motion's) when the split has a validation part.
  std::vector<std::string> log_columns() const;
  /// The latent's KL in nats per encoded frame over the last printing interval (−1: not
  /// measured) and whether the latent had collapsed then (train-bdlstm's warning).
  double kl_per_frame = -1;
  bool latent_collapsed = false;
  /// With a stopping part: the weights with the lowest stopping error so far, checked at every
  /// loss line and every stopping_every iterations (empty before the first check), their
  /// iteration and that error. The model file holds these weights
  /// (and says which iteration they are); a checkpoint holds the last ones and these beside them.
  nn::Vector<float> best_weights;
  std::int64_t best_iteration = 0;
  double best_stopping = 0;
  std::unique_ptr<BdlstmNet<float>> net;
  std::string history;  ///< inherited provenance (the data file's)
  /// Whether the file it was read from held Adam's state: a checkpoint does, a finished model file
  /// does not (training continues only from a checkpoint).
  bool optimizer_state = true;

  /// A new, untrained model (weights from the seed) for a template.
  void initialize();
};

/// What a BD-LSTM file holds: everything (a checkpoint: training resumes from it bit-exactly) or
/// all but Adam's moments (the finished model: a third of a checkpoint's size; gen-bdlstm and
/// inspect-bdlstm need nothing more).
enum class BdlstmFile { checkpoint, model };
/// Writes the model (header included) to `path` atomically.
void save_bdlstm_model(const std::string& path, const BdlstmModel& m,
                       const std::vector<std::string>& inputs, bool force, BdlstmFile kind);
/// Reads and validates a model file.
BdlstmModel load_bdlstm_model(const std::string& path);

}  // namespace df::models
