#include "models/bdlstm/settings.h"

namespace df::models {

Settings bdlstm_network_settings(BdlstmConfig& c) {
  return {
      {
          .name = "directions",
          .target = choice(c.directions),
          .help = "shared: one network runs both chains (the paper's BD-LSTM); standard: each\n"
                  "direction has its own weights; unidirectional: forward chain only",
      },
      {.name = "kl",
       .target = &c.kl,
       .help = "Deterministic encoder (z = mean), no KL term",
       .option = "--no-kl"},
      {.name = "l2", .target = &c.l2, .help = "No L2 penalty on the weights", .option = "--no-l2"},
      {.name = "latent", .target = &c.latent, .help = "Latent size"},
      {.name = "hidden", .target = &c.hidden, .help = "LSTM hidden size"},
      {.name = "lstm_layers", .target = &c.lstm_layers, .help = "LSTM layers"},
      {.name = "conv_layers",
       .target = &c.conv_layers,
       .help = "Mesh convolutions in the encoder (and decoder)"},
      {.name = "alpha_bidir", .target = &c.alpha_bidir, .help = "Weight of L_bidir"},
      {.name = "alpha_reg", .target = &c.alpha_reg, .help = "Weight of L_KL + L_2"},
      {.name = "l2_scope",
       .target = choice(c.l2_scope),
       .help =
           "L_2 over all trainable values (the paper's sum w^2), the weights only (no biases,\n"
           "so the forget-gate bias keeps its 1), or tf: all values, the LSTM forget-gate\n"
           "biases measured from 1 (TensorFlow's forget_bias is a constant outside the weights)",
       .optional = true},
      {.name = "l2_weight",
       .target = &c.l2_weight,
       .help = "Factor of L_2 inside alpha-reg (L_KL + w L_2)",
       .optional = true},
      {.name = "decoder_init",
       .target = choice(c.decoder_init),
       .help = "Last decoder convolution at zero (dX = 0 at first) or small (Glorot x 0.01: the\n"
               "encoder gets a reconstruction gradient from the start)",
       .optional = true},
      {.name = "init_state",
       .target = &c.init_state,
       .help = "Initial LSTM state of the forward chain (backward: minus)"},
      {.name = "carry",
       .target = &c.carry,
       .help = "Motion carried from step to step: X_t+1 = X_t + CARRY (X_t - X_t-1) + dX, so the\n"
               "prediction starts at the given frames' pace (still frames stay still); 0 = the\n"
               "paper (X_t+1 = X_t + dX)",
       .optional = true},
      {.name = "carry_fade",
       .target = &c.carry_fade,
       .help = "The carry fades along a chain: CARRY x FADE^(t-1) at its step t, so a prediction\n"
               "starts at the given frames' pace and, far from them, moves by dX alone (a long\n"
               "generation does not compound the carried motion); 1 = never fades",
       .range = within(0, 1),
       .optional = true},
      {.name = "motion_input",
       .target = &c.motion_input,
       .help = "The encoder reads each step's motion X_t - X_t-1 beside the frame X_t (scaled by\n"
               "the training frames' own frame-to-frame change), so that z can tell the given\n"
               "frames' pace and direction; off = the paper (X_t alone)",
       .optional = true},
      // Not an option: train-bdlstm measures it on the training frames (motion_input); a resumed
      // run's data and split are checked themselves, so their settings are named, not this.
      {.name = "motion_scale", .target = &c.motion_scale, .resume = false, .optional = true},
  };
}

Settings bdlstm_training_settings(BdlstmTraining& t, BdlstmConfig& c) {
  return {
      {.name = "iterations",
       .target = &t.iterations,
       .help = "Training iterations (paper: 7000)",
       .range = at_least(0),
       .resume = false},
      {.name = "window",
       .target = &t.window,
       .help = "Frames per training window",
       .range = at_least(2)},
      {.name = "batch", .target = &t.batch, .help = "Windows per iteration", .range = positive()},
      {.name = "stride",
       .target = &t.stride,
       .help = "Use every STRIDE-th frame (2 for slow motion)",
       .range = positive()},
      {.name = "lr",
       .target = &t.lr,
       .help = "Adam learning rate (betas 0.9/0.999)",
       .range = positive()},
      {.name = "test_fraction",
       .target = &t.test_fraction,
       .help = "Fraction of every sequence held out as a contiguous test part"},
      {.name = "validation_fraction",
       .target = &t.validation_fraction,
       .help =
           "A validation part of each sequence, this fraction of its frames, carved out of the\n"
           "training frames at a place drawn from --seed; no window crosses it. Choose options\n"
           "and iteration counts on it (gen-bdlstm --part validation), never on the test part",
       .optional = true},
      {
          .name = "test_part",
          .target = choice(t.test_part),
          .help = "Where the held-out part lies: end, start, middle, or random (placed by --seed)",
      },
      {.name = "teacher_frames",
       .target = &t.teacher_frames,
       .help = "Feed each chain u ground-truth frames (u uniform in 1..N per iteration) before\n"
               "it runs free, so the network learns to use gen-bdlstm's --initial frames\n"
               "(1 = the paper: only the seed frame)",
       .range = at_least(1),
       .optional = true},
      {.name = "speeds",
       .target = &t.speeds,
       .help = "Play each training window at a speed drawn from this list (comma-separated; 0:\n"
               "the first frame held still, 0.5: half the data's pace, frames interpolated), so\n"
               "that the pace of a prediction must be read off the given frames (1 = the data's\n"
               "own pace, the paper)",
       .range = within(0, 8),
       .optional = true},
      {.name = "kl_warmup",
       .target = &t.kl_warmup,
       .help = "Raise the KL weight linearly from 0 to 1 over N iterations (0 = the paper: 1\n"
               "throughout); counters the latent collapsing to the prior",
       .range = at_least(0),
       .optional = true},
      {.name = "kl_free_bits",
       .target = &c.free_bits,
       .help =
           "Free bits: per step, a latent dimension's KL (mean over the batch) below this many\n"
           "nats is not penalised (0 = the paper); the log's kl column is the penalised value",
       .optional = true},
      {.name = "seed", .target = &t.seed},  // the tool's --seed
  };
}

Settings bdlstm_settings(BdlstmConfig& c, BdlstmTraining& t) {
  Settings all = bdlstm_network_settings(c);
  for (auto& s : bdlstm_training_settings(t, c)) all.push_back(std::move(s));
  return all;
}

}  // namespace df::models
