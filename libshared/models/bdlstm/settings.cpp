#include "models/bdlstm/settings.h"

namespace df::models {

const BdlstmSettings& bdlstm_network_settings() {
  using C = BdlstmConfig;
  static const BdlstmSettings rows = {
      {
          .name = "directions",
          .target = choice(&C::directions),
          .help = "shared: one network runs both chains (the paper's BD-LSTM); standard: each\n"
                  "direction has its own weights; unidirectional: forward chain only",
      },
      {.name = "kl",
       .target = &C::kl,
       .help = "Deterministic encoder (z = mean), no KL term",
       .option = "--no-kl"},
      {.name = "l2", .target = &C::l2, .help = "No L2 penalty on the weights", .option = "--no-l2"},
      {.name = "latent", .target = &C::latent, .help = "Latent size"},
      {.name = "hidden", .target = &C::hidden, .help = "LSTM hidden size"},
      {.name = "lstm_layers", .target = &C::lstm_layers, .help = "LSTM layers"},
      {.name = "conv_layers",
       .target = &C::conv_layers,
       .help = "Mesh convolutions in the encoder (and decoder)"},
      {.name = "alpha_bidir", .target = &C::alpha_bidir, .help = "Weight of L_bidir"},
      {.name = "alpha_reg", .target = &C::alpha_reg, .help = "Weight of L_KL + L_2"},
      {.name = "l2_scope",
       .target = choice(&C::l2_scope),
       .help =
           "L_2 over all trainable values (the paper's sum w^2), the weights only (no biases,\n"
           "so the forget-gate bias keeps its 1), or tf: all values, the LSTM forget-gate\n"
           "biases measured from 1 (TensorFlow's forget_bias is a constant outside the weights)",
       .optional = true},
      {.name = "l2_weight",
       .target = &C::l2_weight,
       .help = "Factor of L_2 inside alpha-reg (L_KL + w L_2)",
       .optional = true},
      {.name = "decoder_init",
       .target = choice(&C::decoder_init),
       .help = "Last decoder convolution at zero (dX = 0 at first) or small (Glorot x 0.01: the\n"
               "encoder gets a reconstruction gradient from the start)",
       .optional = true},
      {.name = "init_state",
       .target = &C::init_state,
       .help = "Initial LSTM state of the forward chain (backward: minus)"},
      {.name = "carry",
       .target = &C::carry,
       .help = "Motion carried from step to step: X_t+1 = X_t + CARRY (X_t - X_t-1) + dX, so the\n"
               "prediction starts at the given frames' pace (still frames stay still); 0 = the\n"
               "paper (X_t+1 = X_t + dX)",
       .optional = true},
      {.name = "carry_fade",
       .target = &C::carry_fade,
       .help = "The carry fades along a chain: CARRY x FADE^(t-1) at its step t, so a prediction\n"
               "starts at the given frames' pace and, far from them, moves by dX alone (a long\n"
               "generation does not compound the carried motion); 1 = never fades",
       .range = within(0, 1),
       .optional = true},
      {.name = "motion_input",
       .target = &C::motion_input,
       .help = "The encoder reads each step's motion X_t - X_t-1 beside the frame X_t (scaled by\n"
               "the training frames' own frame-to-frame change), so that z can tell the given\n"
               "frames' pace and direction; off = the paper (X_t alone)",
       .optional = true},
      // Not an option: train-bdlstm measures it on the training frames (motion_input); a resumed
      // run's data and split are checked themselves, so their settings are named, not this.
      {.name = "motion_scale", .target = &C::motion_scale, .resume = false, .optional = true},
  };
  return rows;
}

const BdlstmSettings& bdlstm_training_settings() {
  using C = BdlstmConfig;
  using T = BdlstmTraining;
  static const BdlstmSettings rows = {
      {.name = "iterations",
       .target = &T::iterations,
       .help = "Training iterations (paper: 7000)",
       .range = at_least(0),
       .resume = false},
      {.name = "window",
       .target = &T::window,
       .help = "Frames per training window",
       .range = at_least(2)},
      {.name = "batch", .target = &T::batch, .help = "Windows per iteration", .range = positive()},
      {.name = "stride",
       .target = &T::stride,
       .help = "Use every STRIDE-th frame (2 for slow motion)",
       .range = positive()},
      {.name = "lr",
       .target = &T::lr,
       .help = "Adam learning rate (betas 0.9/0.999)",
       .range = positive()},
      {.name = "test_fraction",
       .target = &T::test_fraction,
       .help = "Fraction of every sequence held out as a contiguous test part"},
      {.name = "validation_fraction",
       .target = &T::validation_fraction,
       .help =
           "A validation part of each sequence, this fraction of its frames, carved out of the\n"
           "training frames at a place drawn from --seed; no window crosses it. Choose options\n"
           "and iteration counts on it (gen-bdlstm --part validation), never on the test part",
       .optional = true},
      {.name = "stopping_fraction",
       .target = &T::stopping_fraction,
       .help =
           "Early stopping: a stopping part of each sequence, this fraction of its frames, carved\n"
           "out of the training frames (after the validation part) where it leaves the longest\n"
           "stretch of training frames whole (beside the held-out or validation part, or at an\n"
           "end); no window crosses it. The model file keeps the weights of the loss line (or\n"
           "--stopping-every check) where the prediction error on its windows, relative to zero\n"
           "motion's, was lowest (the log's stopping column), so the tool picks the iteration\n"
           "count on frames it did not train on (0 = the paper: the last iteration's weights).\n"
           "Sequences too short for the default's part train without it, with a warning",
       .optional = true},
      {.name = "stopping_every",
       .target = &T::stopping_every,
       .help = "With --stopping-fraction: check the stopping error every N iterations as well\n"
               "as at the loss lines (the model may stop learning what carries within the first\n"
               "loss line's 100 iterations; 0 = at the loss lines only)",
       .range = at_least(0),
       .optional = true},
      {.name = "stopping_untrained",
       .target = &T::stopping_untrained,
       .help = "With --stopping-fraction: check the untrained network too, before the first\n"
               "iteration, and keep it if no later check beats it (with --decoder-init zero it\n"
               "predicts the carried motion alone: zero motion at --carry 0, damped\n"
               "extrapolation at --carry D --carry-fade 1, gen-bdlstm --method damped)",
       .optional = true},
      {
          .name = "test_part",
          .target = choice(&T::test_part),
          .help = "Where the held-out part lies: end, start, middle, or random (placed by --seed)",
      },
      {.name = "teacher_frames",
       .target = &T::teacher_frames,
       .help = "Feed each chain u ground-truth frames (u uniform in 1..N per iteration) before\n"
               "it runs free, so the network learns to use gen-bdlstm's --initial frames\n"
               "(1 = the paper: only the seed frame)",
       .range = at_least(1),
       .optional = true},
      {.name = "speeds",
       .target = &T::speeds,
       .help =
           "Play each training window at a speed drawn from this list (comma-separated; 0:\n"
           "the first frame held still, 0.5: half the data's pace, frames interpolated), so\n"
           "that the pace of a prediction must be read off the given frames (1 = the data's\n"
           "own pace, the paper). Sequences too short for a window at the default's fastest\n"
           "speed, but long enough at the data's pace, train at the default's speeds that fit,\n"
           "with a warning",
       .range = within(0, 8),
       .optional = true},
      {.name = "kl_warmup",
       .target = &T::kl_warmup,
       .help = "Raise the KL weight linearly from 0 to 1 over N iterations (0 = the paper: 1\n"
               "throughout); counters the latent collapsing to the prior",
       .range = at_least(0),
       .optional = true},
      {.name = "kl_free_bits",
       .target = &C::free_bits,
       .help =
           "Free bits: per step, a latent dimension's KL (mean over the batch) below this many\n"
           "nats is not penalised (0 = the paper); the log's kl column is the penalised value",
       .optional = true},
      {.name = "seed", .target = &T::seed},  // the tool's --seed
  };
  return rows;
}

const BdlstmSettings& bdlstm_settings() {
  static const BdlstmSettings rows = joined(bdlstm_network_settings(), bdlstm_training_settings());
  return rows;
}

}  // namespace df::models
