// Every setting of train-msae's network and training run, declared once (models/common/settings.h):
// the tool's options, the model file's /config, its reading and the resume check come from here.
#pragma once

#include "models/common/settings.h"
#include "models/msae/model.h"

namespace df::models {

/// The network and its loss (the option group "Network").
Settings msae_network_settings(MsaeConfig& c);
/// The training run (the option group "Training"; the split lists and checkpoints are the tool's).
Settings msae_training_settings(MsaeTraining& t);
/// Both, as /config holds them.
Settings msae_settings(MsaeConfig& c, MsaeTraining& t);

}  // namespace df::models
