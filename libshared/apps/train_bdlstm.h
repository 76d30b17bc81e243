// train-bdlstm's job: the options checked, the model file and its checkpoint claimed, the acap
// file opened, and models/bdlstm's trainer run over run_trainer.
#pragma once

#include "core/common_options.h"
#include "models/bdlstm/train.h"

namespace df::apps {

/// train-bdlstm: trains the share-weight BD-LSTM on the normalized features of `opt.input` and
/// writes `opt.output` (models::BdlstmTrainer's run; --resume continues its checkpoint).
void train_bdlstm(const models::BdlstmTrainOptions& opt, const CommonOptions& common);

}  // namespace df::apps
