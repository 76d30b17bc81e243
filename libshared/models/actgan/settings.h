// Every setting of train-actgan's networks, losses and training run, declared once
// (models/common/settings.h): the tool's options, the model file's /config, its reading and the
// resume check come from here. What the data fixes (pose size, classes, frame rate, clip length,
// its file) and the validation subjects (a dataset of their own) are the model file's.
#pragma once

#include "models/actgan/model.h"
#include "models/common/settings.h"

namespace df::models {

using ActganSettings = SettingsTable<ActganConfig, ActganTraining>;

/// The networks (the option group "Networks"; the pose size and class count come from the data).
const ActganSettings& actgan_network_settings();
/// The losses (the option group "Losses": the ablations of paper Tables 2, 5 and 6).
const ActganSettings& actgan_loss_settings();
/// The training run (the option group "Training").
const ActganSettings& actgan_training_settings();
/// Every setting, as /config holds them.
const ActganSettings& actgan_settings();

}  // namespace df::models
