#include "models/actgan/settings.h"

namespace df::models {

const ActganSettings& actgan_network_settings() {
  using C = ActganConfig;
  static const ActganSettings rows = {
      {.name = "pose", .target = &C::pose},        // the data's joints × 3
      {.name = "classes", .target = &C::classes},  // the data's classes
      {.name = "noise",
       .target = &C::noise,
       .help = "Noise values per step (xi_t)",
       .range = positive()},
      {.name = "latent",
       .target = &C::latent,
       .help = "Latent frame size (h_t)",
       .range = positive()},
      {.name = "hidden",
       .target = &C::hidden,
       .help = "LSTM hidden size (generator, discriminator, classifier)",
       .range = positive()},
      {.name = "fc",
       .target = &C::fc,
       .help = "Hidden layer of the decoder, the heads and the critic",
       .range = positive()},
      {.name = "step_init",
       .target = choice(&C::step_init),
       .help = "The generator's output layer v_t = FC(o_t) at its Glorot draw or x 0.01 (small:\n"
               "the untrained generator stays where h_1 starts instead of drifting out of the\n"
               "decoder's N(0, I) range)",
       .optional = true},
      {.name = "start",
       .target = choice(&C::start),
       .help = "Where each sequence's latent starts: uniform (h_1 ~ U(-1, 1) per dimension, the\n"
               "authors' code) or normal (h_1 ~ N(0, I), the distribution the decoder was\n"
               "pre-trained on); gen-actgan draws as the model was trained",
       .optional = true},
      {.name = "discriminator",
       .target = choice(&C::discriminator),
       .help =
           "The GAN's discriminator: bilstm (the paper's bidirectional LSTM, binary\n"
           "cross-entropy) or critic (a Wasserstein critic MLP on the whole clip [x_1..x_T, y]\n"
           "with the gradient penalty --gp-lambda, as the pre-training's; fixes the clip length)",
       .optional = true},
      {.name = "disc_input",
       .target = choice(&C::disc_input),
       .help = "What the discriminator sees per frame: frames [x_t, y], or motion [x_t,\n"
               "x_t - x_{t-1}, y] (frames and their differences, as the authors' code)",
       .optional = true},
      {.name = "disc_pool",
       .target = choice(&C::disc_pool),
       .help = "What the discriminator's head reads: last (the BiLSTM's last forward and backward\n"
               "states) or all (every step's outputs, as the authors' code; fixes the clip length)",
       .optional = true},
      {.name = "generator",
       .target = choice(&C::generator),
       .help = "latent: the paper's generator; pose: the baseline RNN whose LSTM output is the\n"
               "pose itself (no latent transitions, no shared decoder; --pretrain-iterations 0)",
       .optional = true},
  };
  return rows;
}

const ActganSettings& actgan_loss_settings() {
  using C = ActganConfig;
  static const ActganSettings rows = {
      {
          .name = "smoothness",
          .target = choice(&C::smoothness),
          .help = "Omega's terms: both, latent, action or none",
      },
      {.name = "sigma1", .target = &C::sigma1, .help = "Omega's weight on |h_t - h_{t-1}|^2"},
      {.name = "sigma2", .target = &C::sigma2, .help = "Omega's weight on |x_t - x_{t-1}|^2"},
      {.name = "gamma",
       .target = &C::gamma,
       .help = "Weight of the classifier's cross-entropy (cycle loss)"},
      {.name = "residual",
       .target = &C::residual,
       .help = "The LSTM gives h_{t+1} itself, not the residual v_t",
       .option = "--direct-latent"},
      {.name = "classifier",
       .target = &C::classifier,
       .help = "No classifier and no cycle loss",
       .option = "--no-classifier"},
      {.name = "gp_lambda",
       .target = &C::gp_lambda,
       .help = "WGAN-GP gradient penalty (pre-training; the GAN with --discriminator critic)"},
  };
  return rows;
}

const ActganSettings& actgan_training_settings() {
  using T = ActganTraining;
  static const ActganSettings rows = {
      {.name = "pretrain_iterations",
       .target = &T::pretrain_iterations,
       .help = "WGAN-GP iterations of the decoder",
       .range = at_least(0)},
      {.name = "iterations",
       .target = &T::iterations,
       .help = "GAN iterations after the pre-training",
       .range = at_least(0),
       .resume = false},
      {.name = "batch",
       .target = &T::batch,
       .help = "Sequences per GAN step",
       .range = at_least(2)},
      {.name = "pretrain_batch",
       .target = &T::pretrain_batch,
       .help = "Poses per pre-training step",
       .range = at_least(2)},
      {.name = "critic_steps",
       .target = &T::critic_steps,
       .help = "Critic updates per decoder update",
       .range = at_least(1)},
      {.name = "d_steps",
       .target = &T::d_steps,
       .help = "Discriminator updates per iteration (k)",
       .range = at_least(1)},
      {.name = "g_steps",
       .target = &T::g_steps,
       .help = "Generator + classifier updates per iteration",
       .range = at_least(1)},
      {.name = "lr",
       .target = &T::lr,
       .help = "Adam learning rate of the GAN",
       .range = positive()},
      {.name = "lr_pretrain",
       .target = &T::lr_pretrain,
       .help = "Adam learning rate of the pre-training",
       .range = positive()},
      // The file holds the rate in use (0 resolved to --lr: model.cpp), so 0 and --lr read alike.
      {.name = "disc_lr",
       .target = &T::disc_lr,
       .help = "Adam learning rate of the GAN's discriminator (0: --lr, as the paper); lower than\n"
               "--lr for a discriminator slower than the generator (two time-scale updates)",
       .range = at_least(0),
       .optional = true},
      {.name = "classifier_only",
       .target = &T::classifier_only,
       .help = "Train only the classifier, on the real clips (the paper's Baseline_T/G; with\n"
               "--pretrain-iterations 0): classify-actions then compares it with the classifier\n"
               "trained inside the GAN",
       .optional = true},
      {.name = "train_decoder",
       .target = &T::train_decoder,
       .help = "Keep the pre-trained frame decoder fixed in the GAN phase, as the authors' code\n"
               "does (only the LSTM learns paths through its latent space); on validation data\n"
               "the discriminator then wins outright, so by default the decoder learns on",
       .option = "--freeze-decoder",
       .optional = true},
      {.name = "disc_noise",
       .target = &T::disc_noise,
       .help = "Instance noise: sigma of Gaussian noise added to every frame the discriminator\n"
               "sees, real and generated (normalized units; 0: none)",
       .range = at_least(0),
       .optional = true},
      {.name = "seed", .target = &T::seed},  // the tool's --seed
  };
  return rows;
}

const ActganSettings& actgan_settings() {
  static const ActganSettings rows =
      joined(joined(actgan_network_settings(), actgan_loss_settings()), actgan_training_settings());
  return rows;
}

}  // namespace df::models
