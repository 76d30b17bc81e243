// Every setting of train-msae's network and training run, declared once (models/common/settings.h):
// the tool's options, the model file's /config, its reading and the resume check come from here.
#pragma once

#include "models/common/settings.h"
#include "models/msae/model.h"

namespace df::models {

using MsaeSettings = SettingsTable<MsaeConfig, MsaeTraining>;

/// The network and its loss (the option group "Network").
const MsaeSettings& msae_network_settings();
/// The training run (the option group "Training"; the split lists and checkpoints are the tool's).
const MsaeSettings& msae_training_settings();
/// Both, as /config holds them.
const MsaeSettings& msae_settings();

}  // namespace df::models
