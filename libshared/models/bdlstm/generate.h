// gen-bdlstm: mesh-sequence synthesis with a trained BD-LSTM (SPEC §6, paper 1 §4):
//   predict   n future frames from u ≥ 1 initial frames (fed in order, then free-running;
//             long sequences restart the LSTM every window with the last u frames);
//   complete  the frames between keyframes: a forward chain from each keyframe and a backward
//             chain from the next, merged at the closest pair of frames of the same (or
//             adjacent) time whose relative feature difference is below a threshold; random
//             initial states are retried until they merge;
//   diverse   --samples K with random initial LSTM states;
// and the baselines of the paper's comparisons: linear extrapolation / interpolation in ACAP
// feature space. Output: an acap file with normalized features (acap2obj makes meshes), one
// sequence per case and sample, with /frames/source (the data frame each generated frame
// corresponds to) and /frames/step (frames after the last given one; 0 for given frames and
// keyframes) for eval-metrics. A model trained with --stride q steps q data frames per
// generated frame (given frames, keyframes and sources are q apart).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/common_options.h"
#include "core/rng.h"
#include "models/bdlstm/chain.h"
#include "models/bdlstm/model.h"
#include "models/common/frame_part.h"

namespace df::models {

/// gen-bdlstm's modes (names as core/choice.h).
enum class GenerateMode { predict, complete };
inline constexpr Named<GenerateMode> kGenerateModeNames[] = {{"predict", GenerateMode::predict},
                                                             {"complete", GenerateMode::complete}};
constexpr std::span<const Named<GenerateMode>> names_of(GenerateMode) {
  return kGenerateModeNames;
}
enum class GenerateMethod { bdlstm, linear, damped, still, nearest };
inline constexpr Named<GenerateMethod> kGenerateMethodNames[] = {
    {"bdlstm", GenerateMethod::bdlstm},
    {"linear", GenerateMethod::linear},
    {"damped", GenerateMethod::damped},
    {"static", GenerateMethod::still},
    {"nearest", GenerateMethod::nearest}};
constexpr std::span<const Named<GenerateMethod>> names_of(GenerateMethod) {
  return kGenerateMethodNames;
}
enum class Restart { never, window };
inline constexpr Named<Restart> kRestartNames[] = {{"never", Restart::never},
                                                   {"window", Restart::window}};
constexpr std::span<const Named<Restart>> names_of(Restart) {
  return kRestartNames;
}
enum class Merge { closest, weighted };
inline constexpr Named<Merge> kMergeNames[] = {{"closest", Merge::closest},
                                               {"weighted", Merge::weighted}};
constexpr std::span<const Named<Merge>> names_of(Merge) {
  return kMergeNames;
}
enum class MergeScale { features, motion };
inline constexpr Named<MergeScale> kMergeScaleNames[] = {{"features", MergeScale::features},
                                                         {"motion", MergeScale::motion}};
constexpr std::span<const Named<MergeScale>> names_of(MergeScale) {
  return kMergeScaleNames;
}

struct BdlstmGenerateOptions {
  std::string model, data, output;
  GenerateMode mode = GenerateMode::predict;
  /// bdlstm | linear (the feature-space baseline) | damped (predict: linear extrapolation whose
  /// step shrinks by `damping` a frame) | static (predict: no motion) | nearest (predict: motion
  /// matching in the model's training part, nearest_motion)
  GenerateMethod method = GenerateMethod::bdlstm;
  /// --method damped: the k-th predicted frame is X_u + (d + d² + … + d^k)(X_u − X_u−1)
  double damping = 0.8;
  int neighbours = 1;  ///< --method nearest: training windows averaged (K nearest)
  /// A frame is a global index of DATA or SEQUENCE:K (K-th frame of that sequence).
  std::vector<std::string> from;       ///< predict: the last given frame of each case
  std::vector<std::string> keyframes;  ///< complete: keyframes of one case, in time order
  /// > 0: cases at every K-th frame of each sequence's held-out part (the model's split)
  int test_every = 0;
  /// which part of the model's split --test-every cases come from: test | validation
  FramePart part = FramePart::test;
  /// predict with --test-every: the first predicted frame of a case is at least this many frames
  /// into the held-out part (0 = --initial), so runs with different --initial predict the same
  /// frames
  int test_context = 0;
  int initial = 1;  ///< u: given frames per prediction
  int length = 15;  ///< predict: future frames
  int gap = 9;      ///< complete with --test-every: frames between the two keyframes
  int samples = 1;  ///< per case; > 1 draws random initial states
  /// std-dev of random initial states around ±init_state (the paper's 0.1, as large as the ±0.1
  /// that tells the shared network its direction; 0.05 with cross-fading did not win on
  /// issue 18's validation parts)
  double state_sigma = 0.1;
  /// complete: merge when the chains' difference, relative as --merge-scale says, is below this
  /// (0 = 1 for "motion", 0.05 for "features", the paper's 5%)
  double threshold = 0;
  int retries = 20;  ///< complete: attempts with random states before giving up
  int window = 0;    ///< predict: restart the chain every WINDOW frames (0 = the model's)
  /// predict: "window" restarts the chain every window from the last u frames with fresh
  /// states (the paper's chaining of fixed-length networks); "never" carries one chain's LSTM
  /// state over the whole length
  Restart restart = Restart::never;
  /// z fed to the LSTM: the encoder's "mean", or a "sample" of q(z|x) as in training
  LatentInput latent = LatentInput::mean;
  /// complete: "closest" (the paper: switch from the forward to the backward chain at their
  /// closest pair of frames, retrying random states until it is below --threshold) or
  /// "weighted" (every step a mix, the forward chain's weight falling linearly over the gap)
  Merge merge = Merge::closest;
  /// complete: frames over which the forward and backward chains are cross-faded around the
  /// merge (0 = switch at the merge, the paper)
  int blend = 0;
  /// complete: --threshold is relative to the forward frame's feature norm ("features", the
  /// paper) or to the chains' mean change per step ("motion")
  MergeScale merge_scale = MergeScale::features;
  /// Data frames per generated frame (0 = the model's training --stride): a model trained on
  /// every q-th frame steps q frames at a time, so given frames, keyframes and /frames/source
  /// are q apart.
  int stride = 0;
};

// --- the steps of gen-bdlstm's job (apps/gen_bdlstm), each callable on its own ---------------

/// The data a generation starts from: features normalized with the model's numbers.
struct GenerationData {
  nn::Matrix<float> features;  ///< [N, 9V]
  std::vector<std::int64_t> offsets;
  std::vector<std::string> sequences;
  std::string history;
  std::size_t sequence_of(std::int64_t frame) const;
};
/// Reads DATA through ModelData (models/common/model_data.h): the template checked, every frame's
/// features in the model's normalization.
GenerationData read_generation_data(const std::string& path, const BdlstmModel& m);

/// One case: predict: its given frames (global, in time order, `stride` apart); complete: its
/// keyframes.
struct GenerationCase {
  std::string name;
  std::vector<std::int64_t> frames;
};
/// The cases of a run: --test-every cases inside the model's held-out parts, or the --from /
/// --keyframes frames. UsageError / InvalidInput when there are none or a frame is invalid.
std::vector<GenerationCase> plan_cases(const BdlstmGenerateOptions& opt, const BdlstmModel& m,
                                       const GenerationData& d, std::int64_t stride);

/// Motion matching (gen-bdlstm --method nearest), a reference that learns nothing: among the
/// windows of the model's training part (the u given frames and `length` more, `stride` data
/// frames apart, clear of the validation and test parts, in d's sequences of the model's split),
/// the `neighbours` whose u frames lie closest to the given ones (sum of squared feature
/// distances; ties: the earlier window). Step k of the prediction is the last given frame plus
/// their mean change from their u-th frame to k steps later.
/// @param given  global frames of d, in time order, `stride` apart
/// @return       `length` rows [1, 9V] (normalized features)
/// InvalidInput when no training window of that span exists.
std::vector<nn::Matrix<float>> nearest_motion(const BdlstmModel& m, const GenerationData& d,
                                              const std::vector<std::int64_t>& given, int length,
                                              std::int64_t stride, int neighbours);

/// One output sequence: normalized features per frame, the data frame of the same time (−1 past
/// the data's end) and the steps after the last given frame (0 for given frames and keyframes).
struct GeneratedSequence {
  std::string name;
  std::vector<nn::Matrix<float>> frames;  ///< each [1, 9V]
  std::vector<std::int64_t> source;
  std::vector<std::int32_t> step;
};

/// One completion of a gap of L steps from the forward chain F (F[0] the first keyframe, F[i] i
/// steps after it) and the backward chain B (B[0] the second keyframe, B[j] j steps before it),
/// row `row` of each: steps 1..L, from F up to step `merge`, from B after it, cross-faded over
/// `blend` frames around the merge (0 = a switch); step L is the second keyframe.
std::vector<nn::Matrix<float>> merged_path(const std::vector<nn::Matrix<float>>& F,
                                           const std::vector<nn::Matrix<float>>& B,
                                           Eigen::Index row, std::int64_t merge, int blend);

/// The same gap without a merge point: step t is (1 − t/L) F_t + (t/L) B_{L−t}, each chain
/// weighing most near its own keyframe (step L is the second keyframe).
std::vector<nn::Matrix<float>> weighted_path(const std::vector<nn::Matrix<float>>& F,
                                             const std::vector<nn::Matrix<float>>& B,
                                             Eigen::Index row);

/// Runs the chains of a model over cases: one object per run, cases in order (the random
/// initial states are drawn from one stream seeded by --seed).
class ChainRunner {
 public:
  ChainRunner(const BdlstmGenerateOptions& opt, const BdlstmModel& m, const GenerationData& d,
              std::int64_t stride, std::uint64_t seed);
  ~ChainRunner();
  /// --samples sequences of the given frames followed by --length predicted ones.
  std::vector<GeneratedSequence> predict(const GenerationCase& c);
  /// --samples sequences from the first keyframe through every gap to the last.
  std::vector<GeneratedSequence> complete(const GenerationCase& c);
  /// Completions that did not merge below --threshold, and the worst merge difference.
  int unmerged() const { return unmerged_; }
  /// The merge threshold in use (--threshold, or its default for --merge-scale).
  double threshold() const { return threshold_; }
  double worst_merge() const { return worst_merge_; }

 private:
  std::int64_t source_of(std::int64_t from, std::int64_t k) const;
  // Paths of steps 1 .. L of every sample across the gap from keyframe a to b.
  std::vector<std::vector<nn::Matrix<float>>> complete_gap(std::int64_t a, std::int64_t b);
  const BdlstmGenerateOptions& opt_;
  const BdlstmModel& m_;
  const GenerationData& d_;
  std::int64_t q_;
  int window_;
  bool restart_;
  LatentInput latent_;
  double threshold_;
  Rng rng_;
  std::unique_ptr<ChainStepper> forward_, backward_own_;
  ChainStepper* backward_;
  int unmerged_ = 0;
  double worst_merge_ = 0;
};

}  // namespace df::models
