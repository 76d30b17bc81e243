// The msae-model file kind (schemas/msae-model.json): the network's configuration, weights, Adam
// and RNG state (enough to resume training bit-exactly), the template and normalization of the
// training data, the shapes trained on / validated on / held out, the geodesic distances from the
// final component centres and the training log. Written by train-msae (final model and periodic
// checkpoints), read by recon-msae and extract-components.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "geometry/acap_features.h"
#include "io/mesh_io.h"
#include "models/common/training.h"
#include "models/msae/network.h"
#include "nn/adam.h"

namespace df::models {

/// How train-msae splits the shapes (MsaeTraining::split) and starts a level's Adam when the
/// levels train one after another (separate_rate); names as core/choice.h.
enum class SplitKind { sequence, collection, lists };
inline constexpr Named<SplitKind> kSplitKindNames[] = {{"sequence", SplitKind::sequence},
                                                       {"collection", SplitKind::collection},
                                                       {"lists", SplitKind::lists}};
constexpr std::span<const Named<SplitKind>> names_of(SplitKind) {
  return kSplitKindNames;
}
/// How a model file's geodesic distances were made: "heat", the heat method with other connected
/// parts at the diameter (files before stop 78), or "heat-bridged", other parts at the straight
/// line (geometry::GeodesicRows since stop 78). The same on a mesh of one part.
enum class GeodesicMethod { heat, heat_bridged };
inline constexpr Named<GeodesicMethod> kGeodesicMethodNames[] = {
    {"heat", GeodesicMethod::heat}, {"heat-bridged", GeodesicMethod::heat_bridged}};
constexpr std::span<const Named<GeodesicMethod>> names_of(GeodesicMethod) {
  return kGeodesicMethodNames;
}
enum class SeparateRate { restart, continue_ };
inline constexpr Named<SeparateRate> kSeparateRateNames[] = {{"restart", SeparateRate::restart},
                                                             {"continue", SeparateRate::continue_}};
constexpr std::span<const Named<SeparateRate>> names_of(SeparateRate) {
  return kSeparateRateNames;
}

/// How the model was trained (recorded in /config; checked on --resume; declared in
/// models/msae/settings.cpp).
struct MsaeTraining {
  std::int64_t iterations = 2000;
  int batch = 256;  ///< shapes per iteration, drawn with replacement from the training shapes
  double lr = 1e-3;
  /// Exponential decay: lr · decay^(step / decay_steps) (the paper: "exponential decay").
  double lr_decay = 0.5;
  double lr_decay_steps = 1000;
  /// The rate rises linearly from lr / N to lr over the first N iterations (0: none, the paper).
  /// Tried because Adam's first steps move every weight by about the rate and so replace a
  /// started block (--init local); measured, it only delays that (docs/msae.md).
  double lr_warmup = 0;
  /// With --init local / local-all: the started blocks' parameters (convolutions, C, decoder
  /// bias) step at this fraction of the rate (1: as every other weight, as before). Adam's first
  /// steps move every weight by about the rate whatever its gradient, so at the full rate they
  /// replace the started components (docs/msae.md); at 0.01 the started block keeps them.
  double started_rate = 1;
  /// With --init local / local-all and --decoder-fc linear: a started block's convolutions start
  /// as s·I and its C as the components / s (1: I and the components, as before). The encoder's
  /// tanh then sees s·x, nearly linear for small s, and the block starts as the projection onto
  /// the components up to its output's tanh alone (at 1 the encoder's tanh bends it too:
  /// docs/msae.md).
  double start_scale = 1;
  /// sequence: every `every`-th shape of each sequence trains, the rest is held out (paper 1:9);
  /// collection: a random `train_fraction` of the shapes trains (paper 1:1); lists: given files.
  SplitKind split = SplitKind::sequence;
  int every = 10;
  double train_fraction = 0.5;
  /// This fraction of the held-out shapes (placed by the seed) validates instead of testing:
  /// iteration counts and options are chosen on it, never on the test shapes.
  double validation_fraction = 0;
  /// Train the levels one after another (iterations shared equally, earlier levels frozen)
  /// instead of jointly (paper Table 4).
  bool separate = false;
  /// Separate training: each level's new Adam starts at `lr` ("restart") or at the rate the
  /// run's schedule has reached when the level starts ("continue": the rate joint training has
  /// there, so that Table 4 compares strategies rather than schedules).
  SeparateRate separate_rate = SeparateRate::restart;
  /// Shapes the decoders make, added to every batch: each of their codes is the same code of a
  /// training shape of the batch drawn at random, independently per code (every block's, through
  /// the current encoder), so that the encoder learns to invert the decoders on combinations of
  /// the components no training shape shows (docs/msae.md). 0 = none (the paper).
  int synthetic = 0;
  /// Their share of the reconstruction loss against the batch's real shapes (1 = as much).
  double synthetic_weight = 1;
  std::uint64_t seed = 0;
};

/// Global frame indices of the data file, in increasing order.
struct MsaeSplit {
  std::string data;  ///< the data file's name as given
  std::vector<std::int64_t> train, validation, test;
};

/// The model and its training state (models/common/training.h: iteration, log, Adam, RNG of the
/// batches).
struct MsaeModel : TrainingState<std::unique_ptr<nn::Adam<float>>> {
  MsaeConfig config;
  MsaeTraining training;
  Mesh tmpl;
  geometry::Normalization normalization;
  MsaeSplit split;
  /// The template's geodesic diameter (mesh units) and the normalized distances from the
  /// centres of the last iteration (sources [n], rows [n, V]).
  double geodesic_diameter = 0;
  GeodesicMethod geodesic_method = GeodesicMethod::heat_bridged;
  std::vector<int> geodesic_sources;
  std::vector<Eigen::VectorXf> geodesic_rows;
  /// The log has a validation_erms column (E_rms × 1000 of the validation shapes' positions).
  bool log_validation_erms = false;
  /// The last loss line's collapse warning (CollapseSigns::describe; "" = none) and the
  /// iteration of the first loss line that warned (0 = none): /training/log's attributes
  std::string collapse;
  std::int64_t collapse_since = 0;
  std::unique_ptr<MsaeNet<float>> net;
  std::string history;  ///< inherited provenance (the data file's)

  /// The training log's columns: iteration total recon sparsity latent, and validation (and
  /// validation_erms when measured) when the split has a validation part.
  std::vector<std::string> log_columns() const;
  /// A new, untrained model (weights from the seed) for a template.
  void initialize();
  /// A fresh Adam with the configured learning rate and decay (separate training starts one per
  /// level, at iteration `start`: with separate_rate "continue" its rate starts where the
  /// schedule is at that iteration).
  std::unique_ptr<nn::Adam<float>> make_adam(std::int64_t start = 0) const;
};

/// Writes the whole model (header included) to `path` atomically.
void save_msae_model(const std::string& path, const MsaeModel& m,
                     const std::vector<std::string>& inputs, bool force);
/// Reads and validates a model file.
MsaeModel load_msae_model(const std::string& path);

}  // namespace df::models
