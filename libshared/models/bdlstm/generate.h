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

#include <string>
#include <vector>

#include "core/tool.h"

namespace df::models {

struct BdlstmGenerateOptions {
  std::string model, data, output;
  std::string mode = "predict";   ///< predict | complete
  std::string method = "bdlstm";  ///< bdlstm | linear (the feature-space baseline) | static (predict: no motion)
  /// A frame is a global index of DATA or SEQUENCE:K (K-th frame of that sequence).
  std::vector<std::string> from;       ///< predict: the last given frame of each case
  std::vector<std::string> keyframes;  ///< complete: keyframes of one case, in time order
  /// > 0: cases at every K-th frame of each sequence's held-out part (the model's split)
  int test_every = 0;
  /// predict with --test-every: the first predicted frame of a case is at least this many frames
  /// into the held-out part (0 = --initial), so runs with different --initial predict the same frames
  int test_context = 0;
  int initial = 1;   ///< u: given frames per prediction
  int length = 15;   ///< predict: future frames
  int gap = 9;       ///< complete with --test-every: frames between the two keyframes
  int samples = 1;   ///< per case; > 1 draws random initial states
  double state_sigma = 0.1;  ///< std-dev of random initial states around ±init_state
  double threshold = 0.05;   ///< complete: merge when ‖S^f − S^b‖ / ‖S^f‖ is below this
  int retries = 20;          ///< complete: attempts with random states before giving up
  int window = 0;            ///< predict: restart the chain every WINDOW frames (0 = the model's)
  /// Data frames per generated frame (0 = the model's training --stride): a model trained on
  /// every q-th frame steps q frames at a time, so given frames, keyframes and /frames/source
  /// are q apart.
  int stride = 0;
};

void generate_bdlstm(const BdlstmGenerateOptions& opt, const CommonOptions& common);

}  // namespace df::models
