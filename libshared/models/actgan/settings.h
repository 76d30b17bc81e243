// Every setting of train-actgan's networks, losses and training run, declared once
// (models/common/settings.h): the tool's options, the model file's /config, its reading and the
// resume check come from here. What the data fixes (pose size, classes, frame rate, clip length,
// its file) and the validation subjects (a dataset of their own) are the model file's.
#pragma once

#include "models/actgan/model.h"
#include "models/common/settings.h"

namespace df::models {

/// The networks (the option group "Networks"; the pose size and class count come from the data).
Settings actgan_network_settings(ActganConfig& c);
/// The losses (the option group "Losses": the ablations of paper Tables 2, 5 and 6).
Settings actgan_loss_settings(ActganConfig& c);
/// The training run (the option group "Training").
Settings actgan_training_settings(ActganTraining& t);
/// Every setting, as /config holds them.
Settings actgan_settings(ActganConfig& c, ActganTraining& t);

}  // namespace df::models
