// train-msae's job: the trainer of models/msae with its validation shapes' E_rms measured by eval
// (the measures live above the models, so the tools' layer joins them, as for train-actgan).
#pragma once

#include "core/common_options.h"
#include "models/msae/train.h"

namespace df::apps {

/// train-msae: the options checked, the model file and its checkpoint claimed, the acap file
/// opened, and models::MsaeTrainer run with eval::ShapeErms (E_rms × 1000 of the validation
/// shapes' positions, each part aligned, in the unit ball) as its validation_erms column.
void train_msae(models::MsaeTrainOptions opt, const CommonOptions& common);

}  // namespace df::apps
