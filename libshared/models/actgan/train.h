// train-actgan: the conditional WGAN-GP pre-training of the shared frame decoder, then the
// bi-directional GAN of paper 3's Algorithm 1 on the training clips of a skeleton file (skel2h5:
// normalized, equal length): per iteration d_steps discriminator updates, then g_steps joint
// generator + classifier updates (adversarial loss + smoothness Omega + gamma x the classifier's
// cross-entropy on real and generated sequences).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/common_options.h"
#include "models/actgan/model.h"
#include "models/common/training.h"

namespace df::models {

/// Equal-length clips, each [length, P] row-major in `frames`, and their labels.
struct ActionClips {
  int length = 0, pose = 0;
  std::vector<float> frames;  ///< [clips, length, pose]
  std::vector<int> labels;
  std::size_t size() const { return labels.size(); }
  /// Frame t of clip c: pose values.
  const float* frame(std::size_t c, std::size_t t) const {
    return frames.data() +
           (c * static_cast<std::size_t>(length) + t) * static_cast<std::size_t>(pose);
  }
};

/// The training sequences of a skeleton file (test == 0; all when it marks none): those of the
/// validation subjects in `validation`, the others in `train`. UsageError for a validation
/// subject that performs no training sequence; InvalidInput for unequal lengths or fewer than 2
/// training clips.
struct ActionData {
  ActionClips train, validation;
};
ActionData training_clips(const io::SkeletonFile& s, const std::string& path,
                          const std::vector<std::int32_t>& validation_subjects = {});

/// Measures a model in training on held-out clips (the log's validation columns, in the order of
/// ActganModel::log_columns()); supplied by the caller (eval::actgan_validation_mmd), as the
/// measures live above the models.
using ActganValidator = std::function<LossTerms(const ActganModel&, const ActionClips&)>;

struct ActganTrainOptions {
  std::string input, output;
  TrainingRun run;  ///< checkpoints, --resume, loss lines
  ActganConfig net;
  ActganTraining training;
  ActganValidator validate;  ///< needed with training.validation_subjects
};

/// One pre-training iteration (critic_steps critic updates with the gradient penalty, then one
/// decoder update) and one GAN iteration (d_steps discriminator updates, then g_steps generator +
/// classifier updates), drawing from m.rng; each returns the loss terms of the log's columns.
LossTerms actgan_pretrain_iteration(ActganModel& m, const ActionClips& d, nn::Tape<float>& tape);
LossTerms actgan_gan_iteration(ActganModel& m, const ActionClips& d, nn::Tape<float>& tape);

/// What train-actgan uses unless --paper-form, chosen on validation parts (docs/actgan.md): a
/// Wasserstein critic of whole clips with the gradient penalty and 5 critic steps per iteration
/// (the paper's BiLSTM discriminator moved the sequences away from the data in every setting
/// tried), Omega's pose term only (its latent term, sigma1, slows one-arm gestures: their motion
/// MMD 5-45x the baseline's with it, 2.5-4.6x without) and each sequence's latent starting at
/// h_1 ~ N(0, I), the decoder's pre-training distribution (the best worst case over three
/// validation sets by 1.9%).
void apply_learning_defaults(ActganConfig& net, ActganTraining& training);
/// The paper's form: the BiLSTM discriminator on binary cross-entropy, one discriminator step,
/// Omega on the latents and the poses, h_1 ~ U(-1, 1).
void apply_paper_form(ActganConfig& net, ActganTraining& training);

/// The options' own rules: each setting's range (the settings table), then the rules between
/// settings (UsageError).
void check_actgan_options(const ActganTrainOptions& opt);

/// An ActGAN training run over run_trainer (models/common/training.h): the training (and
/// validation) clips of a skeleton file, the model they describe, and its hooks — start, resume,
/// the pre-training and GAN iterations, validation, saving. The job around it (options checked,
/// outputs claimed, the file read, eval's measure passed in, the run) is apps::train_actgan's.
class ActganTrainer {
 public:
  ActganTrainer(const ActganTrainOptions& opt, const io::SkeletonFile& s);
  ActganTrainer(const ActganTrainer&) = delete;
  ActganTrainer& operator=(const ActganTrainer&) = delete;
  ActganModel& model() { return m_; }
  /// run_trainer's hooks; they refer to this trainer, which must outlive the run.
  Trainer hooks();

 private:
  LossTerms step(std::int64_t done);

  const ActganTrainOptions& opt_;
  ActionData data_;
  ActganModel m_;
  nn::Tape<float> tape_;
};

}  // namespace df::models
