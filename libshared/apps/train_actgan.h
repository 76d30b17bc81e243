// train-actgan's job: the trainer of models/actgan with its validation measured by eval (the
// measures live above the models, so the tool's layer joins them).
#pragma once

#include <vector>

#include "core/common_options.h"
#include "models/actgan/train.h"

namespace df::apps {

/// train-actgan's validation columns: MMD_avg, MMD_seq and their motion forms (as skeleton_metrics,
/// in the model's normalized coordinates) of `per_class` sequences generated for each class against
/// the held-out clips of that class (classes with fewer than 2 clips are left out), averaged over
/// classes. The noise is drawn from Rng(seed, 2) afresh at every call: the same draw at every
/// evaluation.
std::vector<double> actgan_validation_mmd(const models::ActganModel& model,
                                          const models::ActionClips& clips, int per_class = 100);

/// train-actgan: the options checked, the model file and its checkpoint claimed, the skeleton
/// file read, and models::ActganTrainer run with actgan_validation_mmd as its validator.
void train_actgan(models::ActganTrainOptions opt, const CommonOptions& common);

}  // namespace df::apps
