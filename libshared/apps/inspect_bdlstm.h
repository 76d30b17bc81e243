// inspect-bdlstm: what a trained BD-LSTM has learned, for diagnosing training (issue: latent
// collapse). Reports the training log's first and last rows, the KL of q(z|x) against the prior
// per latent dimension over frames of the training (or held-out) part, and prediction windows
// of that part run with z = the encoder's mean, z drawn from the prior, and z = 0, beside zero
// motion: if the prior or zero predict as well as the mean, the LSTM ignores the latent.
#pragma once

#include <string>

#include "core/common_options.h"
#include "models/common/frame_part.h"

namespace df::apps {
using models::FramePart;

struct BdlstmInspectOptions {
  std::string model, data;
  std::string tsv;  ///< optional: KL per dimension and the error per step, for plots
  FramePart part = FramePart::train;  ///< train | validation | test: the frames probed
  int initial = 3;                    ///< given frames of each probe window
  int length = 10;                    ///< predicted steps of each probe window
  int cases = 64;                     ///< probe windows, evenly spaced over the part
  int max_frames = 1024;              ///< frames encoded for the KL per dimension (evenly spaced)
};

void inspect_bdlstm(const BdlstmInspectOptions& opt, const CommonOptions& common);

}  // namespace df::apps
