// The actgan-model file kind (schemas/actgan-model.json): the networks' configuration, the weights
// of the generator, discriminator, classifier and critic, the state of each one's Adam and the
// RNG (enough to resume training bit-exactly), the training data's classes, skeleton and
// normalization (to write generated poses in its coordinates), and the training log. Written by
// train-actgan (final model and checkpoints), read by gen-actgan and classify-actions.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "io/skeleton_file.h"
#include "models/actgan/network.h"
#include "models/common/training.h"
#include "nn/adam.h"

namespace df::models {

/// How the model is trained (recorded in /config; checked on --resume; declared in
/// models/actgan/settings.cpp).
struct ActganTraining {
  /// WGAN-GP iterations of the frame decoder first, then bi-directional GAN iterations (Algorithm
  /// 1): the counts the defaults were measured at on three validation sets (issue 71); the held-out
  /// curves stop improving at about 600-800 GAN iterations (docs/actgan.md)
  std::int64_t pretrain_iterations = 1000;
  std::int64_t iterations = 800;
  int batch = 32;                        ///< sequences per step
  int pretrain_batch = 64;               ///< frames per pre-training step
  int critic_steps = 5;                  ///< critic steps per decoder step (pre-training)
  int d_steps = 1;                       ///< discriminator steps per iteration (k)
  int g_steps = 2;                       ///< generator + classifier steps per iteration
  double lr = 1e-4, lr_pretrain = 1e-3;  ///< Adam, betas 0.5 / 0.9
  /// The discriminator's Adam learning rate in the GAN phase (0: lr, as the paper); lower for a
  /// discriminator slower than the generator (two time-scale updates, Heusel et al. 2017)
  double disc_lr = 0;
  double discriminator_lr() const { return disc_lr > 0 ? disc_lr : lr; }
  /// Train only the classifier, on the real clips (the paper's Baseline_T/G: a classifier
  /// trained alone, to compare with the one trained inside the bi-directional GAN)
  bool classifier_only = false;
  /// Update the pre-trained frame decoder in the GAN phase too (false: --freeze-decoder, as the
  /// authors' code, where only the LSTM, its output layer and the classifier learn there; chosen
  /// on validation MMD: freezing it lets the discriminator win outright)
  bool train_decoder = true;
  /// Instance noise: sigma of the Gaussian noise added to every frame the discriminator sees, real
  /// and generated, in its steps and the generator's (0: none). Blurs the two distributions'
  /// supports so that the discriminator cannot tell them apart at a glance.
  double disc_noise = 0;
  std::uint64_t seed = 1;
  /// Training subjects held out for validation (their clips are not trained on; the log gets the
  /// MMD of generated sequences against them at every loss line)
  std::vector<std::int32_t> validation_subjects;
};

/// The optimizers, one per network and phase.
struct ActganOptimizers {
  std::unique_ptr<nn::Adam<float>> decoder, critic;  ///< pre-training
  std::unique_ptr<nn::Adam<float>> gen, disc, cls;   ///< the GAN
};

/// The model and its training state (models/common/training.h: iteration, log, the five Adams,
/// RNG of batches and noise).
struct ActganModel : TrainingState<ActganOptimizers> {
  ActganConfig config;
  ActganTraining training;
  std::vector<std::string> class_names;
  std::vector<std::int32_t> parents;
  std::vector<std::string> joint_names;
  io::SkeletonNormalization normalization;
  double frame_rate = 30;
  int length = 0;    ///< frames of the training sequences (the default generation length)
  std::string data;  ///< the training file's name
  std::unique_ptr<ActganGenerator<float>> gen;
  std::unique_ptr<SequenceNet<float>> disc, cls;  ///< disc: with config.discriminator "bilstm"
  std::unique_ptr<Critic<float>>
      clip_critic;                        ///< the GAN's critic with config.discriminator "critic"
  std::unique_ptr<Critic<float>> critic;  ///< the pre-training's critic of single poses
  std::string history;

  /// The loss terms of a log row and the validation measures that follow them when there are
  /// validation subjects.
  static std::vector<std::string> loss_columns();
  static std::vector<std::string> validation_columns();
  /// The training log's columns: iteration, loss_columns(), then with validation subjects
  /// validation_columns().
  std::vector<std::string> log_columns() const;
  /// The GAN's discriminator's parameters (disc or clip_critic).
  nn::ParameterStore<float>& discriminator_store() const;
  /// Untrained networks (weights from Rng(seed, 0)) and fresh optimizers.
  void initialize();
};

void save_actgan_model(const std::string& path, const ActganModel& m,
                       const std::vector<std::string>& inputs, bool force);
ActganModel load_actgan_model(const std::string& path);

}  // namespace df::models
