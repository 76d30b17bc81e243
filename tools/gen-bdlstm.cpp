// gen-bdlstm: predict, complete and diversify mesh sequences with a trained BD-LSTM (paper 1).
#include "apps/gen_bdlstm.h"
#include "core/choice_option.h"
#include "core/tool.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "gen-bdlstm",
      "Generate mesh sequences with a BD-LSTM from train-bdlstm (Qiao et al., TVCG 2020).\n"
      "  --mode predict   feed --initial u frames ending at each --from frame, then let the\n"
      "                   network run --length frames, z = the encoder's mean (--latent\n"
      "                   sample: drawn from q(z|x) as in training); one chain carries its LSTM\n"
      "                   state over any length (--restart window: the paper's restart every\n"
      "                   --window frames from the last u frames, which damps long runs);\n"
      "  --mode complete  fill the gaps between --keyframes: a forward chain from each\n"
      "                   keyframe (states +0.1) and a backward chain from the next (-0.1)\n"
      "                   are merged at the closest pair of frames of the same or adjacent\n"
      "                   time (--blend N cross-fades them over N frames); random initial\n"
      "                   states are retried until the relative feature difference is below\n"
      "                   --threshold (paper: 5%; --merge-scale motion: relative to the\n"
      "                   chains' change per step).\n"
      "The default --restart never (not the paper's) was chosen on validation parts (README).\n"
      "--samples K draws K different results per case from random initial LSTM states.\n"
      "--method linear gives the baseline of the paper's comparisons: linear extrapolation\n"
      "(from the last two given frames) or interpolation in ACAP feature space; --method\n"
      "damped extrapolates the last step shrinking by --damping a frame (X_u + (d + ... +\n"
      "d^k)(X_u - X_u-1), between static at 0 and linear at 1; docs/bdlstm.md has it\n"
      "ahead of both on the validation parts of three sets at the default 0.8); --method\n"
      "static repeats the last given frame (what a network that learned no motion does);\n"
      "--method nearest learns nothing either: of the training part's windows (frames the\n"
      "model trained on) it takes the one whose u frames lie closest to the given frames and\n"
      "adds its change after them to the last given frame (--neighbours K: the mean of K).\n"
      "--test-every K makes the cases from the model's held-out test parts.\n"
      "A model trained with --stride q steps q data frames per generated frame: the\n"
      "given frames and keyframes are q apart, and so are the frames it is compared with.\n"
      "\n"
      "INPUT: MODEL (bdlstm-model) and DATA (acap file on the same template: the given\n"
      "frames). Frames are global indices of DATA or SEQUENCE:K.\n"
      "OUTPUT: an acap .h5 with normalized features, one sequence per case and sample;\n"
      "/frames/source names the DATA frame of the same time (-1 past its end) and\n"
      "/frames/step the frames after the last given one. acap2obj makes meshes of it;\n"
      "eval-metrics compares it with DATA.");
  tool.with_seed(1).with_force();
  df::models::BdlstmGenerateOptions opt;
  auto& app = tool.app();
  app.add_option("MODEL", opt.model, "bdlstm-model .h5 from train-bdlstm")->required();
  app.add_option("DATA", opt.data, "acap .h5 holding the given frames")->required();
  app.add_option("-o,--output", opt.output, "Output acap file (.h5)")->required();
  df::add_choice(app, "--mode", opt.mode, "predict or complete");
  df::add_choice(app, "--method", opt.method,
                 "bdlstm, linear (feature-space baseline), damped (predict: linear extrapolation\n"
                 "whose step shrinks by --damping a frame), static (predict: the last given frame\n"
                 "repeated, the zero-motion reference) or nearest (predict: motion matching, the\n"
                 "training window whose given frames are closest continues them)");
  app.add_option("--damping", opt.damping,
                 "--method damped: the factor the step shrinks by each frame (0: static, 1: "
                 "linear)")
      ->default_val(opt.damping);
  app.add_option("--neighbours", opt.neighbours,
                 "--method nearest: average the changes of the K closest training windows")
      ->default_val(opt.neighbours);
  app.add_option("--from", opt.from,
                 "predict: last given frame of a case (repeatable, or comma-separated: 5,walk:12)")
      ->delimiter(',')
      ->allow_extra_args(false);
  app.add_option("--keyframes", opt.keyframes,
                 "complete: keyframes in time order, e.g. 10,20,35 or walk:0,walk:12")
      ->delimiter(',')
      ->allow_extra_args(false);
  app.add_option("--test-every", opt.test_every,
                 "Cases at every K-th frame of the model's held-out test parts (instead of\n"
                 "--from / --keyframes)")
      ->default_val(opt.test_every);
  df::add_choice(app, "--part", opt.part,
                 "Where --test-every cases lie: test (the held-out part) or validation (the part\n"
                 "train-bdlstm --validation-fraction carved out of the training frames)",
                 {"test", "validation"});
  app.add_option("--test-context", opt.test_context,
                 "predict with --test-every: the first predicted frame is at least C frames into\n"
                 "the held-out part (0 = --initial), so that runs with different --initial and\n"
                 "--method predict the same frames")
      ->default_val(opt.test_context);
  app.add_option("--initial", opt.initial, "predict: given frames u")->default_val(opt.initial);
  app.add_option("--length", opt.length, "predict: frames to generate")->default_val(opt.length);
  app.add_option("--gap", opt.gap, "complete with --test-every: frames between the two keyframes")
      ->default_val(opt.gap);
  app.add_option("--samples", opt.samples, "Results per case; K > 1 draws random initial states")
      ->default_val(opt.samples);
  app.add_option("--state-sigma", opt.state_sigma,
                 "Std-dev of random initial states around +-0.1 (the paper's; as large as the\n"
                 "direction signal)")
      ->default_val(opt.state_sigma);
  app.add_option("--threshold", opt.threshold,
                 "complete: difference that merges the chains, relative as --merge-scale says\n"
                 "(0 = 1 for motion, 0.05 for features)")
      ->default_val(opt.threshold);
  app.add_option("--retries", opt.retries,
                 "complete: attempts per gap before taking the closest pair")
      ->default_val(opt.retries);
  app.add_option("--window", opt.window,
                 "predict: frames per chained run (0 = the training window)")
      ->default_val(opt.window);
  df::add_choice(
      app, "--restart", opt.restart,
      "predict: window = restart the chain every --window frames from the last u frames\n"
      "with fresh states (the paper's chaining); never = one chain carries its LSTM state\n"
      "over the whole length");
  df::add_choice(
      app, "--latent", opt.latent,
      "z fed to the LSTM: mean (the encoder's) or sample (a draw from q(z|x), as in training)",
      {"mean", "sample"});
  df::add_choice(
      app, "--merge", opt.merge,
      "complete: closest = switch chains at their closest pair of frames (the paper);\n"
      "weighted = mix them at every step, the forward chain's weight falling from 1 to 0\n"
      "over the gap (no threshold, no retries)");
  app.add_option("--blend", opt.blend,
                 "complete: cross-fade the forward and backward chains over N frames around the\n"
                 "merge (0 = switch at the merge, the paper)")
      ->default_val(opt.blend);
  df::add_choice(
      app, "--merge-scale", opt.merge_scale,
      "complete: --threshold relative to the frame's feature norm (features, the paper) or\n"
      "to the chains' mean change per step (motion)");
  app.add_option(
         "--stride", opt.stride,
         "Data frames per generated frame (0 = the model's training --stride): given frames,\n"
         "keyframes and the frames compared with the data are this far apart")
      ->default_val(opt.stride);
  tool.footer(
      "Examples:\n"
      "  gen-bdlstm pcow-model.h5 pcow.h5 --from 170 --initial 3 --length 15 -o pred.h5\n"
      "  gen-bdlstm model.h5 data.h5 --from walk:0 --length 300 -o long.h5\n"
      "  gen-bdlstm model.h5 data.h5 --mode complete --keyframes 10,20 --samples 8 -o c.h5\n"
      "  gen-bdlstm model.h5 data.h5 --test-every 2 --initial 2 --method linear -o lin.h5\n"
      "  gen-bdlstm model.h5 data.h5 --test-every 2 --initial 3 --method nearest -o nn.h5\n"
      "  acap2obj pred.h5 -o pred-meshes/");
  return tool.run(argc, argv, [&] { df::apps::generate_bdlstm(opt, tool.common()); });
}
