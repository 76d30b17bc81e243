// Every setting of train-bdlstm's network and training run, declared once
// (models/common/settings.h): the tool's options, the model file's /config, its reading and the
// resume check come from here.
#pragma once

#include "models/bdlstm/model.h"
#include "models/common/settings.h"

namespace df::models {

using BdlstmSettings = SettingsTable<BdlstmConfig, BdlstmTraining>;

/// The network and its loss (the option group "Network"; the ablations of paper Table 2).
const BdlstmSettings& bdlstm_network_settings();
/// The training run (the option group "Training"). The remedies' options (--kl-warmup,
/// --kl-free-bits, --l2-scope, --l2-weight, --decoder-init) are the ones --paper-form sets.
const BdlstmSettings& bdlstm_training_settings();
/// Every setting, as /config holds them.
const BdlstmSettings& bdlstm_settings();

}  // namespace df::models
