// Every setting of train-bdlstm's network and training run, declared once
// (models/common/settings.h): the tool's options, the model file's /config, its reading and the
// resume check come from here.
#pragma once

#include "models/bdlstm/model.h"
#include "models/common/settings.h"

namespace df::models {

/// The network and its loss (the option group "Network"; the ablations of paper Table 2).
Settings bdlstm_network_settings(BdlstmConfig& c);
/// The training run (the option group "Training"). The remedies' options (--kl-warmup,
/// --kl-free-bits, --l2-scope, --l2-weight, --decoder-init) are the ones --paper-form sets.
Settings bdlstm_training_settings(BdlstmTraining& t, BdlstmConfig& c);
/// Every setting, as /config holds them.
Settings bdlstm_settings(BdlstmConfig& c, BdlstmTraining& t);

}  // namespace df::models
