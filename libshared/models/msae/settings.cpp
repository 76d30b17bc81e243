#include "models/msae/settings.h"

namespace df::models {
namespace {

// The blocks: their levels, components, attention, codes, decoder and start.
const MsaeSettings& msae_block_settings() {
  using C = MsaeConfig;
  static const MsaeSettings rows = {
      {.name = "kz",
       .target = &C::kz,
       .help = "Components of each autoencoder, per level (comma-separated)",
       .range = at_least(1)},
      {.name = "d",
       .target = &C::d,
       .help = "Omega's normalized geodesic radius per level (comma-separated)",
       .range = within(0, 1, true)},
      {.name = "attention",
       .target = &C::attention,
       .help =
           "One autoencoder per level on the whole residual, with as many components as the\n"
           "attention tree has there (paper Table 4; --levels 1 --no-attention is the one-level\n"
           "sparse autoencoder of Tan et al.)",
       .option = "--no-attention"},
      {
          .name = "latent",
          .target = choice(&C::latent),
          .help = "Codes z = h C^T, bounded by V(Z) at --theta (linear), or z = tanh(h C^T) (tanh: "
                  "the\n"
                  "paper's 'tanh everywhere' taken literally; its codes saturate at +-1 on real "
                  "meshes\n"
                  "and V(Z) never acts; see docs/msae.md)",
      },
      {.name = "decoder_fc",
       .target = choice(&C::decoder_fc),
       .help = "The decoder's fully connected layer: y = tanh(z C) (tanh, the paper's 'tanh\n"
               "everywhere') or y = z C (linear, as the convMesh code of Tan et al.)",
       .optional = true},
      {.name = "decoder_conv",
       .target = choice(&C::decoder_conv),
       .help =
           "The decoder's mesh convolution uses the encoder's weights transposed, or shared as\n"
           "they are (as the convMesh code)",
       .optional = true},
      {.name = "init",
       .target = choice(&C::init),
       .help = "Initial weights: glorot (uniform), normal (N(0, 0.02^2), as the convMesh code),\n"
               "small (C at glorot x 0.01: components no training shape asks for stay near zero\n"
               "instead of projecting unseen shapes onto random directions), local (glorot,\n"
               "then level 0's components from SPLOCS on the training shapes' features, within\n"
               "radius d, orthonormalised, and its convolutions the identity: AE0 starts as\n"
               "the projection onto the shapes' local linear components) or local-all (every\n"
               "level so, each block from SPLOCS on what it is fed, level by level)",
       .optional = true},
  };
  return rows;
}

// Ω's supports and centres, and the loss's weights.
const MsaeSettings& msae_support_settings() {
  using C = MsaeConfig;
  static const MsaeSettings rows = {
      {.name = "centres",
       .target = choice(&C::centres),
       .help =
           "Where the components' centres start: random (where the initial weights peak; the\n"
           "reconstruction gradient then draws most to the same vertices) or spread (farthest-\n"
           "point sampling: level 0 over the mesh, a child within its parent's radius)",
       .optional = true},
      {.name = "centre_separation",
       .target = &C::centre_separation,
       .help =
           "0: c_k = argmax_i |C_k,i| every iteration (the paper). s > 0: a block's components,\n"
           "strongest first, each take their strongest vertex at least s x d (geodesic) from\n"
           "the centres already given out in the block, so that no two share a centre and\n"
           "Omega pushes them apart (the plain argmax where no vertex is that far)",
       .optional = true},
      {.name = "support",
       .target = choice(&C::support),
       .help = "Omega as a penalty only (soft, the paper: its gradient leaves weights of the\n"
               "order of the step size all over the mesh), as a proximal step (proximal: Omega\n"
               "out of the gradient; after every Adam step each group of C outside a component's\n"
               "radius shrinks by Omega's weight times its step size, and is exactly zero where\n"
               "the reconstruction does not hold it up), or as a hard support (hard: after every\n"
               "step the weights of C outside each radius d are set to zero, Omega's limit:\n"
               "strictly local components)",
       .optional = true},
      {.name = "proximal_cap",
       .target = &C::proximal_cap,
       .help = "With --support proximal: a group of C shrinks by at most this many times its\n"
               "rate per step (0: no cap). Adam's step sizes, which the threshold uses, grow\n"
               "without bound where the reconstruction's gradient is small, so uncapped one step\n"
               "zeroes every group outside the masks of a block that already fits (a started\n"
               "one: --init local); capped, it shrinks as fast as Adam moves a weight",
       .range = at_least(0),
       .optional = true},
      {.name = "centre_features",
       .target = &C::centre_features,
       .help = "Subtract the training shapes' mean features before the first autoencoder and add\n"
               "them back after it: the autoencoders model deviations from the mean shape, and no\n"
               "component is spent on the mean deformation (see docs/msae.md)",
       .optional = true},
      {.name = "attention_sharpness",
       .target = &C::attention_sharpness,
       .help =
           "Attention masks from am^p instead of am (eq. 5-6): 1 (the paper), 2 or 4. Where\n"
           "level-0 components overlap, the masks spread each vertex's residual thin over them\n"
           "and the second level starves; p > 1 gives more of it to the component that owns the\n"
           "vertex most (the masks still sum to 1; see docs/msae.md)",
       .optional = true},
      {.name = "lambda_recon",
       .target = &C::lambda_recon,
       .help = "Weight of the reconstruction MSE"},
      {.name = "lambda_sparse", .target = &C::lambda_sparse, .help = "Weight of Omega(C)"},
      {.name = "lambda_whole",
       .target = &C::lambda_whole,
       .help =
           "Weight of the whole reconstruction's MSE |X - sum of every block's X^|^2, added to\n"
           "the blocks' own losses: each second-level autoencoder reconstructs only its masked\n"
           "share of the residual, and this term makes them fit it together (as the codes\n"
           "recon-msae --fit-codes finds do; docs/msae.md). 0 = none (the paper)",
       .optional = true},
      {.name = "theta",
       .target = &C::theta,
       .help = "V(Z)'s bound on the codes (tanh codes stay below 1: inactive)"},
  };
  return rows;
}

// The schedule: iterations, batches, rates and their warm-up and decay, separate training.
const MsaeSettings& msae_schedule_settings() {
  using T = MsaeTraining;
  static const MsaeSettings rows = {
      // Only separate training divides the iterations among the levels: elsewhere a resumed run
      // may go on longer (train.cpp checks the separate case).
      {.name = "iterations",
       .target = &T::iterations,
       .help = "Training iterations (batches); the paper's 10,000 epochs are a GPU budget",
       .range = at_least(0),
       .resume = false},
      {.name = "batch",
       .target = &T::batch,
       .help = "Shapes per iteration, drawn with replacement",
       .range = positive()},
      {.name = "lr",
       .target = &T::lr,
       .help = "Adam learning rate (betas 0.9/0.999)",
       .range = positive()},
      {.name = "lr_decay",
       .target = &T::lr_decay,
       .help = "Exponential decay: lr x DECAY^(iteration / --lr-decay-steps)",
       .range = within(0, 1, true)},
      {.name = "lr_decay_steps",
       .target = &T::lr_decay_steps,
       .help = "Iterations per factor --lr-decay",
       .range = positive()},
      {.name = "lr_warmup",
       .target = &T::lr_warmup,
       .help = "The rate rises linearly from lr/N to lr over the first N iterations (0: none, the\n"
               "paper). Tried against Adam's first steps replacing a started level 0 (--init\n"
               "local); on chickenCrossing it only delays that (docs/msae.md)",
       .range = at_least(0),
       .optional = true},
      {.name = "started_rate",
       .target = &T::started_rate,
       .help =
           "With --init local or local-all: the started blocks (convolutions, C, decoder bias)\n"
           "step at this fraction of the rate (1: like every weight). Adam's first steps move\n"
           "every weight by about the rate, which replaces the started components; 0.01 keeps\n"
           "them (docs/msae.md)",
       .range = within(0, 1, true, false),
       .optional = true},
      {.name = "start_scale",
       .target = &T::start_scale,
       .help =
           "With --init local or local-all and --decoder-fc linear: the started blocks'\n"
           "convolutions start as S x I and C as the components / S, so that the encoder's tanh\n"
           "acts in its nearly linear range and the block starts as the projection onto the\n"
           "components bent by its output's tanh alone (1: the encoder's tanh too; docs/msae.md)",
       .range = within(0, 1, true, false),
       .optional = true},
      {.name = "separate",
       .target = &T::separate,
       .help =
           "Train level by level (iterations divided equally; earlier levels frozen) instead of\n"
           "jointly (paper Table 4)"},
      {.name = "separate_rate",
       .target = choice(&T::separate_rate),
       .help =
           "With --separate: each level's new Adam starts at --lr (restart) or at the rate the\n"
           "schedule has reached when the level starts (continue: the rate joint training has\n"
           "there, so that joint and separate differ in strategy only)",
       .optional = true},
  };
  return rows;
}

// What each batch is drawn from: synthetic shapes, the split, the seed.
const MsaeSettings& msae_data_settings() {
  using T = MsaeTraining;
  static const MsaeSettings rows = {
      {.name = "synthetic",
       .target = &T::synthetic,
       .help =
           "Add N shapes the decoders make to every batch, each code the same code of one of\n"
           "the batch's training shapes drawn at random (independently per code): the encoder\n"
           "learns to invert the decoders beyond the training shapes' code combinations, where\n"
           "unseen shapes lie (docs/msae.md). 0 = none (the paper)",
       .range = at_least(0),
       .optional = true},
      {.name = "synthetic_weight",
       .target = &T::synthetic_weight,
       .help = "--synthetic shapes' share of the reconstruction loss against the real ones",
       .range = positive(),
       .optional = true},
      // The split is compared as the frames it chose (train.cpp), not as its settings.
      {.name = "split",
       .target = choice(&T::split),
       .help = "sequence: every --every-th shape of each sequence trains, the rest is held out;\n"
               "collection: a random --train-fraction trains (placed by --seed)",
       .choices = {"sequence", "collection"},  // "lists": --train and --test
       .resume = false},
      {.name = "every",
       .target = &T::every,
       .help = "sequence split: train on every N-th shape",
       .range = at_least(2),
       .resume = false},
      {.name = "train_fraction",
       .target = &T::train_fraction,
       .help = "collection split: fraction trained on",
       .range = within(0, 1, true, true),
       .resume = false},
      {.name = "validation_fraction",
       .target = &T::validation_fraction,
       .help =
           "This fraction of the held-out shapes (drawn by --seed) validates instead of testing;\n"
           "its error is logged at every loss line (features, and E_rms x 1000 of positions as\n"
           "eval-metrics measures it). Choose iteration counts and options on it, never on\n"
           "the test shapes",
       .range = within(0, 1, false, true),
       .resume = false},
      {.name = "seed", .target = &T::seed},  // the tool's --seed
  };
  return rows;
}

}  // namespace

const MsaeSettings& msae_network_settings() {
  static const MsaeSettings rows = joined(msae_block_settings(), msae_support_settings());
  return rows;
}

const MsaeSettings& msae_training_settings() {
  static const MsaeSettings rows = joined(msae_schedule_settings(), msae_data_settings());
  return rows;
}

const MsaeSettings& msae_settings() {
  static const MsaeSettings rows = joined(msae_network_settings(), msae_training_settings());
  return rows;
}

}  // namespace df::models
