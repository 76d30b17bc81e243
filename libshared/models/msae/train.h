// train-msae: trains the multiscale attention autoencoder (SPEC §7) on the normalized ACAP
// features of an acap file: batches of shapes drawn from the training split, every block's loss
// summed (joint training) or one level after another (separate), the centres of Ω's masks and
// their geodesic distances recomputed every iteration.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/common_options.h"
#include "models/common/training.h"
#include "models/msae/model.h"

namespace df::io {
class AcapReader;
}  // namespace df::io
namespace df::geometry {
class GeodesicRows;
}  // namespace df::geometry

namespace df::models {

/// Measures reconstructed validation shapes in positions (E_rms × 1000 of their normalized
/// features, rows in the order of `frames`), the tables' measure; made once per run from the model
/// (its data file, split and normalization). Supplied by the caller (eval::ShapeErms), as the
/// measures live above the models.
using MsaeShapeMeasure = std::function<double(const nn::Matrix<float>& normalized)>;
using MsaeShapeMeasureFactory =
    std::function<MsaeShapeMeasure(const MsaeModel&, const std::vector<std::int64_t>& frames)>;

struct MsaeTrainOptions {
  std::string input, output;
  std::string train_list, test_list;  ///< explicit split: files of frame names or indices
  TrainingRun run;                    ///< checkpoints, --resume, loss lines
  MsaeConfig net;
  MsaeTraining training;
  /// When set and there are validation shapes, every loss line also logs their E_rms.
  MsaeShapeMeasureFactory position_error;
};

/// The paper's split of the frames of an acap file (offsets as in its /sequences/offsets):
/// "sequence" trains on every `every`-th frame of each sequence (its first frame included),
/// "collection" on a random round(train_fraction × N) frames drawn from the seed; the rest is
/// held out. Then round(validation_fraction × held out) of the held-out frames, drawn from the
/// seed, validate instead of testing.
MsaeSplit split_shapes(const std::vector<std::int64_t>& offsets, const MsaeTraining& t);

/// An explicit split from list files (one frame name of /frames/names, or a frame index, per
/// line; blank lines and # comments skipped). Without a test list every frame not trained on is
/// held out. InvalidInput names the file and line of an unknown or repeated entry.
MsaeSplit split_from_lists(const std::vector<std::string>& frame_names,
                           const std::string& train_list, const std::string& test_list);

/// train-msae's defaults where they differ from the paper's form (MsaeConfig's and
/// MsaeTraining's own values; --paper-form): chosen by their worst case over the shared sets'
/// validation shapes against SPLOCS on the same ACAP features (issue 65, docs/msae.md).
void apply_msae_defaults(MsaeConfig& net, MsaeTraining& training);

/// The options' own rules: each setting's range (the settings table), then the rules between
/// settings (UsageError).
void check_msae_options(const MsaeTrainOptions& opt);

/// An MSAE training run over run_trainer (models/common/training.h): the model the options and
/// the data describe (settings, template, normalization, split), the features, and its hooks —
/// start (the geodesic distances; --init's data-dependent start), resume, step, validation, the
/// collapse check, saving. The job around it (options checked, outputs claimed, the data opened,
/// eval's measure passed in, the run) is apps::train_msae's.
class MsaeTrainer {
 public:
  /// `features`: every frame's normalized features (models::training_features).
  MsaeTrainer(const MsaeTrainOptions& opt, const CommonOptions& common, const io::AcapReader& in,
              nn::Matrix<float> features);
  MsaeTrainer(const MsaeTrainer&) = delete;
  MsaeTrainer& operator=(const MsaeTrainer&) = delete;
  ~MsaeTrainer();
  MsaeModel& model() { return m_; }
  /// run_trainer's hooks; they refer to this trainer, which must outlive the run.
  Trainer hooks();

 private:
  void check_collapse();

  const MsaeTrainOptions& opt_;
  MsaeModel m_;
  const std::string report_;  ///< how to see the components, for the collapse warning
  nn::Matrix<float> data_;    ///< the normalized features, one row per frame
  nn::Matrix<float> validation_;
  std::unique_ptr<geometry::GeodesicRows> geodesic_;
  nn::Matrix<float> batch_, weights_;
  MsaeShapeMeasure erms_;
};

}  // namespace df::models
